// `hilrig bench`: the work-precision sweep (host/work_precision/work_precision.h) over one or more
// scenes, written as work_precision.csv and work_precision.svg into --out, with the Pareto fronts
// printed. Options: --out DIR (required), --scenes a,b (names under --scenarios DIR, default
// "scenarios", or paths to .textproto files), --duration-s S, --quick (3 s, a small sweep, a
// tiles:16 reference; for tests).
#pragma once

#include <string>
#include <vector>

#include "host/cli/cli_args.h"

namespace hilrig::host {

int BenchCommand(const std::vector<std::string>& args, const CliStreams& io);

}  // namespace hilrig::host
