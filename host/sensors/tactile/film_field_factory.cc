#include "host/sensors/tactile/film_field_factory.h"

#include <charconv>
#include <map>
#include <mutex>

#include "host/sensors/tactile/field_map.h"
#include "host/sensors/tactile/film_magnet.h"

namespace hilrig::host {
namespace {

rig::Result<int> ParseTiles(std::string_view text, std::string_view fidelity) {
  int tiles = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), tiles);
  if (error != std::errc() || end != text.data() + text.size() || tiles < 1 || tiles > 128) {
    return rig::MakeError("field fidelity \"" + std::string(fidelity) +
                          "\": tiles per side must be a whole number in [1, 128]");
  }
  return tiles;
}

}  // namespace

rig::Result<FilmFidelity> ParseFilmFidelity(std::string_view fidelity) {
  const bool operating_map = fidelity.starts_with("opmap:");
  const bool map = fidelity == "map" || fidelity.starts_with("map:") || operating_map;
  if (!map && !fidelity.starts_with("tiles:")) {
    return rig::MakeError("unknown field fidelity \"" + std::string(fidelity) +
                          "\" (expected tiles:N, map:N or opmap:N)");
  }
  const std::string_view count = fidelity == "map" ? "32" : fidelity.substr(fidelity.find(':') + 1);
  const auto tiles = ParseTiles(count, fidelity);
  if (!tiles) return tiles.error();
  return FilmFidelity{map, tiles.value(), operating_map};
}

FieldMapGrid OperatingVolumeMapGrid() {
  FieldMapGrid grid;
  grid.box = PadOperatingVolume(SiliconeParams{}, kPadCalibrationReachN);
  grid.nodes = Eigen::Vector3i(9, 9, 9);
  return grid;
}

std::string FilmFidelityName(const FilmFidelity& level) {
  const std::string prefix = !level.field_map         ? "tiles:"
                             : level.operating_volume ? "opmap:"
                                                      : "map:";
  return prefix + std::to_string(level.tiles_per_side);
}

rig::Result<std::shared_ptr<const FilmFieldModel>> MakeFilmField(
    std::string_view fidelity, const FieldMapTableStore* store,
    const std::atomic<bool>* stop_requested) {
  const auto parsed = ParseFilmFidelity(fidelity);
  if (!parsed) return parsed.error();
  const FilmFidelity& level = parsed.value();
  // Building a level can take a second (opmap:32 tabulates 11^3 film poses from 1 024 tiles), and
  // a scenario folder or a bench sweep asks for the same few levels run after run. The models are
  // immutable and answer a pose the same whatever was asked before, so one instance per level
  // serves every caller for the life of the process: an exact cache, never a state.
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const FilmFieldModel>> built;
  const std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<const FilmFieldModel>& model = built[FilmFidelityName(level)];
  if (model != nullptr) return model;
  auto tiled = std::make_shared<const TiledFilmField>(FilmGeometry{}, level.tiles_per_side);
  if (!level.field_map) {
    model = std::move(tiled);
    return model;
  }
  const FieldMapGrid grid = level.operating_volume ? OperatingVolumeMapGrid() : FieldMapGrid{};
  if (store != nullptr) {
    if (auto table = store->Load(level, grid)) {
      model = FieldMapFilmField::FromTable(tiled, grid, std::move(*table));
      if (model != nullptr) return model;
    }
  }
  auto map = FieldMapFilmField::TabulateUnlessStopped(std::move(tiled), grid, stop_requested);
  if (map == nullptr) {
    return rig::MakeError(rig::ErrorCode::kInterrupted, "interrupted while tabulating the " +
                                                            FilmFidelityName(level) + " field map");
  }
  if (store != nullptr) store->Store(level, grid, map->table());
  model = std::move(map);
  return model;
}

}  // namespace hilrig::host
