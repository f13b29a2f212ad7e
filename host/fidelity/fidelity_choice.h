// The model choices a run is made with (integrator, tolerance, plant substeps, film field
// fidelity), how they are named in tables and plots, the tight reference fidelity a run is
// compared with, and how they are written into a spec. Shared by `hilrig run`'s comparison with
// its reference and by the work-precision sweep.
#pragma once

#include <optional>
#include <string>

#include "host/sensors/tactile/sensor_effect.h"
#include "proto/scenario.pb.h"

namespace hilrig::host {

struct FidelityChoice {
  proto::Integrator integrator = proto::INTEGRATOR_RK4;
  std::optional<double> integrator_tolerance;  // Dormand-Prince only; unset: the spec's own
  int plant_substeps = 1;
  std::string field_fidelity;  // "tiles:32", "map:16", "opmap:32", ...
  // A tactile forward-model effect switched off (models.tactile.<name> false); unset: the spec's.
  std::optional<SensorEffect> effect_off;

  bool operator==(const FidelityChoice&) const = default;
};

// Short names for tables and plots: "SIE", "midpoint", "RK4", "DP".
std::string IntegratorName(proto::Integrator integrator);

// The integrator with its tolerance where it has one: "RK4", "DP(1e-06)".
std::string IntegratorLabel(const FidelityChoice& fidelity);

// "RK4 x1 opmap:32", "DP(1e-10) x8 tiles:64", "RK4 x1 opmap:32 without earth_field".
std::string FidelityLabel(const FidelityChoice& fidelity);

// Dormand-Prince at 1e-10, 8 plant steps per tick, tiles:64; --quick uses tiles:16.
FidelityChoice ReferenceFidelity(bool quick);

// The scene's own choices, with the defaults the resolver fills in (RK4, 1 substep, tiles:32).
FidelityChoice SceneFidelity(const proto::Scenario& spec);

// `spec` with `fidelity` applied (integrator, tolerance, substeps, field fidelity, the effect off).
proto::Scenario WithFidelity(proto::Scenario spec, const FidelityChoice& fidelity);

// Whether `effect` is on in a spec with these tactile models: its switch if set, else its default.
bool EffectOn(const proto::Tactile& tactile, SensorEffect effect);

// `spec` cut to `duration_s`: timeline entries after it are dropped so the spec stays valid; every
// envelope stays (one whose window opens after the end is then reported as not evaluated).
proto::Scenario TruncatedTo(proto::Scenario spec, double duration_s);

}  // namespace hilrig::host
