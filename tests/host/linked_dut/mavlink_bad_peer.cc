// A MAVLink flight stack that breaks the simulator contract on purpose, started by MavlinkDut in
// the stand-in's place (tests/host/linked_dut/mavlink_bad_peer_test.cc). It takes the stand-in's
// arguments (--mavlink HOST:PORT --api HOST:PORT --config FILE) and one more, --mode:
//   silent      connects and announces itself, then never answers a step
//   garbage     answers each step with bytes that are no frame
//   nan         answers with a motor output that is not a number
//   twice       answers each step twice
//   wrong-time  answers each step at a time a microsecond later than asked
//   disconnect  answers ten steps, then hangs up and exits with status 3
//   refuse      denies every command (COMMAND_ACK result 4) and answers the steps
//   no-gripper  answers the gripper command as unsupported (result 3), as a PX4 without one does
//   echo        answers each step properly, after estimates that tell what it received: position
//               (north 1, east 2, down -3) m, external force north = the last gripper command's
//               param3, grasp force = the CAN_FRAMEs received so far
//   mute        connects but never sends its heartbeat on the API link
//   late        answers nothing for 15 steps, then those and every step after, as PX4 boots
// Otherwise it answers each step properly, all outputs zero and disarmed.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dut_link/posix/line_io.h"
#include "host/mavlink/mavlink_frame.h"
#include "host/mavlink/mavlink_messages.h"

namespace {

namespace mav = ::hilrig::mavlink;

struct Endpoint {
  std::string host;
  std::uint16_t port = 0;
};

std::optional<Endpoint> ParseEndpoint(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos) return std::nullopt;
  return Endpoint{text.substr(0, colon),
                  static_cast<std::uint16_t>(std::stoi(text.substr(colon + 1)))};
}

struct Peer {
  int tcp = -1;
  int udp = -1;
  sockaddr_in api{};
  std::uint8_t sequence = 0;

  void Write(int fd, std::span<const std::uint8_t> bytes, const sockaddr_in* to = nullptr) const {
    if (to != nullptr) {
      ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(to),
               sizeof *to);
    } else {
      (void)!::write(fd, bytes.data(), bytes.size());
    }
  }
  void Send(const mav::AnyMessage& message, bool api_link) {
    std::array<std::uint8_t, mav::kMaxFrameBytes> frame;
    const std::size_t size = mav::EncodeMessage(message, sequence++, 1, 1, frame);
    Write(api_link ? udp : tcp, std::span(frame.data(), size), api_link ? &api : nullptr);
  }
};

// What the echo mode reports.
struct Received {
  float gripper_param3 = 0;
  int can_frames = 0;
};

// Answers the commands the API link brought: accepted, or refused as `mode` says.
void DrainApi(Peer& peer, const std::string& mode, Received& received) {
  std::array<std::uint8_t, 512> datagram;
  while (true) {
    const ssize_t got = ::recv(peer.udp, datagram.data(), datagram.size(), MSG_DONTWAIT);
    if (got <= 0) return;
    mav::FrameParser parser(&mav::FindWireInfo);
    parser.Feed(std::span<const std::uint8_t>(datagram.data(), std::size_t(got)),
                [&](const mav::Frame& frame) {
                  const auto message = mav::DecodeMessage(frame);
                  const auto* command =
                      message ? std::get_if<mav::CommandLong>(&*message) : nullptr;
                  if (command == nullptr) return;
                  if (command->command == 211) received.gripper_param3 = command->param3;
                  mav::CommandAck ack;
                  ack.command = command->command;
                  ack.result = 0;                        // MAV_RESULT_ACCEPTED
                  if (mode == "refuse") ack.result = 4;  // MAV_RESULT_DENIED
                  // MAV_CMD_DO_GRIPPER, MAV_RESULT_UNSUPPORTED
                  if (mode == "no-gripper" && command->command == 211) ack.result = 3;
                  peer.Send(ack, /*api_link=*/true);
                });
  }
}

void Answer(Peer& peer, const std::string& mode, std::uint64_t time_usec,
            const Received& received) {
  if (mode == "echo") {
    mav::DebugFloatArray estimates;
    estimates.time_usec = time_usec;
    estimates.array_id = 1;
    const std::string name = "hilrig";
    std::copy(name.begin(), name.end(), estimates.name.begin());
    estimates.data[0] = 1;
    estimates.data[1] = 2;
    estimates.data[2] = -3;
    estimates.data[3] = received.gripper_param3;
    estimates.data[6] = static_cast<float>(received.can_frames);
    peer.Send(estimates, /*api_link=*/true);
  }
  mav::HilActuatorControls controls;
  controls.time_usec = mode == "wrong-time" ? time_usec + 1 : time_usec;
  controls.mode = 1;
  controls.flags = 1;
  if (mode == "nan") controls.controls[2] = std::numeric_limits<float>::quiet_NaN();
  if (mode == "garbage") {
    const std::array<std::uint8_t, 8> junk = {0x00, 0x13, 0x37, 0xFD, 0x01, 0x02, 0x42, 0x99};
    peer.Write(peer.tcp, junk);
    return;
  }
  peer.Send(controls, /*api_link=*/false);
  if (mode == "twice") peer.Send(controls, /*api_link=*/false);
}

}  // namespace

int main(int argc, char** argv) {
  std::optional<Endpoint> sim, api;
  std::string mode;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--mavlink") sim = ParseEndpoint(value);
    if (flag == "--api") api = ParseEndpoint(value);
    if (flag == "--mode") mode = value;
  }
  if (!sim || !api) {
    std::cerr << "mavlink_bad_peer: --mavlink HOST:PORT --api HOST:PORT [--mode MODE]\n";
    return 2;
  }
  Peer peer;
  peer.udp = ::socket(AF_INET, SOCK_DGRAM, 0);
  peer.api.sin_family = AF_INET;
  peer.api.sin_port = htons(api->port);
  ::inet_pton(AF_INET, api->host.c_str(), &peer.api.sin_addr);
  // Dialled first, as PX4 does: a rig that waits for its flight stack binds both ports before.
  hilrig::dut_link::OwnedLine line;
  for (int attempt = 0; attempt < 500 && !line.ok(); ++attempt) {
    line = hilrig::dut_link::ConnectTcpLine(sim->host, sim->port, 1000);
    if (!line.ok()) ::usleep(10'000);
  }
  if (!line.ok()) {
    std::cerr << "mavlink_bad_peer: " << line.error() << "\n";
    return 1;
  }
  peer.tcp = line.fd();
  if (mode != "mute") peer.Send(mav::Heartbeat{}, /*api_link=*/true);
  mav::FrameParser parser(&mav::FindWireInfo);
  std::array<std::uint8_t, 1024> bytes;
  int steps = 0;
  std::vector<std::uint64_t> held;  // `late`: the steps not answered yet
  Received received;
  while (true) {
    pollfd entry{peer.tcp, POLLIN, 0};
    if (::poll(&entry, 1, 100) <= 0) continue;
    const ssize_t got = ::read(peer.tcp, bytes.data(), bytes.size());
    if (got <= 0) return 0;
    DrainApi(peer, mode, received);
    parser.Feed(std::span<const std::uint8_t>(bytes.data(), std::size_t(got)),
                [&](const mav::Frame& frame) {
                  const auto message = mav::DecodeMessage(frame);
                  if (message && std::holds_alternative<mav::CanFrame>(*message)) {
                    ++received.can_frames;
                  }
                  const auto* sensor = message ? std::get_if<mav::HilSensor>(&*message) : nullptr;
                  if (sensor == nullptr || mode == "silent") return;
                  ++steps;
                  if (mode == "disconnect" && steps > 10) {
                    ::close(peer.tcp);
                    std::_Exit(3);
                  }
                  if (mode == "late" && steps <= 15) {
                    held.push_back(sensor->time_usec);
                    return;
                  }
                  for (const std::uint64_t time_usec : held) {
                    Answer(peer, mode, time_usec, received);
                  }
                  held.clear();
                  Answer(peer, mode, sensor->time_usec, received);
                });
  }
}
