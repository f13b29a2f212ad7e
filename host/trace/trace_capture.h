// The few trace columns a run keeps in memory, from one RunSinks::trace_sample callback, for the
// two things that read a run's trace after it. The comparison with a reference
// (host/fidelity/trace_comparison.h) matches samples one by one; `hilrig run` does so as the run
// goes, against the reference read from its cache entry, but the work-precision sweep compares
// runs it keeps whole, so CapturedTrace keeps the compared columns at the full trace rate and
// grows with the run. The plots beside the report (host/report/run_plots.h) need no more than a
// plot has pixel columns, so PlottedTrace keeps each plotted signal decimated
// (host/trace/decimated_series.h) and stays the same size however long the run.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "host/trace/decimated_series.h"
#include "host/trace/trace_sample.h"

namespace hilrig::host {

// The compared columns of one trace sample: what a reference keeps of each of its samples.
struct ComparedSample {
  double time_s = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double grasp_force_n = 0;
  double load_n = 0;
};

ComparedSample ComparedColumnsOf(const TraceSample& sample);

struct CapturedTrace {
  std::vector<double> time_s;
  std::vector<Eigen::Vector3d> position_m;
  std::vector<double> grasp_force_n;
  std::vector<double> load_n;

  std::size_t size() const { return time_s.size(); }
  void Add(const TraceSample& sample);
  void AddCompared(double time_s, const Eigen::Vector3d& position_m, double grasp_force_n,
                   double load_n);
  void AddCompared(const ComparedSample& sample) {
    AddCompared(sample.time_s, sample.position_m, sample.grasp_force_n, sample.load_n);
  }
  ComparedSample At(std::size_t i) const {
    return {time_s[i], position_m[i], grasp_force_n[i], load_n[i]};
  }
};

// The horizontal path of the vehicle and of its reference, for a top view, in bounded memory: a
// path needs x and y of the same samples, which per-signal decimation would not keep, so this
// keeps every stride-th sample and doubles the stride (dropping every other kept sample) when
// kMaxPoints are kept, plus the last sample added.
class DecimatedPath {
 public:
  static constexpr std::size_t kMaxPoints = 4096;

  struct Point {
    double x_m = 0, y_m = 0, reference_x_m = 0, reference_y_m = 0;
  };

  // Never fails; does not allocate once kMaxPoints are kept.
  void Add(const Eigen::Vector3d& position_m, const Eigen::Vector3d& reference_m);

  // The kept points in the order added, the last one added included.
  std::vector<Point> ToPoints() const;

  std::size_t stride() const { return stride_; }

 private:
  std::vector<Point> kept_;
  std::optional<Point> last_;  // the latest sample when it was not kept
  std::size_t stride_ = 1;
  std::size_t added_ = 0;
};

struct PlottedTrace {
  DecimatedSeries grasp_force_n;
  DecimatedSeries grasp_force_estimate_n;
  DecimatedSeries grasp_force_setpoint_n;
  DecimatedSeries load_n;
  DecimatedSeries load_estimate_n;
  DecimatedSeries altitude_error_m;
  DecimatedSeries horizontal_error_m;
  std::array<DecimatedSeries, 3> position_m;   // x, y, z
  std::array<DecimatedSeries, 3> reference_m;  // x, y, z
  std::array<DecimatedSeries, kTracePadCount> pad_force_n;
  std::array<DecimatedSeries, kTracePadCount> pad_force_estimate_n;
  DecimatedPath path;

  void Add(const TraceSample& sample);
};

}  // namespace hilrig::host
