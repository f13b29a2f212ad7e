// A sweep for the tests of `hilrig sweep` and its parts: `duration_s` of hover over two vehicle
// masses and `seeds` seeds (2 x seeds cases), with one envelope on the altitude error whose
// `altitude_upper_m` sets how strict it is (1e-6 m fails every case). Written into a fresh
// folder as hover.textproto and sweep.textproto.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/test_files.h"

namespace hilrig::host {

inline std::filesystem::path HoverSweepFolder(
    const std::string& name, double altitude_upper_m, int seeds,
    const std::string& criteria = "criterion { min_pass_rate: 0.3 }", double duration_s = 1) {
  const std::filesystem::path dir = FreshTestDir(name);
  std::ofstream(dir / "hover.textproto")
      << "name: \"hover_sweep\"\n"
         "vehicle { initial_position_m { z: 1 } }\n"
         "simulation { duration_s: "
      << duration_s
      << " }\n"
         "envelopes { name: \"altitude\" signal: ALTITUDE_ERROR_M upper: "
      << altitude_upper_m << " }\n";
  std::ofstream(dir / "sweep.textproto")
      << "name: \"hover_mass\"\n"
         "scenario: \"hover.textproto\"\n"
         "seeds { count: "
      << seeds
      << " }\n"
         "axis { path: \"vehicle.mass_kg\" list { value: 0.5 value: 0.6 } }\n"
      << criteria << "\n";
  return dir;
}

}  // namespace hilrig::host
