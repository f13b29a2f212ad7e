// A tabulated field map: the cheap fidelity level of the film's field. It samples any
// FilmFieldModel once, on a regular grid of film-centre positions around the working volume, and
// then answers FieldAtChip with tricubic Catmull-Rom interpolation (C1, 64 table reads). The error
// against the source is measured, not assumed (MaxRelativeError; tests and the work-precision
// table in bench/film_field_bench.cc).
//
// Tilt: the grid holds only the un-tilted film. Any model of a rigid film obeys
// FieldAtChip({c, R}) = R · FieldAtChip({Rᵀc, I}) (turn the chip frame with the film), so a tilted
// pose is answered exactly from the same table as long as Rᵀc lies on the grid; every model behind
// this interface is a rigid film. Outside the grid, FieldAtChip falls back to the source model (so
// it is always right, only slower) and Lookup says so by returning nothing.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include "host/sensors/tactile/film_field.h"
#include "host/sensors/tactile/silicone_model.h"
#include "rig/result.h"

namespace hilrig::host {

// An axis-aligned box of film-centre positions in the chip frame.
struct FilmCentreBox {
  Eigen::Vector3d min_m;
  Eigen::Vector3d max_m;
};

// The design's working volume: film centre x, y in ±3 mm, z in -10 ± 2 mm.
FilmCentreBox FilmWorkingVolume();

// The film poses that pad forces up to `max_force_pad_n` (per pad axis: shear x, shear y, normal
// compression) reach on `silicone`, with `margin` on every reach: the volume a sensor is used in.
// Shear goes both ways; normal force only compresses, so below the rest pose the box keeps just
// the margin's share.
FilmCentreBox PadOperatingVolume(const SiliconeParams& silicone,
                                 const Eigen::Vector3d& max_force_pad_n, double margin = 1.2);

// The force reach the calibration jigs load a pad to (0-3 N normal, +-1.5 N shear): the
// operating volume of the "opmap" fidelity level and of the compensation fit.
inline const Eigen::Vector3d kPadCalibrationReachN(1.5, 1.5, 3.0);

struct FieldMapGrid {
  // The working volume with a 1 mm margin in every direction.
  FilmCentreBox box{Eigen::Vector3d(-0.004, -0.004, -0.013), Eigen::Vector3d(0.004, 0.004, -0.007)};
  // Nodes per axis, including both ends (>= 2). The default (0.8 mm in x, y; 0.75 mm in z) stays
  // within 3.5e-4 of a 16 x 16 tile source over the working volume and builds from it in about a
  // third of a second; 17 x 17 x 13 gets 6e-5 for three times the build
  // (bench/film_field_bench.cc).
  Eigen::Vector3i nodes = Eigen::Vector3i(11, 11, 9);
};

class FieldMapFilmField final : public FilmFieldModel {
 public:
  // Evaluates source on the grid (plus one layer of nodes outside it, for the cubic stencil).
  explicit FieldMapFilmField(std::shared_ptr<const FilmFieldModel> source,
                             const FieldMapGrid& grid = {});
  // A map from a table tabulated before (table() of a map of the same source and grid, kept in a
  // file), evaluating nothing; null when CheckTable refuses the table.
  static std::shared_ptr<const FieldMapFilmField> FromTable(
      std::shared_ptr<const FilmFieldModel> source, const FieldMapGrid& grid,
      std::vector<Eigen::Vector3d> table);
  // Whether `table` can be the table of a map on `grid`: StoredNodeCount(grid) nodes, all finite.
  // The error says which it is not.
  static rig::Result<void> CheckTable(const FieldMapGrid& grid,
                                      const std::vector<Eigen::Vector3d>& table);
  // Tabulates like the constructor, looking at `stop_requested` (may be null) before every node
  // (a node of a map from tiles:128 takes about 13 ms); null once it was set.
  static std::shared_ptr<const FieldMapFilmField> TabulateUnlessStopped(
      std::shared_ptr<const FilmFieldModel> source, const FieldMapGrid& grid,
      const std::atomic<bool>* stop_requested);
  // The nodes the grid stores (grid.nodes + 2 per axis): the size of table().
  static std::size_t StoredNodeCount(const FieldMapGrid& grid);

  // Interpolated inside the grid, the source model outside it.
  Eigen::Vector3d FieldAtChip(const FilmPose& pose) const override;

  // The interpolated field, or nothing when the (un-tilted) film centre is off the grid.
  std::optional<Eigen::Vector3d> Lookup(const FilmPose& pose) const;

  const FieldMapGrid& grid() const { return grid_; }
  // The field at every stored node, x fastest, then y, then z.
  const std::vector<Eigen::Vector3d>& table() const { return table_; }

 private:
  FieldMapFilmField(std::shared_ptr<const FilmFieldModel> source, const FieldMapGrid& grid,
                    std::vector<Eigen::Vector3d> table);
  // A source and a grid of at least 2 nodes per axis over a box of positive extent.
  static bool Usable(const FilmFieldModel* source, const FieldMapGrid& grid);
  void SetUpGrid();
  // Evaluates the source at every stored node; false, the table unfinished, once a stop is
  // requested.
  bool Tabulate(const std::atomic<bool>* stop_requested);
  const Eigen::Vector3d& Node(int i, int j, int k) const;
  // The un-tilted film's field at `centre` from the table, or nothing off the grid.
  std::optional<Eigen::Vector3d> Interpolate(const Eigen::Vector3d& centre) const;

  std::shared_ptr<const FilmFieldModel> source_;
  FieldMapGrid grid_;
  Eigen::Vector3d spacing_m_;
  Eigen::Vector3i stored_;  // grid_.nodes + 2
  std::vector<Eigen::Vector3d> table_;
};

// max |a - b| / |b| over samples_per_axis^3 un-tilted film poses spread evenly over the working
// volume (ends included): the accuracy measure of the work-precision table.
double MaxRelativeError(const FilmFieldModel& a, const FilmFieldModel& b, int samples_per_axis);

}  // namespace hilrig::host
