// Starting the dut_emu process of a ProcessDut and opening its HIL link, on either transport
// (DutLinkTransport): shared memory for a DUT on this host (the child inherits the mapping's
// descriptor, which nobody else can reach, so no token; the tick's CAN frames ride in the step
// requests), or TCP (the child dials the runner's listener and proves the link token it finds in
// its environment; the CAN frames cross a loopback UDP bus). With ProcessDutOptions::can_uri the
// frames cross that bus on either transport. Both watch the child while they wait for its hello,
// so a DUT that dies or never speaks fails the start with an error that says which.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "host/link/child_process.h"
#include "host/link/hil_link_socket.h"
#include "host/linked_dut/process_dut.h"
#include "rig/can_bus.h"
#include "rig/result.h"

namespace hilrig::host {

// `seconds` in whole milliseconds, rounded up (a wait never ends before its deadline).
inline int CeilMilliseconds(double seconds) { return static_cast<int>(std::ceil(seconds * 1000)); }

struct LaunchedDut {
  std::optional<ChildProcess> child;  // none for a DUT that dialled in (ProcessDutOptions::listen)
  std::unique_ptr<LinkConnection> link;  // the DUT's hello read, nothing sent yet
  // Where the runner forwards the DUT's CAN frames; null: they travel in the step requests.
  std::unique_ptr<rig::CanBus> forward_bus;
  std::uint64_t peers_refused = 0;  // TCP: connections that did not prove the token
  std::string peers_refused_summary;
};

// Spawns `dut_emu_path` on options.transport and waits (at most options.start_timeout_s) for the
// DUT's hello; with options.listen, spawns nothing and waits as long for a DUT the user starts
// to dial in and prove the token (ignoring `dut_emu_path`). Fails when the listener, mapping, bus
// or child cannot be made, when the child exits, when no proper hello comes in time, or (code
// kInterrupted) on options.stop_requested.
rig::Result<LaunchedDut> LaunchDut(const std::string& dut_emu_path,
                                   const ProcessDutOptions& options);

}  // namespace hilrig::host
