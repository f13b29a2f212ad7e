#include "host/linked_dut/serial_dut.h"

#include <cmath>

#include "host/linked_dut/serial_dut_link.h"
#include "rig/number_text.h"

namespace hilrig::host {

rig::Result<void> ValidateSerialDutOptions(const SerialDutOptions& options) {
  const auto check = [](double seconds, const char* what) -> rig::Result<void> {
    if (std::isfinite(seconds) && seconds > 0 && seconds <= 3600) return {};
    return rig::MakeError(std::string("serial dut ") + what + " " + rig::NumberText(seconds) +
                          " s: must be positive, finite and at most an hour");
  };
  if (auto session = ValidateLinkedDutOptions(SessionOptionsOf(options)); !session) {
    return session.error();
  }
  for (const auto& [seconds, what] : {std::pair{options.start_timeout_s, "start timeout"},
                                      std::pair{options.hello_interval_s, "hello interval"},
                                      std::pair{options.config_retry_s, "configuration retry"},
                                      std::pair{options.step_retry_s, "step retry"}}) {
    if (auto valid = check(seconds, what); !valid) return valid;
  }
  if (options.step_retry_s >= options.answer_timeout_s) {
    return rig::MakeError("serial dut step retry " + rig::NumberText(options.step_retry_s) +
                          " s: must be shorter than the answer timeout " +
                          rig::NumberText(options.answer_timeout_s) + " s");
  }
  return {};
}

LinkedDutOptions SessionOptionsOf(const SerialDutOptions& options) {
  LinkedDutOptions session;
  session.pacing = options.pacing;
  session.answer_timeout_s = options.answer_timeout_s;
  session.clock = options.clock;
  session.pacing_option = "SerialDutOptions::pacing, SerialDutOptions::clock";
  return session;
}

SerialDut::SerialDut(const DutFirmware& firmware, std::unique_ptr<rig::CanBus> runner_bus,
                     double control_period_s, SerialLineOpener open_lines,
                     const SerialDutOptions& options)
    : LinkedDut(std::make_unique<SerialDutLink>(firmware, control_period_s, std::move(open_lines),
                                                options),
                std::move(runner_bus), SessionOptionsOf(options)) {}

}  // namespace hilrig::host
