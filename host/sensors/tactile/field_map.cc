#include "host/sensors/tactile/field_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

#include "rig/stop_request.h"

namespace hilrig::host {
namespace {

// Catmull-Rom weights of the nodes at -1, 0, 1, 2 for a fraction t in [0, 1] of the cell [0, 1].
void CatmullRomWeights(double t, double w[4]) {
  const double t2 = t * t;
  const double t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}

}  // namespace

FilmCentreBox FilmWorkingVolume() {
  return {Eigen::Vector3d(-0.003, -0.003, -0.012), Eigen::Vector3d(0.003, 0.003, -0.008)};
}

FilmCentreBox PadOperatingVolume(const SiliconeParams& silicone,
                                 const Eigen::Vector3d& max_force_pad_n, double margin) {
  const Eigen::Vector3d reach_m = StaticDisplacement(silicone, max_force_pad_n);
  const Eigen::Vector3d rest_m = silicone.rest_pose.centre_m;
  const Eigen::Vector3d lateral_m(margin * reach_m.x(), margin * reach_m.y(), 0);
  return {rest_m - lateral_m - Eigen::Vector3d(0, 0, (margin - 1) * reach_m.z()),
          rest_m + lateral_m + Eigen::Vector3d(0, 0, margin * reach_m.z())};
}

FieldMapFilmField::FieldMapFilmField(std::shared_ptr<const FilmFieldModel> source,
                                     const FieldMapGrid& grid)
    : source_(std::move(source)), grid_(grid) {
  SetUpGrid();
  Tabulate(nullptr);
}

bool FieldMapFilmField::Tabulate(const std::atomic<bool>* stop_requested) {
  table_.resize(static_cast<size_t>(stored_.prod()));
  FilmPose pose;
  for (int k = 0; k < stored_.z(); ++k) {
    for (int j = 0; j < stored_.y(); ++j) {
      for (int i = 0; i < stored_.x(); ++i) {
        if (rig::StopRequested(stop_requested)) return false;
        pose.centre_m =
            grid_.box.min_m + spacing_m_.cwiseProduct(Eigen::Vector3d(i - 1, j - 1, k - 1));
        table_[(static_cast<size_t>(k) * stored_.y() + j) * stored_.x() + i] =
            source_->FieldAtChip(pose);
      }
    }
  }
  return true;
}

std::shared_ptr<const FieldMapFilmField> FieldMapFilmField::TabulateUnlessStopped(
    std::shared_ptr<const FilmFieldModel> source, const FieldMapGrid& grid,
    const std::atomic<bool>* stop_requested) {
  std::shared_ptr<FieldMapFilmField> map(new FieldMapFilmField(std::move(source), grid, {}));
  if (!map->Tabulate(stop_requested)) return nullptr;
  return map;
}

FieldMapFilmField::FieldMapFilmField(std::shared_ptr<const FilmFieldModel> source,
                                     const FieldMapGrid& grid, std::vector<Eigen::Vector3d> table)
    : source_(std::move(source)), grid_(grid), table_(std::move(table)) {
  SetUpGrid();
}

bool FieldMapFilmField::Usable(const FilmFieldModel* source, const FieldMapGrid& grid) {
  return source != nullptr && (grid.nodes.array() >= 2).all() &&
         (grid.box.max_m.array() > grid.box.min_m.array()).all();
}

void FieldMapFilmField::SetUpGrid() {
  if (!Usable(source_.get(), grid_)) {
    std::fprintf(stderr, "FieldMapFilmField: no source or a degenerate grid\n");
    std::abort();
  }
  spacing_m_ = (grid_.box.max_m - grid_.box.min_m)
                   .cwiseQuotient((grid_.nodes.array() - 1).matrix().cast<double>());
  stored_ = grid_.nodes.array() + 2;
}

std::size_t FieldMapFilmField::StoredNodeCount(const FieldMapGrid& grid) {
  return static_cast<std::size_t>((grid.nodes.array() + 2).prod());
}

std::shared_ptr<const FieldMapFilmField> FieldMapFilmField::FromTable(
    std::shared_ptr<const FilmFieldModel> source, const FieldMapGrid& grid,
    std::vector<Eigen::Vector3d> table) {
  if (!Usable(source.get(), grid) || !CheckTable(grid, table)) return nullptr;
  return std::shared_ptr<const FieldMapFilmField>(
      new FieldMapFilmField(std::move(source), grid, std::move(table)));
}

rig::Result<void> FieldMapFilmField::CheckTable(const FieldMapGrid& grid,
                                                const std::vector<Eigen::Vector3d>& table) {
  if (table.size() != StoredNodeCount(grid)) {
    return rig::MakeError(std::to_string(table.size()) + " nodes, the grid stores " +
                          std::to_string(StoredNodeCount(grid)));
  }
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (!table[i].allFinite())
      return rig::MakeError("node " + std::to_string(i) + " is not finite");
  }
  return {};
}

const Eigen::Vector3d& FieldMapFilmField::Node(int i, int j, int k) const {
  return table_[(static_cast<size_t>(k) * stored_.y() + j) * stored_.x() + i];
}

std::optional<Eigen::Vector3d> FieldMapFilmField::Lookup(const FilmPose& pose) const {
  // The silicone translates the film without tilting it, so nearly every pose is un-tilted. The
  // rotation is then exactly the identity, and turning by it (1 c + 0 c' + 0 c'') changes no
  // finite value: skipping it gives the same field.
  if (pose.orientation.coeffs() == Eigen::Quaterniond::Identity().coeffs()) {
    return Interpolate(pose.centre_m);
  }
  const Eigen::Matrix3d rotation = pose.orientation.normalized().toRotationMatrix();
  // The centre as seen from a chip frame turned with the film; the table is of the un-tilted film.
  const std::optional<Eigen::Vector3d> b = Interpolate(rotation.transpose() * pose.centre_m);
  if (!b) return std::nullopt;
  return rotation * *b;
}

std::optional<Eigen::Vector3d> FieldMapFilmField::Interpolate(const Eigen::Vector3d& centre) const {
  int base[3];
  double w[3][4];
  for (int a = 0; a < 3; ++a) {
    const double s = (centre[a] - grid_.box.min_m[a]) / spacing_m_[a];
    const int last_cell = grid_.nodes[a] - 2;
    // A little slack so that the grid's own end nodes, reached through rounding, count as inside.
    constexpr double kSlack = 1e-9;
    if (!(s >= -kSlack && s <= last_cell + 1 + kSlack)) return std::nullopt;
    const int cell = std::clamp(static_cast<int>(std::floor(s)), 0, last_cell);
    CatmullRomWeights(s - cell, w[a]);
    base[a] = cell;  // stored index of node cell - 1 (the stored grid starts one node early)
  }
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector3d plane = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) {
      Eigen::Vector3d row = Eigen::Vector3d::Zero();
      for (int i = 0; i < 4; ++i) row += w[0][i] * Node(base[0] + i, base[1] + j, base[2] + k);
      plane += w[1][j] * row;
    }
    b += w[2][k] * plane;
  }
  return b;
}

Eigen::Vector3d FieldMapFilmField::FieldAtChip(const FilmPose& pose) const {
  if (auto b = Lookup(pose)) return *b;
  return source_->FieldAtChip(pose);
}

double MaxRelativeError(const FilmFieldModel& a, const FilmFieldModel& b, int samples_per_axis) {
  const FilmCentreBox box = FilmWorkingVolume();
  const int n = std::max(samples_per_axis, 2);
  double worst = 0.0;
  FilmPose pose;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d f(static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1),
                                static_cast<double>(k) / (n - 1));
        pose.centre_m = box.min_m + (box.max_m - box.min_m).cwiseProduct(f);
        const Eigen::Vector3d ref = b.FieldAtChip(pose);
        worst = std::max(worst, (a.FieldAtChip(pose) - ref).norm() / ref.norm());
      }
    }
  }
  return worst;
}

}  // namespace hilrig::host
