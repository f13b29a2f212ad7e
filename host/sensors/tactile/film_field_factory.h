// Builds a film field model from its fidelity name, as scenarios and the CLI name it:
// "tiles:N" (N x N cuboid tiles, 1 <= N <= 128) or "map:N" (a field map tabulated from tiles:N;
// "map" alone is map:32). The film geometry is the default FilmGeometry.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "host/sensors/tactile/film_field.h"
#include "rig/result.h"

namespace hilrig::host {

// The cheapest level whose force error stays below 1 % of the 0.05 N budget (README,
// work-precision).
inline constexpr std::string_view kDefaultFilmFidelity = "tiles:32";

struct FilmFidelity {
  bool field_map = false;
  int tiles_per_side = 0;
};

// Checks a fidelity name without building anything.
rig::Result<FilmFidelity> ParseFilmFidelity(std::string_view fidelity);

rig::Result<std::shared_ptr<const FilmFieldModel>> MakeFilmField(std::string_view fidelity);

}  // namespace hilrig::host
