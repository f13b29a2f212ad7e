// The page of a sweep folder, index.html beside summary.json, written by the merge: the sweep's
// verdict, its criteria measured against their limits, each envelope's pass rate with its Wilson
// interval and margin quantiles, the pass map of a sweep over two axes (sweep_map.h), a histogram
// of each envelope's worst value across the cases with its limits drawn, and the cases that did
// not pass with the command that runs each alone. Like summary.json it is made from the case rows,
// the summary and the sweep alone, never from the timing columns, the shard split or the output
// folder's path, so a sweep merged from any number of shards, here or on a cluster, gets the same
// bytes. One self-contained file (host/report/html_page.h: no script, no load): the map is drawn
// in the page, and map.svg beside it is a link, never loaded.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "host/sweep/sweep_spec.h"
#include "proto/sweep.pb.h"

namespace hilrig::host {

inline constexpr const char* kSweepPageFile = "index.html";
// The failing cases the page lists; failing.txt has them all.
inline constexpr std::size_t kSweepPageMaxFailing = 100;

// The page for `results` (the merged rows, in case order) and their `summary`; `hilrig` and
// `runs_dir` make the commands as failing.txt has them (ReproduceCommand). Cannot fail: a sweep
// without cases, or worst values that are not finite, get a page that says so.
std::string SweepPageHtml(const LoadedSweep& sweep,
                          const std::vector<proto::SweepCaseResult>& results,
                          const proto::SweepSummary& summary, const std::string& hilrig,
                          const std::string& runs_dir);

}  // namespace hilrig::host
