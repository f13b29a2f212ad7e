#include "host/sensors/tactile/film_field_factory.h"

#include <charconv>

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
    std::string_view fidelity, const FieldMapTableStore* tables,
    const std::atomic<bool>* stop_requested) {
  const auto parsed = ParseFilmFidelity(fidelity);
  if (!parsed) return parsed.error();
  const FilmFidelity& level = parsed.value();
  auto tiled = std::make_shared<const TiledFilmField>(FilmGeometry{}, level.tiles_per_side);
  if (!level.field_map) return std::shared_ptr<const FilmFieldModel>(std::move(tiled));
  const FieldMapGrid grid = level.operating_volume ? OperatingVolumeMapGrid() : FieldMapGrid{};
  if (tables != nullptr) {
    if (auto table = tables->Load(level, grid)) {
      if (auto model = FieldMapFilmField::FromTable(tiled, grid, std::move(*table))) {
        return std::shared_ptr<const FilmFieldModel>(std::move(model));
      }
    }
  }
  auto map = FieldMapFilmField::TabulateUnlessStopped(std::move(tiled), grid, stop_requested);
  if (map == nullptr) {
    return rig::MakeError(rig::ErrorCode::kInterrupted, "interrupted while tabulating the " +
                                                            FilmFidelityName(level) + " field map");
  }
  if (tables != nullptr) tables->Store(level, grid, map->table());
  return std::shared_ptr<const FilmFieldModel>(std::move(map));
}

rig::Result<std::shared_ptr<const FilmFieldModel>> FilmFieldModels::Get(
    std::string_view fidelity, const std::atomic<bool>* stop_requested) {
  const auto parsed = ParseFilmFidelity(fidelity);
  if (!parsed) return parsed.error();
  const std::string name = FilmFidelityName(parsed.value());
  Level* level = nullptr;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::unique_ptr<Level>& slot = levels_[name];
    if (slot == nullptr) slot = std::make_unique<Level>();
    level = slot.get();  // levels are never erased, so the pointer outlives the lock
  }
  const std::lock_guard<std::mutex> lock(level->mutex);
  if (level->model != nullptr) return level->model;
  auto built = MakeFilmField(name, tables_, stop_requested);
  if (!built) return built.error();
  level->model = std::move(built).value();
  return level->model;
}

}  // namespace hilrig::host
