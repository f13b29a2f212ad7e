// Reads text a line at a time with a cap on a line's length, so an input without newlines (a
// binary file, /dev/zero, a hostile writer on a pipe) costs at most the cap in memory: the reader
// stops at the first line past it instead of buffering the whole stream. For line-oriented inputs
// whose lines are short by nature (decode's readings, candump logs).
#pragma once

#include <cstddef>
#include <istream>
#include <string>

namespace hilrig::rig {

enum class LineRead {
  kLine,       // `line` holds the next line, without its newline
  kTooLong,    // the next line is longer than the cap; the stream is left part-way into it
  kEnd,        // no more lines
  kReadError,  // the stream failed (badbit), e.g. an I/O error on the descriptor beneath it
};

// Reads the next line of `in` into `line`; never holds more than `max_bytes` + 2 bytes of it.
LineRead ReadBoundedLine(std::istream& in, std::size_t max_bytes, std::string& line);

}  // namespace hilrig::rig
