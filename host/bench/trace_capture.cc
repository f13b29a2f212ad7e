#include "host/bench/trace_capture.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <string_view>

namespace hilrig::host {
namespace {

// The columns kept, by their names in TraceCsvWriter's header.
constexpr std::array<std::string_view, 6> kColumns = {"time_s", "x_m",           "y_m",
                                                      "z_m",    "grasp_force_n", "load_n"};

std::vector<std::string_view> Split(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

bool Parse(std::string_view text, double& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

}  // namespace

TraceCapture::TraceCapture() : std::ostream(nullptr) { rdbuf(&buffer_); }

TraceCapture::LineBuffer::int_type TraceCapture::LineBuffer::overflow(int_type c) {
  if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
  const char ch = traits_type::to_char_type(c);
  if (ch == '\n') {
    EndLine();
  } else {
    line += ch;
  }
  return c;
}

std::streamsize TraceCapture::LineBuffer::xsputn(const char* text, std::streamsize count) {
  for (std::streamsize i = 0; i < count; ++i) overflow(traits_type::to_int_type(text[i]));
  return count;
}

void TraceCapture::LineBuffer::EndLine() {
  if (have_header) {
    ReadRow();
  } else {
    ReadHeader();
  }
  line.clear();
}

void TraceCapture::LineBuffer::ReadHeader() {
  const std::vector<std::string_view> names = Split(line);
  columns.clear();
  for (std::string_view wanted : kColumns) {
    const auto found = std::find(names.begin(), names.end(), wanted);
    columns.push_back(found == names.end() ? -1 : static_cast<int>(found - names.begin()));
  }
  have_header = true;
}

void TraceCapture::LineBuffer::ReadRow() {
  const std::vector<std::string_view> fields = Split(line);
  std::array<double, kColumns.size()> values{};
  for (std::size_t i = 0; i < kColumns.size(); ++i) {
    const int column = columns[i];
    if (column < 0 || static_cast<std::size_t>(column) >= fields.size() ||
        !Parse(fields[static_cast<std::size_t>(column)], values[i])) {
      ++bad_rows;
      return;
    }
  }
  trace.time_s.push_back(values[0]);
  trace.position_m.emplace_back(values[1], values[2], values[3]);
  trace.grasp_force_n.push_back(values[4]);
  trace.load_n.push_back(values[5]);
}

}  // namespace hilrig::host
