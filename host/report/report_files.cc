#include "host/report/report_files.h"

#include <google/protobuf/util/json_util.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "host/report/xml_text.h"

namespace hilrig::host {

rig::Result<void> WriteTextFile(const std::string& path, const std::string& content) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return rig::MakeError("cannot write " + path);
  file << content;
  file.close();
  if (!file) return rig::MakeError("error while writing " + path);
  return {};
}

namespace {

std::string FormatNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}

std::string FormatBounds(const proto::EnvelopeResult& result) {
  std::ostringstream bounds;
  bounds << '[' << (result.has_lower() ? FormatNumber(result.lower()) : "-") << ", "
         << (result.has_upper() ? FormatNumber(result.upper()) : "-") << ']';
  return bounds.str();
}

const char* VerdictName(proto::Verdict verdict) { return verdict == proto::PASS ? "PASS" : "FAIL"; }

}  // namespace

rig::Result<void> WriteJsonFile(const google::protobuf::Message& message, const std::string& path) {
  std::string json;
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  const auto status = google::protobuf::util::MessageToJsonString(message, &json, options);
  if (!status.ok()) return rig::MakeError("cannot render " + path + ": " + status.ToString());
  return WriteTextFile(path, json);
}

rig::Result<void> WriteJunitXml(const proto::Report& report, const std::string& path) {
  int failures = 0;
  std::ostringstream cases;
  for (const proto::EnvelopeResult& result : report.envelopes()) {
    cases << "    <testcase classname=\"" << EscapeXmlText(report.scenario()) << "\" name=\""
          << EscapeXmlText(result.name()) << "\">\n";
    if (!result.meets_expectation()) {
      ++failures;
      cases << "      <failure message=\"" << EscapeXmlText(FormatEnvelopeLine(result)) << "\"/>\n";
    }
    cases << "    </testcase>\n";
  }
  if (report.stop_reason() != "completed") {
    ++failures;
    cases << "    <testcase classname=\"" << EscapeXmlText(report.scenario())
          << "\" name=\"run completes\">\n      <failure message=\""
          << EscapeXmlText(report.stop_reason()) << "\"/>\n    </testcase>\n";
  }
  const int tests = report.envelopes_size() + (report.stop_reason() != "completed" ? 1 : 0);
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites>\n  <testsuite name=\"" << EscapeXmlText(report.scenario()) << "\" tests=\""
      << tests << "\" failures=\"" << failures << "\" time=\"" << report.wall_s() << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  return WriteTextFile(path, xml.str());
}

std::string FormatEnvelopeLine(const proto::EnvelopeResult& result) {
  std::string line = std::string(VerdictName(result.verdict())) + "  " + result.name();
  if (result.samples_checked() == 0) {
    line += "  no samples in its window";
  } else {
    line += "  worst " + FormatNumber(result.worst_value()) + " at " +
            FormatNumber(result.worst_at_s()) + " s";
  }
  line += "  limit " + FormatBounds(result);
  if (result.verdict() == proto::FAIL && result.samples_checked() > 0) {
    line += "  first out at " + FormatNumber(result.first_violation_at_s()) + " s";
  }
  if (result.expected() != proto::PASS) {
    line += std::string("  (expected ") + VerdictName(result.expected()) +
            (result.meets_expectation() ? ", as expected)" : ", NOT MET)");
  }
  return line;
}

std::string FormatTimingLine(const proto::Report& report) {
  char buffer[200];
  std::snprintf(buffer, sizeof(buffer),
                "real-time factor %.0fx (%.3g s simulated in %.3g s wall, %s; setup %.3g s)",
                report.real_time_factor(), report.simulated_s(), report.wall_s(),
                report.stop_reason().c_str(), report.setup_s());
  return buffer;
}

std::string FormatObjectLine(const proto::ObjectOutcome& outcome) {
  char buffer[200];
  if (outcome.damage() == "none") {
    std::snprintf(buffer, sizeof(buffer), "object %s: undamaged, %s, peak %.3g N per pad",
                  outcome.fixture().c_str(), outcome.final_state().c_str(),
                  outcome.peak_normal_force_n());
  } else {
    std::snprintf(buffer, sizeof(buffer), "object %s: %s at %.3g s, %s, peak %.3g N per pad",
                  outcome.fixture().c_str(), outcome.damage().c_str(), outcome.damaged_at_s(),
                  outcome.final_state().c_str(), outcome.peak_normal_force_n());
  }
  return buffer;
}

}  // namespace hilrig::host
