#include "host/fidelity/fidelity_choice.h"

#include <google/protobuf/descriptor.h>

#include <algorithm>
#include <cstdint>

#include "host/sensors/tactile/film_field_factory.h"
#include "rig/check.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr double kReferenceTolerance = 1e-10;
// Dormand-Prince's tolerance when the spec leaves it to the resolver.
constexpr double kDefaultTolerance = 1e-6;
constexpr int kReferenceSubsteps = 8;

// The models.tactile switch of `effect`, found by the effect's name: every effect names its switch
// (sensor_effect.h), and a test holds each name to an optional bool field of the message.
const google::protobuf::FieldDescriptor& SwitchOf(SensorEffect effect) {
  const google::protobuf::FieldDescriptor* field =
      proto::Tactile::descriptor()->FindFieldByName(SensorEffectName(effect));
  HILRIG_CHECK(field != nullptr && field->type() == google::protobuf::FieldDescriptor::TYPE_BOOL &&
                   field->has_presence(),
               "a sensor effect without its models.tactile switch");
  return *field;
}

void SwitchOff(SensorEffect effect, proto::Tactile& tactile) {
  tactile.GetReflection()->SetBool(&tactile, &SwitchOf(effect), false);
}

}  // namespace

std::string IntegratorName(proto::Integrator integrator) {
  switch (integrator) {
    case proto::INTEGRATOR_SEMI_IMPLICIT_EULER:
      return "SIE";
    case proto::INTEGRATOR_MIDPOINT:
      return "midpoint";
    case proto::INTEGRATOR_DORMAND_PRINCE:
      return "DP";
    case proto::INTEGRATOR_RK4:
      return "RK4";
    default:
      break;
  }
  return "integrator" + std::to_string(static_cast<int>(integrator));
}

std::string IntegratorLabel(const FidelityChoice& fidelity) {
  std::string name = IntegratorName(fidelity.integrator);
  if (fidelity.integrator == proto::INTEGRATOR_DORMAND_PRINCE) {
    name.append("(")
        .append(rig::NumberText(fidelity.integrator_tolerance.value_or(kDefaultTolerance)))
        .append(")");
  }
  return name;
}

std::string FidelityLabel(const FidelityChoice& fidelity) {
  std::string label = IntegratorLabel(fidelity) + " x" + std::to_string(fidelity.plant_substeps) +
                      " " + fidelity.field_fidelity;
  if (fidelity.effect_off) label.append(" without ").append(SensorEffectName(*fidelity.effect_off));
  return label;
}

FidelityChoice ReferenceFidelity(bool quick) {
  return {proto::INTEGRATOR_DORMAND_PRINCE, kReferenceTolerance, kReferenceSubsteps,
          quick ? "tiles:16" : "tiles:64", std::nullopt};
}

FidelityChoice SceneFidelity(const proto::Scenario& spec) {
  FidelityChoice fidelity;
  fidelity.integrator = spec.models().integrator();
  if (spec.models().has_integrator_tolerance()) {
    fidelity.integrator_tolerance = spec.models().integrator_tolerance();
  }
  fidelity.plant_substeps = spec.simulation().has_plant_substeps()
                                ? static_cast<int>(spec.simulation().plant_substeps())
                                : 1;
  const proto::Tactile& tactile = spec.models().tactile();
  fidelity.field_fidelity =
      tactile.has_field_fidelity() ? tactile.field_fidelity() : std::string(kDefaultFilmFidelity);
  return fidelity;
}

proto::Scenario WithFidelity(proto::Scenario spec, const FidelityChoice& fidelity) {
  proto::Models& models = *spec.mutable_models();
  models.set_integrator(fidelity.integrator);
  if (fidelity.integrator_tolerance) {
    models.set_integrator_tolerance(*fidelity.integrator_tolerance);
  } else {
    models.clear_integrator_tolerance();
  }
  spec.mutable_simulation()->set_plant_substeps(
      static_cast<std::uint32_t>(std::max(fidelity.plant_substeps, 0)));
  if (!fidelity.field_fidelity.empty()) {
    models.mutable_tactile()->set_field_fidelity(fidelity.field_fidelity);
  }
  if (fidelity.effect_off) SwitchOff(*fidelity.effect_off, *models.mutable_tactile());
  return spec;
}

bool EffectOn(const proto::Tactile& tactile, SensorEffect effect) {
  const google::protobuf::FieldDescriptor& field = SwitchOf(effect);
  const google::protobuf::Reflection& reflection = *tactile.GetReflection();
  return reflection.HasField(tactile, &field) ? reflection.GetBool(tactile, &field)
                                              : OnByDefault(effect);
}

proto::Scenario TruncatedTo(proto::Scenario spec, double duration_s) {
  spec.mutable_simulation()->set_duration_s(duration_s);
  auto& timeline = *spec.mutable_timeline();
  timeline.erase(std::remove_if(timeline.begin(), timeline.end(),
                                [&](const auto& entry) { return entry.at_s() > duration_s; }),
                 timeline.end());
  // Envelopes stay: one whose window opens at or after the new end sees no sample, and its
  // report says it was not evaluated rather than leave it out of the verdict.
  return spec;
}

}  // namespace hilrig::host
