// `hilrig compare BASE CANDIDATE`: the regression gate between two builds' results.
//   hilrig compare BASE CANDIDATE [--margin-tolerance F] [--pass-rate-tolerance P]
//                  [--confidence C] [--trace-atol A] [--trace-rtol R] [--out FILE]
// BASE and CANDIDATE are two run folders (`hilrig run --out`) or two sweep folders (`hilrig sweep
// --out`). Prints each envelope's and check's change (for runs each traced signal's largest
// difference and where the traces part, for sweeps the cases whose verdict flipped, which are
// listed and not graded), writes the comparison as JSON to FILE if asked, and exits 0 when the
// candidate is not worse than the base beyond the tolerances, 1 when it is, 2 for bad usage or a
// folder that cannot be read (a sweep's runs.csv among its files).
#pragma once

#include <string>
#include <vector>

#include "host/cli/cli_args.h"

namespace hilrig::host {

int CompareCommand(const std::vector<std::string>& args, const CliStreams& io);

}  // namespace hilrig::host
