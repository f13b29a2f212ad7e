#include "rig/bounded_line.h"

namespace hilrig::rig {

LineRead ReadBoundedLine(std::istream& in, std::size_t max_bytes, std::string& line) {
  // Room for one byte past the cap, so a line of exactly the cap is told from a longer one.
  line.resize(max_bytes + 2);
  in.getline(line.data(), static_cast<std::streamsize>(line.size()));
  const auto extracted = static_cast<std::size_t>(in.gcount());
  if (in.bad()) return LineRead::kReadError;
  if (extracted == 0 && in.fail()) return LineRead::kEnd;
  // getline fails with characters extracted only when the buffer filled before a newline.
  if (in.fail()) return LineRead::kTooLong;
  // A newline was extracted (and counted) unless the last line ended without one.
  const std::size_t length = in.eof() ? extracted : extracted - 1;
  if (length > max_bytes) return LineRead::kTooLong;
  line.resize(length);
  return LineRead::kLine;
}

}  // namespace hilrig::rig
