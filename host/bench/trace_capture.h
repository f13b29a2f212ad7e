// Keeps, in memory, the few trace columns a work-precision comparison needs (time, position, grasp
// force, vertical load) from a run, without files. RunSinks has no per-sample callback and the
// runner is not ours to change, so TraceCapture is an std::ostream the runner's trace_csv sink
// writes into: TraceCsvWriter formats every double as its shortest round-trip text
// (std::to_chars), so reading the row back with std::from_chars gives the sample's exact values.
// If RunSinks gains a TraceSample callback, only this file changes.
#pragma once

#include <Eigen/Core>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

namespace hilrig::host {

struct CapturedTrace {
  std::vector<double> time_s;
  std::vector<Eigen::Vector3d> position_m;
  std::vector<double> grasp_force_n;
  std::vector<double> load_n;

  std::size_t size() const { return time_s.size(); }
};

class TraceCapture final : public std::ostream {
 public:
  TraceCapture();
  TraceCapture(const TraceCapture&) = delete;
  TraceCapture& operator=(const TraceCapture&) = delete;

  const CapturedTrace& trace() const { return buffer_.trace; }
  // Rows that could not be read (a missing column, a number that does not parse); 0 in a good run.
  std::size_t bad_rows() const { return buffer_.bad_rows; }

 private:
  struct LineBuffer final : std::streambuf {
    std::string line;
    std::vector<int> columns;  // time, x, y, z, grasp force, load; -1: missing from the header
    bool have_header = false;
    CapturedTrace trace;
    std::size_t bad_rows = 0;

    int_type overflow(int_type c) override;
    std::streamsize xsputn(const char* text, std::streamsize count) override;
    void EndLine();
    void ReadHeader();
    void ReadRow();
  };
  LineBuffer buffer_;
};

}  // namespace hilrig::host
