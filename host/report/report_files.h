// Writes a run report in its file forms: report.json (the protobuf JSON rendering of
// proto/report.proto; WriteJsonFile serves the other result messages too) and junit.xml (one test
// case per envelope, so CI systems show each check), and renders the console lines `hilrig run`
// prints.
#pragma once

#include <google/protobuf/message.h>

#include <string>
#include <vector>

#include "proto/report.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// Any of the rig's result messages (report, accuracy) as protobuf JSON, field names as in .proto.
rig::Result<void> WriteJsonFile(const google::protobuf::Message& message, const std::string& path);
// Reads a file WriteJsonFile wrote (or a later build's, whose unknown fields are skipped) into
// `message`. Fails, naming the file, when it cannot be read, is over 64 MiB or is not that
// message's JSON.
rig::Result<void> ReadJsonFile(const std::string& path, google::protobuf::Message& message);
// Whole or not at all: written beside `path` and renamed over it.
rig::Result<void> WriteTextFile(const std::string& path, const std::string& content);
rig::Result<void> WriteJunitXml(const proto::Report& report, const std::string& path);

// "PASS  altitude_error  worst 0.0123 at 12.3 s  limit [-, 0.05]" (+ "(expected FAIL)" etc.).
std::string FormatEnvelopeLine(const proto::EnvelopeResult& result);

// "DUT FAULT  3 non-finite commands refused, the first at 2.01 s (rotor_thrust_n[0] = nan): the
// run fails".
std::string FormatDutFaultLine(const proto::DutFaults& faults);

// "object balloon: burst at 12.3 s, destroyed, peak 0.46 N per pad".
std::string FormatObjectLine(const proto::ObjectOutcome& outcome);

// The last line of a run: simulated and wall time and the real-time factor.
std::string FormatTimingLine(const proto::Report& report);

// A timing or target check's value or limit in the units a bench engineer reads timing in: seconds
// ("s") as "1020 us", fractions as "0.78 %".
std::string FormatTimingValue(double value, const std::string& unit);

// "PASS  timing loop_period_p99_max_s  1020 us  limit 2000 us", or "----  timing
// loop_period_p99_max_s  not evaluated (lockstep)  limit 2000 us"; `kind` is the second word
// ("target" for the target envelopes).
std::string FormatTimingCheckLine(const proto::TimingCheckResult& result,
                                  const char* kind = "timing");

// "target stm32f405 at 168 MHz: work per control step p50 1302, p99 1410, max 2210 cycles (0.78 %,
// 0.84 %, 1.3 % of 1000 us) over 3000 steps; flash 41234 B, RAM 6120 B".
std::string FormatTargetLine(const proto::Target& target);

// A real-time run's timing block: loop period p50/p99/max, late ticks, tick work, missed DUT
// commands and the DUT's latency per stream, in µs. None for a lockstep run.
std::vector<std::string> FormatRealtimeTiming(const proto::Timing& timing);
// "fidelity error vs reference DP(1e-10) x8 tiles:64 (cached): grasp force RMS ... N (max ...),
// load RMS ..., position RMS ... m (max ...)"; the grasp force and load only in grasp scenes.
std::string FormatFidelityErrorLine(const proto::FidelityError& error, bool grasp_scene);

}  // namespace hilrig::host
