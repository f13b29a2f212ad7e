#include "host/linked_dut/process_dut.h"

#include <cmath>

#include "host/linked_dut/process_dut_link.h"
#include "rig/number_text.h"

namespace hilrig::host {

std::string ListenEndpoint(const ProcessDutOptions& options) {
  return options.listen_address + ":" + std::to_string(options.listen_port);
}

rig::Result<rig::CanBusUri> ParseDutCanBusUri(const std::string& uri) {
  auto parsed = rig::ParseCanBusUri(uri);
  if (!parsed) return parsed.error();
  const auto refused = [&uri](const std::string& why) {
    return rig::MakeError("CAN bus \"" + uri + "\": " + why);
  };
  switch (parsed.value().scheme) {
    case rig::CanBusUri::Scheme::kSocketCan:
      return parsed;
    case rig::CanBusUri::Scheme::kEmulated:
      return refused(
          "an emulated bus lives inside one process, the dut process cannot reach it; "
          "a run's dut bus is socketcan:IFACE");
    case rig::CanBusUri::Scheme::kUdp:
      return refused(
          "the rig chooses the run's own UDP bus to the dut process itself; "
          "a run's dut bus is socketcan:IFACE");
    case rig::CanBusUri::Scheme::kGsUsb:
      return refused(
          "one process claims a gs_usb adapter over libusb, so the runner and the dut process "
          "cannot share it; bring it up under the kernel's gs_usb driver and use socketcan:IFACE");
  }
  return refused("unknown scheme");
}

rig::Result<void> ValidateProcessDutOptions(const ProcessDutOptions& options) {
  const auto bad_timeout = [](double seconds) {
    return !std::isfinite(seconds) || seconds <= 0 || seconds > 3600;
  };
  if (auto session = ValidateLinkedDutOptions(SessionOptionsOf(options)); !session) {
    return session.error();
  }
  if (bad_timeout(options.start_timeout_s)) {
    return rig::MakeError("dut start timeout " + rig::NumberText(options.start_timeout_s) +
                          " s: must be positive, finite and at most an hour");
  }
  if (options.listen_address.empty()) return rig::MakeError("empty link listen address");
  if (options.transport == DutLinkTransport::kSharedMemory &&
      options.listen_address != ProcessDutOptions{}.listen_address) {
    return rig::MakeError(
        "link listen address " + options.listen_address +
        ": a listen address is for the TCP link, the shared-memory link has none");
  }
  if (options.listen) {
    if (options.transport != DutLinkTransport::kTcp) {
      return rig::MakeError("a DUT that dials in does so over the TCP link");
    }
    if (options.listen_port == 0 || options.listen_port == 65535) {
      return rig::MakeError("listen port " + std::to_string(options.listen_port) +
                            ": must be 1 to 65534 (the CAN bus takes the next one)");
    }
    if (options.token_file.empty()) return rig::MakeError("a listening DUT needs a token file");
  }
  if (!options.can_uri.empty()) {
    if (auto uri = ParseDutCanBusUri(options.can_uri); !uri) return uri.error();
  }
  return {};
}

LinkedDutOptions SessionOptionsOf(const ProcessDutOptions& options) {
  LinkedDutOptions session;
  session.pacing = options.pacing;
  session.answer_timeout_s = options.answer_timeout_s;
  session.clock = options.wall_clock;
  session.pacing_option = "ProcessDutOptions::pacing, ProcessDutOptions::wall_clock";
  return session;
}

ProcessDut::ProcessDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
                       double control_period_s, const ProcessDutOptions& options)
    : LinkedDut(std::make_unique<ProcessDutLink>(firmware, control_period_s, options),
                std::move(runner_bus), SessionOptionsOf(options)) {}

rig::Result<std::unique_ptr<ProcessDut>> ProcessDut::Launch(const DutFirmware& firmware,
                                                            std::unique_ptr<rig::CanBus> runner_bus,
                                                            double control_period_s,
                                                            const ProcessDutOptions& options) {
  auto dut =
      std::make_unique<ProcessDut>(firmware, std::move(runner_bus), control_period_s, options);
  if (auto started = dut->Start(); !started) return started.error();
  return dut;
}

pid_t ProcessDut::pid() const { return static_cast<const ProcessDutLink&>(link()).pid(); }

}  // namespace hilrig::host
