#include "host/report/sweep_outcome.h"

namespace hilrig::host {
namespace {

struct NamedOutcome {
  proto::SweepCaseResult::Outcome outcome;
  const char* name;
};

constexpr NamedOutcome kOutcomes[] = {
    {proto::SweepCaseResult::PASSED, "passed"},
    {proto::SweepCaseResult::FAILED, "failed"},
    {proto::SweepCaseResult::STOPPED, "stopped"},
    {proto::SweepCaseResult::INVALID, "invalid"},
    {proto::SweepCaseResult::SET_UP_FAILED, "set_up_failed"},
};

}  // namespace

const char* OutcomeName(proto::SweepCaseResult::Outcome outcome) {
  for (const NamedOutcome& named : kOutcomes) {
    if (named.outcome == outcome) return named.name;
  }
  return "unknown";
}

std::optional<proto::SweepCaseResult::Outcome> OutcomeNamed(std::string_view name) {
  for (const NamedOutcome& named : kOutcomes) {
    if (named.name == name) return named.outcome;
  }
  return std::nullopt;
}

}  // namespace hilrig::host
