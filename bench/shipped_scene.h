// A shipped scenario from scenarios/, resolved and set up (film field, DUT calibration) the way
// `hilrig run` does it, for the benchmarks that step whole scenes; setup failures abort, since a
// benchmark of a scene that does not load measures nothing.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "host/setup/scene_setup.h"

namespace hilrig::host {

// The films of every benchmark in this process: scenes of one level share one model, as the runs
// of one `hilrig run` do.
inline FilmFieldModels& BenchFilmModels() {
  static FilmFieldModels models;
  return models;
}

// scenarios/<name>.textproto, run for `duration_s` when given, else for its own duration.
// Never fails: aborts with the loader's or the setup's message.
inline ScenarioConfig ShippedScene(const std::string& name,
                                   std::optional<double> duration_s = std::nullopt) {
  auto spec = LoadScenario(std::string(HILRIG_SOURCE_DIR) + "/scenarios/" + name + ".textproto");
  if (!spec) {
    std::fprintf(stderr, "%s\n", spec.error().message.c_str());
    std::abort();
  }
  if (duration_s) spec.value().mutable_simulation()->set_duration_s(*duration_s);
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  rig::Result<void> set_up = BuildFilmField(config, &BenchFilmModels());
  if (set_up) set_up = LoadTactileCalibration(config);
  if (!set_up) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), set_up.error().message.c_str());
    std::abort();
  }
  return config;
}

}  // namespace hilrig::host
