// Landing while holding an object (scenarios/edges/landing_with_bottle.textproto): the vehicle,
// handed a bottle, is sent into the ground. The
// pads' forces at touch-down must come from the landing gear's deceleration, which the physics
// step resolves, not from the whole descent speed removed within one step; so they converge as
// the plant step shrinks, the bottle is not crushed by a numerical spike, and the touch-down shows
// in the trace (ground_force_n) and in the report.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "host/setup/scene_setup.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

double Metric(const proto::Report& report, const std::string& name) {
  for (const auto& metric : report.metrics()) {
    if (metric.name() == name) return metric.value();
  }
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

struct Landing {
  proto::Report report;
  std::string trace;
};

Landing LandWithSubsteps(int substeps) {
  auto spec =
      LoadScenario(test_support::SourceDir() + "/scenarios/edges/landing_with_bottle.textproto");
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  spec.value().mutable_simulation()->set_plant_substeps(substeps);
  ScenarioConfig config = ResolveScenario(spec.value(), std::nullopt);
  EXPECT_TRUE(LoadTactileCalibration(config).ok());
  std::ostringstream trace;
  const rig::SimClock wall_clock;
  Landing landing;
  landing.report = RunScenario(config, {.trace_csv = &trace}, {.wall_clock = &wall_clock});
  landing.trace = trace.str();
  return landing;
}

// The largest value of the trace's ground_force_n column.
double LargestGroundForceInTrace(const std::string& trace) {
  std::istringstream lines(trace);
  std::string line;
  std::getline(lines, line);
  std::size_t column = 0;
  std::istringstream header(line);
  for (std::string name; std::getline(header, name, ',') && name != "ground_force_n";) ++column;
  double largest = 0;
  while (std::getline(lines, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (std::size_t i = 0; i <= column; ++i) std::getline(cells, cell, ',');
    largest = std::max(largest, std::stod(cell));
  }
  return largest;
}

TEST(LandingWithObjectTest, PadForcesConvergeAsThePlantStepShrinks) {
  const Landing coarse = LandWithSubsteps(2);
  const Landing fine = LandWithSubsteps(8);
  const double coarse_peak_n = Metric(coarse.report, "grasp_pad_force_peak");
  const double fine_peak_n = Metric(fine.report, "grasp_pad_force_peak");
  EXPECT_GT(fine_peak_n, 0.3);  // the grasp itself: 3.5 N over six pads, and the bottle's weight
  EXPECT_LT(std::abs(coarse_peak_n - fine_peak_n), 0.1 * fine_peak_n);
  EXPECT_LT(
      std::abs(Metric(coarse.report, "ground_force_max") - Metric(fine.report, "ground_force_max")),
      0.1 * Metric(fine.report, "ground_force_max"));
  // No numerical spike crushes the bottle (it crushes at 8 N per contact): the pads slide over
  // it once the deceleration asks more shear of them than friction gives.
  EXPECT_LT(fine_peak_n, 8.0);
  EXPECT_EQ(fine.report.objects(0).damage(), "none");
}

TEST(LandingWithObjectTest, TouchDownShowsInTraceAndReport) {
  const Landing landing = LandWithSubsteps(2);
  EXPECT_EQ(landing.report.stop_reason(), "completed");
  EXPECT_EQ(Metric(landing.report, "ground_impacts_holding_object"), 1);
  const double impact_speed_m_s = Metric(landing.report, "ground_impact_speed_max");
  EXPECT_GT(impact_speed_m_s, 0.3);
  // The gear's push: about v (sqrt(k m) + c) for the vehicle and the bottle it carries, well above
  // their weight, and bounded by the gear rather than by one step's velocity change.
  const double ground_force_max_n = Metric(landing.report, "ground_force_max");
  const double mass_kg = 0.556 + 0.180;
  EXPECT_GT(ground_force_max_n, 2 * mass_kg * 9.81);
  EXPECT_LT(ground_force_max_n, impact_speed_m_s * (std::sqrt(1e4 * mass_kg) + 104) * 1.2);
  // The 100 Hz trace samples the touch-down (it lasts tens of milliseconds) above the weight.
  EXPECT_GT(LargestGroundForceInTrace(landing.trace), 1.2 * 0.556 * 9.81);
}

}  // namespace
}  // namespace hilrig::host
