#include "host/replay/replay.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hilrig::host {
namespace {

// Commands replayed for steps whose recorded command has not come yet; a real-time recording's
// command comes a few ticks after its step. Older ones are dropped past this many.
constexpr std::size_t kMaxAwaitedCommands = 4096;

double Difference(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) {
    return std::isnan(a) && std::isnan(b) ? 0.0 : std::numeric_limits<double>::infinity();
  }
  if (a == b) return 0.0;  // equal infinities too
  return std::abs(a - b);
}

double Difference(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double largest = 0;
  for (int i = 0; i < 3; ++i) largest = std::max(largest, Difference(a[i], b[i]));
  return largest;
}

double Difference(bool a, bool b) { return a == b ? 0.0 : 1.0; }

template <typename Array>
double LargestOf(const Array& a, const Array& b) {
  double largest = 0;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, Difference(a[i], b[i]));
  return largest;
}

}  // namespace

const char* DutOutputName(DutOutput output) {
  switch (output) {
    case DutOutput::kRotorThrust:
      return "rotor_thrust_n";
    case DutOutput::kArmed:
      return "armed";
    case DutOutput::kServoAngle:
      return "servo_angle_rad";
    case DutOutput::kGraspForceEstimate:
      return "grasp_force_estimate_n";
    case DutOutput::kExternalForce:
      return "external_force_world_n";
    case DutOutput::kTactileForce:
      return "tactile_force_sensor_n";
    case DutOutput::kTactileReady:
      return "tactile_ready";
    case DutOutput::kEstimatedPosition:
      return "estimated_position_m";
  }
  return "?";
}

double OutputDifference(DutOutput output, const ActuatorMessage& a, const ActuatorMessage& b) {
  switch (output) {
    case DutOutput::kRotorThrust:
      return LargestOf(a.rotor_thrust_n, b.rotor_thrust_n);
    case DutOutput::kArmed:
      return Difference(a.armed, b.armed);
    case DutOutput::kServoAngle:
      return Difference(a.servo_angle_rad, b.servo_angle_rad);
    case DutOutput::kGraspForceEstimate:
      return Difference(a.grasp_force_estimate_n, b.grasp_force_estimate_n);
    case DutOutput::kExternalForce:
      return Difference(a.external_force_world_n, b.external_force_world_n);
    case DutOutput::kTactileForce:
      return LargestOf(a.tactile_force_sensor_n, b.tactile_force_sensor_n);
    case DutOutput::kTactileReady:
      return Difference(a.tactile_ready, b.tactile_ready);
    case DutOutput::kEstimatedPosition:
      return Difference(a.estimated_position_m, b.estimated_position_m);
  }
  return 0.0;
}

const OutputComparison* ReplayOutcome::FirstParted() const {
  const OutputComparison* first = nullptr;
  for (const OutputComparison& output : outputs) {
    if (!output.first_past_tick) continue;
    if (first == nullptr || *output.first_past_tick < *first->first_past_tick) first = &output;
  }
  return first;
}

namespace {

// One replay's state: the DUT's commands awaiting their recorded ones, and the comparison so far.
class Replayer {
 public:
  Replayer(DutPort& dut, ReplayCanBus& bus, double tolerance) : dut_(dut), bus_(bus) {
    outcome_.tolerance = tolerance;
    for (int i = 0; i < kDutOutputCount; ++i) {
      OutputComparison output;
      output.output = static_cast<DutOutput>(i);
      outcome_.outputs.push_back(output);
    }
  }

  // False once the DUT has failed.
  bool Take(const RecordedEvent& event) {
    if (const auto* input = std::get_if<DutInput>(&event)) {
      ++outcome_.inputs;
      dut_.Send(*input);
    } else if (const auto* frame = std::get_if<rig::TimedCanFrame>(&event)) {
      ++outcome_.can_frames;
      bus_.Push(*frame);
    } else if (const auto* step = std::get_if<RecordedStep>(&event)) {
      return Step(*step);
    } else {
      Compare(std::get<RecordedCommand>(event));
    }
    return true;
  }

  ReplayOutcome& outcome() { return outcome_; }

 private:
  bool Step(const RecordedStep& step) {
    ++outcome_.steps;
    outcome_.replayed_to_ns = step.time_ns;
    rig::Result<ActuatorMessage> command = dut_.Step(step.tick, step.time_ns);
    if (!command) {
      outcome_.dut_failure = command.error();
      outcome_.dut_failure_tick = step.tick;
      return false;
    }
    if (awaited_.size() >= kMaxAwaitedCommands) awaited_.erase(awaited_.begin());
    awaited_[step.tick] = std::move(command).value();
    return true;
  }

  void Compare(const RecordedCommand& recorded) {
    const auto replayed = awaited_.find(recorded.tick);
    if (replayed == awaited_.end()) {
      ++outcome_.commands_unmatched;
      return;
    }
    ++outcome_.commands_compared;
    for (OutputComparison& output : outcome_.outputs) {
      const double difference = OutputDifference(output.output, replayed->second, recorded.command);
      if (difference > output.largest) {
        output.largest = difference;
        output.largest_tick = recorded.tick;
        output.largest_time_ns = recorded.time_ns;
      }
      if (difference > outcome_.tolerance && !output.first_past_tick) {
        output.first_past_tick = recorded.tick;
        output.first_past_time_ns = recorded.time_ns;
      }
    }
    awaited_.erase(awaited_.begin(), std::next(replayed));
  }

  DutPort& dut_;
  ReplayCanBus& bus_;
  std::map<std::uint64_t, ActuatorMessage> awaited_;
  ReplayOutcome outcome_;
};

}  // namespace

rig::Result<ReplayOutcome> ReplayTraffic(const mcap::McapContents& contents,
                                         const RecordedTraffic& traffic, DutPort& dut,
                                         ReplayCanBus& bus, double tolerance,
                                         const std::atomic<bool>* stop_requested) {
  Replayer replayer(dut, bus, tolerance);
  for (const mcap::McapMessage& message : contents.messages) {
    if (stop_requested != nullptr && stop_requested->load(std::memory_order_relaxed)) {
      replayer.outcome().interrupted = true;
      break;
    }
    auto event = traffic.Decode(message);
    if (!event) return event.error();
    if (event.value() && !replayer.Take(*event.value())) break;
  }
  return std::move(replayer.outcome());
}

}  // namespace hilrig::host
