// The pass map of a sweep over two or more list or grid axes: the points of its first two such
// axes as a grid (host/report/grid_map.h), the first across and the second up, each cell filled
// by the share of the cases at the point that passed. A point holds every case at it: each seed,
// each scenario and each value of the further axes, so a sweep with seeds reads "k/n" in its
// cells. The merge writes it beside the sweep's page as map.svg and the page draws it
// (sweep_page.h); like the page it is made from the case rows alone, so it has the same bytes
// whatever the shard split. A sweep with fewer than two such axes has no map.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/report/grid_map.h"
#include "host/sweep/sweep_spec.h"
#include "proto/sweep.pb.h"

namespace hilrig::host {

inline constexpr const char* kSweepMapFile = "map.svg";

// The map's axes, as indices into the spec's axes: the first two with points (a list or a grid;
// a distribution draws a value per case and makes no grid). Nothing with fewer than two.
std::optional<std::pair<int, int>> SweepMapAxes(const proto::Sweep& spec);

// The map of `results` (rows of the sweep's cases, as the merge accepted them; a row whose case
// number the sweep does not have is left out). Nothing when SweepMapAxes is nothing.
std::optional<GridMap> SweepPassMap(const LoadedSweep& sweep,
                                    const std::vector<proto::SweepCaseResult>& results);

// The map as map.svg holds it (RenderGridMapSvg); nothing without a map.
std::optional<std::string> SweepMapSvg(const LoadedSweep& sweep,
                                       const std::vector<proto::SweepCaseResult>& results);

}  // namespace hilrig::host
