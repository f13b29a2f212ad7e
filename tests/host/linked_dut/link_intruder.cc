// A hostile process on the runner's host, for the tests of the link's authentication. ProcessDut
// runs it in dut_emu's place (ProcessDutOptions::dut_emu_path) with dut_emu's arguments plus
// `--intrude MODE`. It connects to the runner's link port before dut_emu exists, so that its
// connection is the first the runner accepts, then forks: the child is the intruder, and this
// process becomes the real dut_emu (exec, same arguments without --intrude, same environment), so
// the runner still watches the pid it started. The intruder does not use the link token.
//   --intrude hello     says it is the DUT (a DUT hello without the token) and answers every step
//                       request with a forged command: rotors off, armed.
//   --intrude datagram  stays silent on the link until the runner drops it (the DUT has proved
//                       itself, so dut_emu's CAN port is bound), then sends a well-formed CAN frame
//                       to dut_emu's UDP CAN port from a socket of its own.
//   --intrude garbage   as datagram, but sends kGarbageDatagrams datagrams that are no frame at
//                       all (a byte each: together far below a socket's receive buffer).
// The intruder ends when the runner closes its connection, or after kIdleLimitMs without a word.
#include <unistd.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include "host/link/hil_link_codec.h"
#include "host/link/hil_link_socket.h"
#include "rig/udp_bus.h"
#include "tests/support/test_paths.h"

namespace {

using hilrig::host::LinkConnection;
using hilrig::host::LinkReceiveStatus;

constexpr int kIdleLimitMs = 10'000;
constexpr int kGarbageDatagrams = 100;

struct Arguments {
  std::vector<std::string> dut_emu;  // argv for the real dut_emu
  std::string mode;
  std::string link_host;
  std::uint16_t link_port = 0;
  std::uint16_t dut_can_port = 0;  // --can udp:BASE:1:2 puts dut_emu on BASE + 1
};

Arguments Parse(int argc, char** argv) {
  Arguments parsed;
  parsed.dut_emu.push_back(::hilrig::test_support::BinDir() + "/dut_emu");
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const std::string value = i + 1 < argc ? argv[i + 1] : "";
    if (arg == "--intrude") {
      parsed.mode = value;
      ++i;
      continue;
    }
    if (arg == "--link") {
      parsed.link_host = value.substr(0, value.rfind(':'));
      parsed.link_port = static_cast<std::uint16_t>(std::stoi(value.substr(value.rfind(':') + 1)));
    }
    if (arg == "--can")
      parsed.dut_can_port = static_cast<std::uint16_t>(std::stoi(value.substr(4)) + 1);
    parsed.dut_emu.push_back(arg);
  }
  return parsed;
}

// Before dut_emu starts, so that the runner has it before dut_emu's.
bool SayHelloAsTheDut(LinkConnection& link) {
  hilrig::proto::LinkMessage hello;
  hello.mutable_hello()->set_role(hilrig::proto::Hello::DUT);
  hello.mutable_hello()->set_name("dut_emu 1");
  hilrig::host::LinkSequencer().Stamp(hello, 0);
  return link.Send(hello).ok();
}

void AnswerWithForgedCommands(LinkConnection& link) {
  std::uint64_t commands = 0;
  while (true) {
    const hilrig::host::LinkReceived received = link.Receive(kIdleLimitMs);
    if (received.status != LinkReceiveStatus::kMessage || received.message.has_bye()) return;
    if (!received.message.has_step()) continue;
    hilrig::host::ActuatorMessage command;
    command.stamp = {commands++, received.message.step().now_ns()};
    command.answers_sequence = received.message.step().tick();
    command.armed = true;
    if (!link.Send(hilrig::host::ToLink(command)).ok()) return;
  }
}

// Waits until the runner drops the intruder's link connection (the DUT has proved itself and
// bound its CAN port); false when it never does.
bool WaitToBeDropped(LinkConnection& link) {
  while (true) {
    const hilrig::host::LinkReceived received = link.Receive(kIdleLimitMs);
    if (received.status == LinkReceiveStatus::kTimeout) return false;
    if (received.status != LinkReceiveStatus::kMessage) return true;
  }
}

void SendGarbageOnceDropped(LinkConnection& link, std::uint16_t dut_can_port) {
  if (!WaitToBeDropped(link)) return;
  namespace asio = boost::asio;
  asio::io_context io;
  asio::ip::udp::socket socket(io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const std::uint8_t garbage = 0xA5;
  for (int i = 0; i < kGarbageDatagrams; ++i) {
    socket.send_to(asio::buffer(&garbage, 1), {asio::ip::make_address("127.0.0.1"), dut_can_port});
  }
}

void SendForgedFrameOnceDropped(LinkConnection& link, std::uint16_t dut_can_port) {
  while (true) {
    const hilrig::host::LinkReceived received = link.Receive(kIdleLimitMs);
    if (received.status == LinkReceiveStatus::kTimeout) return;  // never dropped: nothing to do
    if (received.status != LinkReceiveStatus::kMessage) break;   // closed: the DUT is in
  }
  namespace asio = boost::asio;
  asio::io_context io;
  asio::ip::udp::socket socket(io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  std::array<std::uint8_t, hilrig::rig::kUdpCanMaxDatagramBytes> datagram{};
  const std::size_t size = hilrig::rig::EncodeUdpCanDatagram(
      hilrig::rig::CanFrame::Classic(0x123, std::array<std::uint8_t, 3>{1, 2, 3}), 0, datagram);
  socket.send_to(asio::buffer(datagram.data(), size),
                 {asio::ip::make_address("127.0.0.1"), dut_can_port});
}

}  // namespace

int main(int argc, char** argv) {
  const Arguments arguments = Parse(argc, argv);
  auto link = LinkConnection::Connect(arguments.link_host, arguments.link_port, kIdleLimitMs);
  if (!link) {
    std::cerr << "link_intruder: " << link.error().message << "\n";
    return 1;
  }
  if (arguments.mode == "hello" && !SayHelloAsTheDut(*link.value())) {
    std::cerr << "link_intruder: cannot send its hello\n";
    return 1;
  }
  const pid_t intruder = ::fork();
  if (intruder == 0) {
    if (arguments.mode == "hello") AnswerWithForgedCommands(*link.value());
    if (arguments.mode == "datagram")
      SendForgedFrameOnceDropped(*link.value(), arguments.dut_can_port);
    if (arguments.mode == "garbage") SendGarbageOnceDropped(*link.value(), arguments.dut_can_port);
    ::_exit(0);
  }
  link.value().reset();  // the connection is the intruder's alone
  std::vector<char*> args;
  for (const std::string& arg : arguments.dut_emu) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  ::execv(args[0], args.data());
  std::cerr << "link_intruder: cannot start " << args[0] << "\n";
  return 1;
}
