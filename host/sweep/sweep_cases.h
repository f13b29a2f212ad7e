// The cases of a sweep in one fixed order, each computed from its index alone: scenario by
// scenario, then the points of the list and grid axes (the last axis varying fastest), then the
// seeds. A distribution axis adds no points; it draws its value per case from a stream seeded by
// the case's seed and the axis's path, so a case is the same wherever, whenever and in whichever
// shard it runs, and cases that share a seed share their draws across scenarios and grid points
// (common random numbers: a grid comparison is not blurred by different draws).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/sweep/sweep_spec.h"
#include "proto/scenario.pb.h"
#include "proto/sweep.pb.h"
#include "rig/result.h"

namespace hilrig::host {

struct SweepCase {
  std::uint64_t index = 0;   // 0-based, in the sweep's order
  std::size_t scenario = 0;  // into LoadedSweep::scenarios
  std::uint64_t seed = 0;
  std::vector<double> values;  // one per axis, in the spec's order
  // One per axis: the index of the case's value among the axis's points (AxisPoints), so that
  // cases at one point of the grid are found as such even when a list repeats a value; 0 for a
  // distribution axis, which has no points.
  std::vector<std::size_t> point_index;
};

// The values of a list or grid axis, in order (a grid's ends exact); empty for a distribution.
std::vector<double> AxisPoints(const proto::Axis& axis);

// Cases the spec expands to, as a double so that an absurd spec cannot overflow the count before
// validation refuses it. Scenarios without a sweep seed list count one seed each.
double CaseCountEstimate(const proto::Sweep& sweep);
std::uint64_t CaseCount(const LoadedSweep& sweep);

// A sweep's axes expanded to their points once, so that taking each of its cases in turn does not
// expand them again. Refers to the sweep, which must outlive it.
class SweepCaseSpace {
 public:
  explicit SweepCaseSpace(const LoadedSweep& sweep);

  std::uint64_t case_count() const { return case_count_; }
  // Case `index` (< case_count()). O(axes); allocates the values vector.
  SweepCase CaseAt(std::uint64_t index) const;

 private:
  const LoadedSweep* sweep_;
  std::vector<std::vector<double>> axis_points_;  // AxisPoints of each axis, in the spec's order
  std::uint64_t seed_count_ = 1;
  std::uint64_t per_scenario_ = 1;  // points x seeds
  std::uint64_t case_count_ = 0;
};

// The case's scenario: its spec with the case's seed and each axis's value set. Fails, naming the
// case and its values, when a value does not fit its field or the changed spec does not validate
// (a grid that makes a mass negative).
rig::Result<proto::Scenario> CaseScenario(const LoadedSweep& sweep, const SweepCase& sweep_case);

// "seed 3, object.mass_kg=0.25, timeline[1].grasp.force_n=2" for messages and runs.csv.
std::string CaseLabel(const LoadedSweep& sweep, const SweepCase& sweep_case);

// Why a truncated normal cannot be drawn from by redrawing (its window holds less than 1e-3 of
// the probability); nothing when it can.
std::optional<std::string> TruncatedNormalProblem(const proto::Distribution::Normal& normal);

}  // namespace hilrig::host
