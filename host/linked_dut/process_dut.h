// The DUT as its own process: dut_emu, a user's program (`--dut exec:`) or a DUT the user starts
// (`--dut listen:`), on the HIL link. The link is shared memory by default
// (host/link/shm_byte_stream.h: a tick costs no system call, and the tactile CAN frames ride in
// the step request), or TCP with the frames on a loopback UDP CAN bus (DutLinkTransport::kTcp).
// Each step hands over the frames that reached the runner's "dut" endpoint since the last one and
// says how many and when they arrived, so the DUT process sees exactly what the in-process DUT
// would. The session (lockstep or real time, the watchdog, the first failure that sticks, bye and
// reap) is LinkedDut's; the link's half is host/linked_dut/process_dut_link.h.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/dut/firmware_config.h"
#include "host/linked_dut/linked_dut.h"
#include "rig/can_bus.h"
#include "rig/can_open.h"
#include "rig/clock.h"

namespace hilrig::host {

// What carries the HIL link to the dut_emu process (host/linked_dut/process_dut_launch.h).
enum class DutLinkTransport {
  kSharedMemory,  // memfd rings inherited by the child: same host, fastest, no token
  kTcp,           // a TCP connection to listen_address, proven with the link token
};

struct ProcessDutOptions {
  DutLinkTransport transport = DutLinkTransport::kSharedMemory;
  std::string dut_emu_path;  // empty: "dut_emu" next to the running executable
  // `--dut exec:`: a program of the user's, started in dut_emu's place with `program_args` before
  // the link's arguments; it speaks the HIL link as dut_emu does. A path, or a name looked up in
  // PATH. Empty: dut_emu.
  std::string program;
  std::vector<std::string> program_args;
  // `--dut listen:`: start nothing, and wait (start_timeout_s) on listen_address:listen_port for a
  // DUT the user starts, which proves the token in token_file (written there with a new token
  // when the file does not exist). Over TCP, its CAN frames on the loopback UDP bus at
  // listen_port + 1 (it is node 1 of 2), or on can_uri.
  bool listen = false;
  std::uint16_t listen_port = 0;
  std::string token_file;
  // Where the wait for a DUT to dial in is announced (may be null), and what ends it early (may be
  // null): a user's Ctrl-C, so a run waiting for a DUT that never comes stops within a slice.
  std::ostream* notes = nullptr;
  const std::atomic<bool>* stop_requested = nullptr;
  // The watchdog: how long one Step waits for its answer (lockstep), or how long the oldest
  // unanswered request may wait in wall time (real time).
  double answer_timeout_s = 1.0;
  double start_timeout_s = 10.0;             // for the process to connect and say hello
  std::string listen_address = "127.0.0.1";  // kTcp only
  std::vector<std::string> extra_args;       // appended to dut_emu's command line (test hooks)
  // Lockstep: inputs go out with the tick's request and Step waits; RequestStep fails. Real time:
  // every message goes out at once, sends never wait for the socket, and the response latencies
  // are measured; it needs wall_clock.
  DutPacing pacing = DutPacing::kLockstep;
  // The clock of the watchdog and the latencies (it must outlive the ProcessDut); null: a
  // SteadyClock of the port's own, for lockstep only. Either way the watchdog's deadlines are on
  // a clock that moves by itself: they bound a real process.
  const rig::Clock* wall_clock = nullptr;
  // The bus the runner's CAN frames cross to the DUT: empty for a loopback UDP bus of the run's
  // own, or a socketcan:IFACE URI that the forwarder and dut_emu both open, as a bench is wired.
  // Nobody announces a real bus's frames to the DUT: they reach it when the bus delivers them, so
  // such a run's CAN timing follows the wall clock and real time is its meaningful mode.
  std::string can_uri;
  // Opens can_uri for the forwarder; unset: rig::OpenCanBus (tests hand in a bus of their own).
  std::function<rig::Result<std::unique_ptr<rig::CanBus>>(const std::string& uri)> open_can_bus;
};

// ProcessDutOptions::can_uri read by rig::ParseCanBusUri, refused unless two processes can share
// the bus it names: the errors name the URI and why.
rig::Result<rig::CanBusUri> ParseDutCanBusUri(const std::string& uri);

// Checks the options: a positive finite timeout, an address (other than the default only on the
// TCP link), a bus the DUT process can share.
rig::Result<void> ValidateProcessDutOptions(const ProcessDutOptions& options);

// "ADDRESS:PORT" a listening ProcessDut waits on.
std::string ListenEndpoint(const ProcessDutOptions& options);

// The process link's session options: its pacing, watchdog and clock.
LinkedDutOptions SessionOptionsOf(const ProcessDutOptions& options);

// A DUT process on the HIL link: the linked-DUT session (host/linked_dut/linked_dut.h) over the
// process link (host/linked_dut/process_dut_link.h).
class ProcessDut final : public LinkedDut {
 public:
  // `runner_bus` is the DUT's endpoint on the runner's emulated bus. Nothing runs until Start,
  // which starts the program (or awaits the DUT that dials in) and completes the handshake: the
  // first connection whose hello proves the token is the DUT (others are refused, counted in
  // link_peers_refused and named in the description), which then gets the runner's hello and the
  // firmware configuration.
  ProcessDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
             double control_period_s, const ProcessDutOptions& options);
  // Constructs and starts one (tests, tools).
  static rig::Result<std::unique_ptr<ProcessDut>> Launch(const DutFirmware& firmware,
                                                         std::unique_ptr<rig::CanBus> runner_bus,
                                                         double control_period_s,
                                                         const ProcessDutOptions& options);

  // -1 before Start, or for a DUT that dialled in.
  pid_t pid() const;
};

}  // namespace hilrig::host
