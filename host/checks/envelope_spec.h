// An envelope of a scenario, resolved from its spec: the signal it watches, its bounds and time
// window, and the verdict the author expects. ResolveScenario fills it; the checks, the runner and
// the run's plots read it, so none of them needs the spec's message types.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "host/trace/trace_sample.h"

namespace hilrig::host {

enum class EnvelopeVerdict { kPass, kFail };

struct EnvelopeSpec {
  std::string name;
  // The trace signal's key, the enum SignalReaderFor reads and the report names.
  proto::Signal signal = proto::SIGNAL_UNSPECIFIED;
  std::optional<std::size_t> pad;  // the pad a PAD_* signal watches (0 = tactile node 1)
  std::optional<double> lower;     // unset: no lower bound
  std::optional<double> upper;     // unset: no upper bound
  double from_s = 0;
  std::optional<double> until_s;  // unset: to the end of the run
  EnvelopeVerdict expect = EnvelopeVerdict::kPass;
  bool abort_on_violation = false;  // stop the run at the first violation
  // Check the signal's mean over this trailing window instead of each sample.
  std::optional<double> mean_over_s;
};

}  // namespace hilrig::host
