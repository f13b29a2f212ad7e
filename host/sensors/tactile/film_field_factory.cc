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

rig::Result<std::shared_ptr<const FilmFieldModel>> MakeFilmField(std::string_view fidelity) {
  const auto parsed = ParseFilmFidelity(fidelity);
  if (!parsed) return parsed.error();
  auto tiled =
      std::make_shared<const TiledFilmField>(FilmGeometry{}, parsed.value().tiles_per_side);
  if (!parsed.value().field_map) return std::shared_ptr<const FilmFieldModel>(tiled);
  const FieldMapGrid grid =
      parsed.value().operating_volume ? OperatingVolumeMapGrid() : FieldMapGrid{};
  return std::shared_ptr<const FilmFieldModel>(
      std::make_shared<const FieldMapFilmField>(tiled, grid));
}

}  // namespace hilrig::host
