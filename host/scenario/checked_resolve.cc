#include "host/scenario/checked_resolve.h"

#include <vector>

#include "host/scenario/scenario_validation.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {

rig::Result<ScenarioConfig> ResolveChecked(const proto::Scenario& spec,
                                           const std::string& spec_directory,
                                           std::optional<std::uint64_t> seed) {
  const std::vector<FieldProblem> problems = ValidateScenario(spec);
  if (!problems.empty()) {
    return rig::MakeError(spec.name() + ": " + problems.front().field_path + ": " +
                          problems.front().message);
  }
  if (spec.models().tactile().enabled() && spec.models().tactile().has_field_fidelity()) {
    // Parsed, not built: building a field map here would tabulate it once more per run.
    if (auto film = ParseFilmFidelity(spec.models().tactile().field_fidelity()); !film) {
      return rig::MakeError(spec.name() +
                            ": models.tactile.field_fidelity: " + film.error().message);
    }
  }
  return ResolveScenario(spec, seed, spec_directory);
}

}  // namespace hilrig::host
