// dut_emu: the dut_fw controller as its own process, behind the HIL link. It connects to the
// runner's link, proves with the runner's link token that it is the DUT the runner started, takes
// the firmware configuration the runner sends (refused if any number is bad), and from then on
// forwards each link message to an InProcessDut -- the very code the in-process run uses, not a
// copy -- which reads the tactile sensors from a CAN bus of its own (the loopback UDP bus, or
// a real bus on a bench, any rig::OpenCanBus opens). On the shared-memory link (--link-shm, a
// descriptor the runner handed down; no token) the frames ride in the step requests instead
// (link_can_bus.h) and take the same path to the DUT from there. A StepRequest is answered with the
// ActuatorCommand of that tick. In lockstep the request says how many CAN frames the runner put on
// the bus for this step and when each finished arriving on the emulated bus; the server waits for
// exactly those frames (the bus and the link are separate channels) and hands them to the DUT with
// those times, so both runs see the same inputs. In a real-time run the runner does not wait for
// the answer, so the server waits for the frames at most one control period and then steps with
// what arrived (counted); frames a DUT that fell behind finds ahead of their request wait for it
// (staged_can_bus.h). Each command says what the DUT had consumed (last IMU / VIO / setpoint
// sequence, CAN frames), from which the runner measures response latency per stream.
//
// The library part lets tests run the server in a thread; dut_emu/main.cc is the executable.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/link/link_token.h"
#include "rig/can_bus.h"
#include "rig/can_open.h"
#include "rig/result.h"

namespace hilrig::dut_emu {

// Exit codes of dut_emu.
inline constexpr int kExitOk = 0;        // the runner said bye, or a signal asked us to stop
inline constexpr int kExitFailed = 1;    // the link or the bus failed, or the runner misbehaved
inline constexpr int kExitUsage = 2;     // bad command line
inline constexpr int kExitTestHook = 3;  // --test-exit-at-tick fired

struct DutEmuOptions {
  std::string link_host = "127.0.0.1";
  std::uint16_t link_port = 0;
  // --link-shm FD: the shared-memory link whose descriptor the runner handed down (instead of
  // --link); -1: TCP. Nobody else can reach it, so it takes no link token.
  int link_shm_fd = -1;
  // --link-shm without --can: the CAN frames ride in the step requests, no bus carries them.
  bool can_in_link = false;
  // What the hello proves to the runner (LoadLinkToken); without one the runner refuses the DUT.
  std::optional<host::LinkToken> link_token;
  std::string token_file;  // --token-file: where a DUT started by hand finds its token
  // --can, as rig::OpenCanBus reads it; the runner's UDP bus, whose frames it announces, unless
  // told otherwise.
  rig::CanBusUri can{rig::CanBusUri::Scheme::kUdp, {}, {}, {}};
  int connect_timeout_ms = 5000;
  // How long a StepRequest waits for the CAN frames it announces before the DUT gives up.
  int frame_wait_timeout_ms = 1000;
  // Test hooks that make the DUT misbehave when asked for this tick: answer with bytes that are
  // no link frame, exit without a word, stay silent (and alive), or answer a tick never asked
  // for (this tick + kWrongTickOffset).
  std::optional<std::uint64_t> garbage_at_tick;
  std::optional<std::uint64_t> exit_at_tick;
  std::optional<std::uint64_t> silent_at_tick;
  std::optional<std::uint64_t> wrong_tick_at_tick;
};

inline constexpr std::uint64_t kWrongTickOffset = 1'000'000;

// argv[1..] of dut_emu: (--link HOST:PORT --can URI | --link-shm FD [--can URI])
// [--token-file PATH] [--frame-timeout-ms N]
// [--test-garbage-at-tick T] [--test-exit-at-tick T] [--test-silent-at-tick T]
// [--test-wrong-tick-at-tick T].
rig::Result<DutEmuOptions> ParseDutEmuArgs(const std::vector<std::string>& args);

// The link token for the hello: read from options.token_file when one is given, else parsed from
// `environment_value`, the value of host::kLinkTokenEnvironment (null: unset), which is how the
// runner hands it to the dut_emu it starts. Missing or malformed: an error saying where to put it.
rig::Result<host::LinkToken> LoadLinkToken(const DutEmuOptions& options,
                                           const char* environment_value);

extern const char* const kDutEmuUsage;

// Runs the DUT until the runner says bye, the link fails or `stop_requested` is set; returns an
// exit code and says why on `log`. `bus`, when given, replaces the bus options.can describes.
int RunDutEmu(const DutEmuOptions& options, const std::atomic<bool>* stop_requested,
              std::ostream& log, std::unique_ptr<rig::CanBus> bus = nullptr);

}  // namespace hilrig::dut_emu
