// The sizes a scenario spec may have. Names (the scenario's and each envelope's) go into every test
// case of junit.xml, the plots' legends, report.txt and the terminal, so they are one short line of
// characters that no XML reader, CI tool or terminal takes for anything but text. Every other
// string and the spec's lists are bounded so that a spec cannot grow the rig's memory, its output
// files or its error messages without bound.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "host/scenario/field_problems.h"
#include "proto/scenario.pb.h"

namespace hilrig::host {

// A name holds at most this many characters, each a letter, a digit, a space or one of _ - . : + (
// ).
inline constexpr std::size_t kMaxNameChars = 200;
// Every other string: the description, fixture and fidelity names, the calibration file's path.
// 4096 bytes is Linux's PATH_MAX, and pages of description.
inline constexpr std::size_t kMaxTextBytes = 4096;
// Each envelope is checked at every trace sample and is a test case in junit.xml; the shipped
// specs hold 2 to 8.
inline constexpr int kMaxEnvelopes = 1000;
// One entry a second over the longest run (86 400 s) fits. Loading a spec holds its text, the parse
// locations, the messages and the resolved events, about 1.5 KB per entry.
inline constexpr int kMaxTimelineEntries = 100000;

// The envelopes' mean_over_s windows hold every trace sample they span (at most the run), 16 bytes
// each: 1e6 samples in all is 16 MB, a 1000 s steady-state check on ten signals at the default
// 100 Hz trace.
inline constexpr double kMaxMeanWindowSamples = 1e6;

// Adds a problem for each string longer than its limit and each list longer than its bound; false
// when there was one.
bool CheckSpecSizes(const proto::Scenario& scenario, const ProblemList& problems);

// Adds a problem at the envelope whose mean window takes the spec's windows past
// kMaxMeanWindowSamples.
void CheckMeanWindows(const proto::Scenario& scenario, const ProblemList& problems);

// What is wrong with a string field (or element `index` of a repeated one; -1 for a single one)
// that holds a control character, or nothing: paths and names reach the terminal, the pages and
// the commands a sweep writes for a shell, where a line break or an escape sequence would be taken
// for more than text. Line breaks and tabs are allowed in a scenario's description alone. Any
// other field: nothing.
std::optional<std::string> ControlCharacterProblem(const google::protobuf::Message& message,
                                                   const google::protobuf::FieldDescriptor* field,
                                                   int index);

// What is wrong with a name's characters (where, without quoting the name), or nothing.
std::optional<std::string> NameCharacterProblem(std::string_view name);

}  // namespace hilrig::host
