// Which DUT a run talks to, as `hilrig run --dut` and its options name it, and the one factory
// that builds it. The command line only hands over the words; the kinds, which option goes with
// which kind, and every DUT's construction live here, so a new kind of DUT (a user's program, a
// MAVLink peer) is added in this file and its port, not in each command.
#pragma once

#include <atomic>
#include <optional>
#include <ostream>
#include <string>

#include "host/dut/dut_port.h"
#include "host/linked_dut/dialed_lines.h"
#include "host/linked_dut/mavlink_dut.h"
#include "host/linked_dut/process_dut.h"
#include "host/linked_dut/serial_dut.h"
#include "host/linked_dut/serial_lines.h"
#include "rig/result.h"

namespace hilrig::host {

enum class DutKind {
  kInProcess,       // dut_fw in this process, in double precision (the default)
  kInProcessFloat,  // dut_fw in this process, in single precision as the target computes it
  kProcess,         // dut_emu in a process of its own, over the HIL link
  kExec,            // a program of the user's in dut_emu's place, over the same link
  kListen,          // a program the user starts, which dials the rig's TCP link
  kQemu,            // the firmware image on QEMU's STM32F405, over its serial lines
  kSerial,          // a board on serial devices
  kMavlinkEmu,      // PX4's stand-in (dut_emu --mavlink) over MAVLink, as PX4 SITL is driven
  kPx4Sitl,         // PX4 SITL the user starts, over MAVLink
  kMavlinkEmuHitl,  // PX4's stand-in on a pseudo-terminal, in real time, as a board is driven
  kPx4Hitl,         // PX4 on a board, over MAVLink on its serial port, in real time
};

// The word `--dut` takes for a kind ("inproc", "inproc-float", "process", "exec", "listen",
// "qemu", "serial", "mavlink-emu", "px4-sitl", "mavlink-emu-hitl", "px4-hitl"); exec, listen,
// serial and px4-hitl take their details after a colon, px4-sitl may take its simulator port.
const char* DutKindName(DutKind kind);

// The command line's words, unparsed; unset: the option was not given.
struct DutArguments {
  std::optional<std::string> dut;           // --dut
  std::optional<std::string> timeout_s;     // --dut-timeout-s
  std::optional<std::string> link;          // --dut-link
  std::optional<std::string> can;           // --can
  std::optional<std::string> target_image;  // --target-image
};

// A parsed, checked DUT description: the kind and the options of that kind (the others keep
// their defaults).
struct DutChoice {
  DutKind kind = DutKind::kInProcess;
  // kProcess; kExec (program, program_args); kListen (listen, listen_address, listen_port,
  // token_file)
  ProcessDutOptions process;
  SerialDutOptions serial;  // kQemu, kSerial, and kExec and kListen on `line`
  // kExec and kListen with --dut-link line: the DUT speaks the serial link over TCP and dials the
  // rig (host/linked_dut/dialed_lines.h) instead of the process link.
  bool line = false;
  DialedLineSpec dialed;
  SerialPortSpec port;                      // kSerial
  MavlinkDutPortOptions mavlink;            // kMavlinkEmu, kPx4Sitl
  std::optional<std::string> target_image;  // kQemu; unset: the one ./scripts/build-target makes
};

// Fails, naming the option, on an unknown kind, an option the kind does not take (--target-image
// without qemu, --dut-link or --can without process or exec, --dut-timeout-s with an in-process
// DUT) or a value out of range. `exec:PROGRAM[,ARG...]` splits at commas: an argument cannot
// hold one. `listen:ADDRESS:PORT[,token=FILE]` waits 60 s by default (a person starts the DUT;
// --dut-timeout-s does not change it), with the token in ./hilrig_link_token unless FILE is
// given. Reads no file and opens nothing.
rig::Result<DutChoice> ParseDutChoice(const DutArguments& arguments);

// What the DUTs a factory makes may reach of the command that runs them (each may be null): its
// stop request, which ends a wait for a DUT to dial in, and where that wait is announced.
struct DutFactorySeams {
  const std::atomic<bool>* stop_requested = nullptr;
  std::ostream* notes = nullptr;
};

// The factory of the chosen DUT; `realtime` gives a DUT behind a link a wall clock of its own for
// its watchdog and latencies, kept alive by the factory. Fails for kQemu when the image cannot be
// found (the error lists where it looked), and for kMavlinkEmu in real time. Nothing starts until
// the runner calls the factory.
rig::Result<DutFactory> MakeDutFactory(const DutChoice& choice, bool realtime,
                                       const DutFactorySeams& seams = {});

}  // namespace hilrig::host
