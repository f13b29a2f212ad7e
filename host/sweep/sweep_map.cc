#include "host/sweep/sweep_map.h"

#include "host/sweep/sweep_cases.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

std::vector<std::string> TickLabels(const proto::Axis& axis) {
  std::vector<std::string> labels;
  for (const double value : AxisPoints(axis)) labels.push_back(rig::NumberText(value));
  return labels;
}

}  // namespace

std::optional<std::pair<int, int>> SweepMapAxes(const proto::Sweep& spec) {
  std::vector<int> gridded;
  for (int a = 0; a < spec.axis_size() && gridded.size() < 2; ++a) {
    if (!AxisPoints(spec.axis(a)).empty()) gridded.push_back(a);
  }
  if (gridded.size() < 2) return std::nullopt;
  return std::pair{gridded[0], gridded[1]};
}

std::optional<GridMap> SweepPassMap(const LoadedSweep& sweep,
                                    const std::vector<proto::SweepCaseResult>& results) {
  const auto axes = SweepMapAxes(sweep.spec);
  if (!axes) return std::nullopt;
  const auto [x, y] = *axes;
  GridMap map;
  map.title = sweep.spec.name() + ": cases passed";
  map.x_label = sweep.spec.axis(x).path();
  map.y_label = sweep.spec.axis(y).path();
  map.columns = TickLabels(sweep.spec.axis(x));
  map.rows = TickLabels(sweep.spec.axis(y));
  map.cells.resize(map.columns.size() * map.rows.size());
  const SweepCaseSpace cases(sweep);
  for (const proto::SweepCaseResult& row : results) {
    if (row.index() >= cases.case_count()) continue;
    const SweepCase at = cases.CaseAt(row.index());
    GridMapCell& cell = map.cells[at.point_index[y] * map.columns.size() + at.point_index[x]];
    ++cell.cases;
    if (row.outcome() == proto::SweepCaseResult::PASSED) ++cell.passed;
  }
  return map;
}

std::optional<std::string> SweepMapSvg(const LoadedSweep& sweep,
                                       const std::vector<proto::SweepCaseResult>& results) {
  const std::optional<GridMap> map = SweepPassMap(sweep, results);
  if (!map) return std::nullopt;
  return RenderGridMapSvg(*map);
}

}  // namespace hilrig::host
