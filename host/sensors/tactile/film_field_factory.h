// Builds a film field model from its fidelity name, as scenarios and the CLI name it:
// "tiles:N" (N x N cuboid tiles, 1 <= N <= 128), "map:N" (a field map over the working volume
// tabulated from tiles:N; "map" alone is map:32) or "opmap:N" (a 9^3 field map over the default
// pad's operating volume, the film poses that 0-3 N normal and +-1.5 N shear reach, from tiles:N:
// tighter cells where contact scenes actually go; poses outside it fall back to tiles:N). The film
// geometry is the default FilmGeometry.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "host/sensors/tactile/field_map.h"
#include "host/sensors/tactile/film_field.h"
#include "rig/result.h"

namespace hilrig::host {

// The cheapest level whose force error stays below 1 % of the 0.05 N budget (README,
// work-precision).
inline constexpr std::string_view kDefaultFilmFidelity = "tiles:32";

struct FilmFidelity {
  bool field_map = false;
  int tiles_per_side = 0;
  bool operating_volume = false;  // the map covers the pad's operating volume (opmap)
};

// The grid of "opmap:N".
FieldMapGrid OperatingVolumeMapGrid();

// Checks a fidelity name without building anything.
rig::Result<FilmFidelity> ParseFilmFidelity(std::string_view fidelity);

// Where tabulated field maps are kept between processes (host/cache/field_map_store.h keeps them
// in files; tests use a fake). A map level asks it before tabulating and hands it what it
// tabulated. Load answers nothing for a table it does not have or cannot read; the table it
// answers is checked against the grid before use.
class FieldMapTableStore {
 public:
  virtual ~FieldMapTableStore() = default;
  virtual std::optional<std::vector<Eigen::Vector3d>> Load(const FilmFidelity& level,
                                                           const FieldMapGrid& grid) const = 0;
  virtual void Store(const FilmFidelity& level, const FieldMapGrid& grid,
                     const std::vector<Eigen::Vector3d>& table) const = 0;
};

// The canonical name of a level ("map" is "map:32").
std::string FilmFidelityName(const FilmFidelity& level);

// The model of a level, built afresh: a map level first asks `tables`, if given, for its table,
// and hands it the table it had to tabulate; tabulating (a second or more) ends with an
// "interrupted" error (code kInterrupted), nothing kept, once `stop_requested` (may be null) is
// set. Fails only on a name ParseFilmFidelity refuses, or on the stop.
rig::Result<std::shared_ptr<const FilmFieldModel>> MakeFilmField(
    std::string_view fidelity, const FieldMapTableStore* tables = nullptr,
    const std::atomic<bool>* stop_requested = nullptr);

// The film models one owner (a command, a sweep's shard, a benchmark process) has built, one per
// level, shared by every run it sets up: a scenario folder or a work-precision sweep asks for the
// same few levels run after run, and a map level takes a second or more to tabulate. The models
// are immutable and answer a pose the same whatever was asked before, so sharing one is exact.
// Safe to call from several threads: a level being built holds back only the callers asking for
// that same level, which then share its model; a build that failed or was stopped keeps nothing.
class FilmFieldModels {
 public:
  // `tables` (may be null) keeps map tables between processes; it must outlive this object.
  explicit FilmFieldModels(const FieldMapTableStore* tables = nullptr) : tables_(tables) {}
  FilmFieldModels(const FilmFieldModels&) = delete;
  FilmFieldModels& operator=(const FilmFieldModels&) = delete;

  // The level's model (MakeFilmField through the tables) the first time, the same one after it;
  // "map" and "map:32" name one level.
  rig::Result<std::shared_ptr<const FilmFieldModel>> Get(
      std::string_view fidelity, const std::atomic<bool>* stop_requested = nullptr);

 private:
  struct Level {
    std::mutex mutex;  // held while the level is built
    std::shared_ptr<const FilmFieldModel> model;
  };

  const FieldMapTableStore* tables_;
  std::mutex mutex_;  // guards levels_ only, never a build
  std::map<std::string, std::unique_ptr<Level>> levels_;
};

}  // namespace hilrig::host
