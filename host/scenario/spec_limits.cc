#include "host/scenario/spec_limits.h"

#include <algorithm>
#include <cmath>

#include "host/scenario/scenario_config.h"
#include "rig/number_text.h"
#include "rig/printable_text.h"

namespace hilrig::host {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

bool IsName(const FieldDescriptor* field) {
  return field ==
             proto::Scenario::descriptor()->FindFieldByNumber(proto::Scenario::kNameFieldNumber) ||
         field ==
             proto::Envelope::descriptor()->FindFieldByNumber(proto::Envelope::kNameFieldNumber);
}

// The string field's text (element `index` of a repeated one; -1 for a single one); `scratch` may
// hold it.
const std::string& TextOf(const Message& message, const FieldDescriptor* field, int index,
                          std::string& scratch) {
  const auto* reflection = message.GetReflection();
  return index < 0 ? reflection->GetStringReference(message, field, &scratch)
                   : reflection->GetRepeatedStringReference(message, field, index, &scratch);
}

// Only the length is named: the text may be megabytes.
std::optional<std::string> TextSizeProblem(const Message& message, const FieldDescriptor* field,
                                           int index) {
  if (field->cpp_type() != FieldDescriptor::CPPTYPE_STRING) return std::nullopt;
  std::string scratch;
  const std::string& text = TextOf(message, field, index, scratch);
  if (IsName(field)) {
    if (text.size() <= kMaxNameChars) return std::nullopt;
    return "a name may hold at most " + std::to_string(kMaxNameChars) + " characters, got " +
           std::to_string(text.size());
  }
  if (text.size() <= kMaxTextBytes) return std::nullopt;
  return "must be at most " + std::to_string(kMaxTextBytes) + " bytes, got " +
         std::to_string(text.size());
}

// The first entry past the bound is where the problem is located.
bool CheckCount(int count, int bound, const char* list, const ProblemList& problems) {
  if (count <= bound) return true;
  problems.Element(list, bound)
      .AddHere("is past the bound of " + std::to_string(bound) + " " + list +
               " entries (the spec has " + std::to_string(count) + ")");
  return false;
}

bool IsNameCharacter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         std::string_view(" _-.:+()").find(c) != std::string_view::npos;
}

}  // namespace

bool CheckSpecSizes(const proto::Scenario& scenario, const ProblemList& problems) {
  bool within = true;
  CheckEveryScalar(scenario, problems,
                   [&](const Message& message, const FieldDescriptor* field, int index) {
                     auto problem = TextSizeProblem(message, field, index);
                     within = within && !problem;
                     return problem;
                   });
  within =
      CheckCount(scenario.timeline_size(), kMaxTimelineEntries, "timeline", problems) && within;
  within = CheckCount(scenario.envelopes_size(), kMaxEnvelopes, "envelopes", problems) && within;
  return within;
}

void CheckMeanWindows(const proto::Scenario& scenario, const ProblemList& problems) {
  const double trace_rate_hz = TraceRateHz(scenario.simulation());
  const double duration_s = scenario.simulation().duration_s();
  // Bad rates and durations are refused on their own.
  if (!(trace_rate_hz > 0 && std::isfinite(trace_rate_hz) && duration_s > 0)) return;
  double samples = 0;
  for (int i = 0; i < scenario.envelopes_size(); ++i) {
    const proto::Envelope& envelope = scenario.envelopes(i);
    if (!(envelope.mean_over_s() > 0)) continue;
    // A window longer than the run holds the whole run.
    samples += std::min(envelope.mean_over_s(), duration_s) * trace_rate_hz;
    if (samples > kMaxMeanWindowSamples) {
      problems.Element("envelopes", i)
          .Add("mean_over_s", "the mean windows up to here hold " + rig::NumberText(samples) +
                                  " trace samples, past the bound of " +
                                  rig::NumberText(kMaxMeanWindowSamples));
      return;
    }
  }
}

std::optional<std::string> ControlCharacterProblem(const Message& message,
                                                   const FieldDescriptor* field, int index) {
  if (field->cpp_type() != FieldDescriptor::CPPTYPE_STRING) return std::nullopt;
  std::string scratch;
  const std::string& text = TextOf(message, field, index, scratch);
  const bool description = field == proto::Scenario::descriptor()->FindFieldByNumber(
                                        proto::Scenario::kDescriptionFieldNumber);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (description && (c == '\n' || c == '\t')) continue;
    // A C1 control (U+0080 to U+009F) is two bytes in UTF-8.
    const std::size_t width = c == 0xc2 ? 2 : 1;
    if (!rig::IsPrintableText(std::string_view(text).substr(i, width))) {
      return "byte " + std::to_string(i + 1) + " starts a control character (" +
             rig::PrintableText(text.substr(i, width)) + ")";
    }
  }
  return std::nullopt;
}

std::optional<std::string> NameCharacterProblem(std::string_view name) {
  // Every character before the first bad one is ASCII, so its byte offset is its position.
  const auto bad = std::find_if_not(name.begin(), name.end(), IsNameCharacter);
  if (bad == name.end()) return std::nullopt;
  return "character " + std::to_string(bad - name.begin() + 1) +
         " is not a letter, digit, space or one of _ - . : + ( )";
}

}  // namespace hilrig::host
