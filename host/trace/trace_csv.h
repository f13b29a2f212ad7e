// Writes trace samples as CSV with a header row. Numbers are printed in their shortest form that
// reads back to the same double (std::to_chars), which is both fast enough for the lockstep loop
// and byte-reproducible: the same run gives the same file.
#pragma once

#include <ostream>
#include <string>

#include "host/trace/trace_sample.h"

namespace hilrig::host {

class TraceCsvWriter {
 public:
  // Writes the header at once; `out` must outlive the writer.
  explicit TraceCsvWriter(std::ostream& out);

  void Write(const TraceSample& sample);

 private:
  void Append(double value);

  std::ostream& out_;
  std::string line_;
};

}  // namespace hilrig::host
