#include "host/sweep/sweep_cases.h"

#include <algorithm>
#include <cmath>

#include "host/scenario/field_path.h"
#include "host/scenario/scenario_validation.h"
#include "host/sensors/random_stream.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// The least probability a truncated normal's window may hold, and the redraws allowed: with
// p >= 1e-3, 100 000 draws all missing has a chance of e^-100.
constexpr double kMinWindowProbability = 1e-3;
constexpr int kMaxRedraws = 100'000;

bool IsPointAxis(const proto::Axis& axis) {
  return axis.values_case() == proto::Axis::kList || axis.values_case() == proto::Axis::kGrid;
}

std::uint64_t SeedCount(const proto::Sweep& sweep) {
  if (sweep.seeds().list_size() > 0) return sweep.seeds().list_size();
  return sweep.seeds().has_count() ? sweep.seeds().count() : 1;
}

std::uint64_t SeedAt(const LoadedSweep& sweep, std::size_t scenario, std::uint64_t i) {
  const proto::Seeds& seeds = sweep.spec.seeds();
  if (seeds.list_size() > 0) return seeds.list(static_cast<int>(i));
  if (seeds.has_count()) return (seeds.has_first() ? seeds.first() : 1) + i;
  const proto::Scenario& spec = sweep.scenarios[scenario].spec;
  return spec.has_seed() ? spec.seed() : 1;
}

// A stream id per axis path (FNV-1a), top bit set so that no path shares a sensor's stream.
std::uint64_t PathStreamId(const std::string& path) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : path) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  return hash | (1ull << 63);
}

double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// The draw of a validated distribution; a truncated normal redraws a bounded number of times.
double Draw(const proto::Distribution& distribution, RandomStream& random) {
  switch (distribution.kind_case()) {
    case proto::Distribution::kUniform: {
      const auto& uniform = distribution.uniform();
      return uniform.low() + random.Uniform01() * (uniform.high() - uniform.low());
    }
    case proto::Distribution::kLogUniform: {
      const auto& range = distribution.log_uniform();
      const double log_low = std::log(range.low());
      return std::exp(log_low + random.Uniform01() * (std::log(range.high()) - log_low));
    }
    case proto::Distribution::kNormal: {
      const auto& normal = distribution.normal();
      double value = normal.mean();
      for (int attempt = 0; attempt < kMaxRedraws; ++attempt) {
        value = normal.mean() + normal.sigma() * random.Gaussian();
        if ((!normal.has_low() || value >= normal.low()) &&
            (!normal.has_high() || value <= normal.high())) {
          return value;
        }
      }
      return std::nan("");  // refused by SetNumberAt as not finite: the case fails, named
    }
    case proto::Distribution::KIND_NOT_SET:
      break;
  }
  return std::nan("");
}

}  // namespace

std::vector<double> AxisPoints(const proto::Axis& axis) {
  if (axis.values_case() == proto::Axis::kList) {
    return {axis.list().value().begin(), axis.list().value().end()};
  }
  if (axis.values_case() != proto::Axis::kGrid) return {};
  const proto::Grid& grid = axis.grid();
  std::vector<double> points;
  const std::uint32_t count = grid.count();
  for (std::uint32_t i = 0; i < count; ++i) {
    if (i + 1 == count && count > 1) {
      points.push_back(grid.to());
      break;
    }
    const double t = count > 1 ? double(i) / double(count - 1) : 0.0;
    points.push_back(grid.log() ? std::exp(std::log(grid.from()) +
                                           t * (std::log(grid.to()) - std::log(grid.from())))
                                : grid.from() + t * (grid.to() - grid.from()));
  }
  return points;
}

double CaseCountEstimate(const proto::Sweep& sweep) {
  double points = 1;
  for (const proto::Axis& axis : sweep.axis()) {
    if (axis.values_case() == proto::Axis::kList) points *= axis.list().value_size();
    if (axis.values_case() == proto::Axis::kGrid) points *= axis.grid().count();
  }
  return double(sweep.scenario_size()) * points * double(SeedCount(sweep));
}

std::uint64_t CaseCount(const LoadedSweep& sweep) { return SweepCaseSpace(sweep).case_count(); }

SweepCaseSpace::SweepCaseSpace(const LoadedSweep& sweep)
    : sweep_(&sweep), seed_count_(SeedCount(sweep.spec)) {
  std::uint64_t points = 1;
  for (const proto::Axis& axis : sweep.spec.axis()) {
    axis_points_.push_back(AxisPoints(axis));
    if (IsPointAxis(axis)) points *= axis_points_.back().size();
  }
  per_scenario_ = points * seed_count_;
  case_count_ = sweep.scenarios.size() * per_scenario_;
}

SweepCase SweepCaseSpace::CaseAt(std::uint64_t index) const {
  const LoadedSweep& sweep = *sweep_;
  SweepCase result;
  result.index = index;
  result.scenario = static_cast<std::size_t>(index / per_scenario_);
  std::uint64_t point = (index % per_scenario_) / seed_count_;
  result.seed = SeedAt(sweep, result.scenario, index % seed_count_);
  const int axes = sweep.spec.axis_size();
  result.values.assign(axes, 0.0);
  result.point_index.assign(axes, 0);
  // Mixed radix over the point axes, the last one varying fastest.
  for (int a = axes - 1; a >= 0; --a) {
    if (!IsPointAxis(sweep.spec.axis(a))) continue;
    const std::vector<double>& points = axis_points_[a];
    result.point_index[a] = static_cast<std::size_t>(point % points.size());
    result.values[a] = points[result.point_index[a]];
    point /= points.size();
  }
  for (int a = 0; a < axes; ++a) {
    const proto::Axis& axis = sweep.spec.axis(a);
    if (axis.values_case() != proto::Axis::kDistribution) continue;
    RandomStream random = RandomStream::FromSeed(result.seed, PathStreamId(axis.path()));
    result.values[a] = Draw(axis.distribution(), random);
  }
  return result;
}

std::string CaseLabel(const LoadedSweep& sweep, const SweepCase& sweep_case) {
  std::string label = "seed " + std::to_string(sweep_case.seed);
  for (int a = 0; a < sweep.spec.axis_size(); ++a) {
    label += ", " + sweep.spec.axis(a).path() + "=" + rig::NumberText(sweep_case.values[a]);
  }
  return label;
}

rig::Result<proto::Scenario> CaseScenario(const LoadedSweep& sweep, const SweepCase& sweep_case) {
  proto::Scenario scenario = sweep.scenarios[sweep_case.scenario].spec;
  scenario.set_seed(sweep_case.seed);
  const std::string context = "case " + std::to_string(sweep_case.index) + " (" + scenario.name() +
                              ", " + CaseLabel(sweep, sweep_case) + "): ";
  for (const proto::SweepSet& every_case : sweep.spec.set()) {
    auto set = SetNumberAt(scenario, every_case.path(), every_case.value());
    if (!set.ok()) return rig::InContext(context, set.error());
  }
  for (int a = 0; a < sweep.spec.axis_size(); ++a) {
    auto set = SetNumberAt(scenario, sweep.spec.axis(a).path(), sweep_case.values[a]);
    if (!set.ok()) return rig::InContext(context, set.error());
  }
  std::string problems;
  for (const FieldProblem& problem : ValidateScenario(scenario)) {
    problems += (problems.empty() ? "" : "; ") + problem.field_path + ": " + problem.message;
  }
  if (!problems.empty()) return rig::MakeError(context + problems);
  return scenario;
}

std::optional<std::string> TruncatedNormalProblem(const proto::Distribution::Normal& normal) {
  if (!(normal.sigma() > 0) || !std::isfinite(normal.mean())) return std::nullopt;  // said apart
  const double below =
      normal.has_low() ? NormalCdf((normal.low() - normal.mean()) / normal.sigma()) : 0.0;
  const double above =
      normal.has_high() ? NormalCdf((normal.high() - normal.mean()) / normal.sigma()) : 1.0;
  if (above - below >= kMinWindowProbability) return std::nullopt;
  return "[low, high] holds " + rig::NumberText(std::max(0.0, above - below)) +
         " of the normal's probability; it must hold at least 0.001";
}

}  // namespace hilrig::host
