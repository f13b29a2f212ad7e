#include "host/runner/runner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "host/checks/envelope_check.h"
#include "host/dut/in_process_dut.h"
#include "host/report/stop_reason.h"
#include "host/runner/command_exchange.h"
#include "host/runner/dut_faults.h"
#include "host/runner/gripper_scene.h"
#include "host/runner/model_list.h"
#include "host/runner/navigation_devices.h"
#include "host/runner/realtime_pacer.h"
#include "host/runner/run_statistics.h"
#include "host/runner/scene_devices.h"
#include "host/runner/timing_checks.h"
#include "host/scenario/timeline_schedule.h"
#include "host/trace/log_epoch.h"
#include "host/trace/trace_csv.h"
#include "rig/candump_log.h"
#include "rig/check.h"
#include "rig/emulated_bus.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr std::int64_t kProgressPeriodNs = 5'000'000'000;
constexpr std::uint64_t kWallClockPollTicks = 4096;

Eigen::Vector3d RollPitchYawDeg(const Eigen::Quaterniond& q) {
  const double roll =
      std::atan2(2 * (q.w() * q.x() + q.y() * q.z()), 1 - 2 * (q.x() * q.x() + q.y() * q.y()));
  const double pitch = std::asin(std::clamp(2 * (q.w() * q.y() - q.z() * q.x()), -1.0, 1.0));
  const double yaw =
      std::atan2(2 * (q.w() * q.z() + q.x() * q.y()), 1 - 2 * (q.y() * q.y() + q.z() * q.z()));
  return Eigen::Vector3d(roll, pitch, yaw) * kRadToDeg;
}

double TiltDeg(const Eigen::Quaterniond& q) {
  const double body_z_up = (q * Eigen::Vector3d::UnitZ()).z();
  return std::acos(std::clamp(body_z_up, -1.0, 1.0)) * kRadToDeg;
}

// The pads' forces the devices see without a gripper.
const std::array<Eigen::Vector3d, kGripperPadCount> kNoPadForce = ZeroPadVectors();

rig::EmulatedBusConfig BusConfigFor(const ScenarioConfig& config) {
  rig::EmulatedBusConfig bus;
  bus.nominal_bitrate_bps = std::llround(config.can_bitrate_bps);
  bus.data_bitrate_bps = bus.nominal_bitrate_bps;
  return bus;
}

using rig::SecondsFromNs;

}  // namespace

// Every piece of run state lives here; Tick() steps it.
class ScenarioRunner::Impl {
 public:
  Impl(const ScenarioConfig& config, const RunSinks& sinks, const RunControl& control);
  ~Impl() { StopDut(); }
  bool Tick();
  proto::Report Finish();
  std::uint64_t TimelineEntriesStepped() const;

 private:
  void StartDut();
  void StopDut();
  bool Step();
  bool TakeArrivedCommand();
  // The held command and the buffer the next one is written into; applying swaps the two.
  const ActuatorMessage& command() const { return *held_; }
  ActuatorMessage& incoming() { return *incoming_; }
  bool ApplyIncoming();
  bool ControlStep(std::uint64_t control_tick, std::int64_t now_ns);
  void StepPlant(std::int64_t now_ns);
  bool PlantFinite() const;
  // Whether the integrator resolves the vehicle's spin at this step (see kMaxRotationPerStepRad);
  // keeps the run's largest rotation per step for the report.
  bool SpinResolved();
  void FillGraspTrace(TraceSample& sample) const;
  bool RecordTrace(std::int64_t now_ns);
  void AppendBusMetrics(std::int64_t now_ns, proto::Report& report);
  void DrainCanLog(std::int64_t now_ns);
  void ReportProgress(std::int64_t now_ns);
  void AppendTiming(proto::Report& report, bool& passed) const;
  void AppendTarget(proto::Report& report, bool& passed) const;
  void WarnOfMissingSensorBytes(const DutCounters& counters) const;

  const ScenarioConfig& config_;
  RunSinks sinks_;
  RunControl control_;
  rig::SimClock clock_;
  rig::EmulatedBus bus_;
  std::unique_ptr<rig::CanBus> can_logger_;
  std::unique_ptr<DutPort> dut_;  // null when the factory failed
  bool dut_started_ = false;
  bool dut_stopped_ = false;
  ReferenceTrajectory reference_;
  IntervalSumSchedule<Eigen::Vector3d> disturbance_force_n_;

  // The scene's devices, then RunControl::added_devices, in tick order.
  std::vector<std::unique_ptr<DeviceEmulator>> devices_;
  DeviceSchedule device_schedule_;
  QuadrotorState plant_;
  std::optional<GripperScene> gripper_;
  std::optional<PlantView> plant_view_;  // of plant_ and the gripper's pads, for the devices
  GripperCommand grasp_command_;
  double grasp_command_since_s_ = 0;
  QuadrotorStepSize plant_substep_;  // the step and its rotor-lag blend, computed once
  std::uint64_t setpoint_sequence_ = 0;
  std::array<ActuatorMessage, 2> commands_;
  ActuatorMessage* held_ = &commands_[0];
  ActuatorMessage* incoming_ = &commands_[1];
  ReferenceSample current_reference_;

  std::vector<rig::TimedCanFrame> logged_frames_;
  std::vector<EnvelopeCheck> checks_;
  std::vector<EnvelopeProgress> check_progress_;
  std::optional<TraceCsvWriter> trace_writer_;
  std::optional<rig::CandumpLogWriter> can_writer_;
  RunStatistics statistics_;
  std::optional<RealtimePacer> pacer_;         // set in real-time runs
  std::unique_ptr<CommandExchange> exchange_;  // lockstep, or real time on pacer_
  RunStop stop_;
  std::uint64_t can_frames_logged_ = 0;
  std::uint64_t non_finite_samples_ = 0;
  double max_rotation_per_step_rad_ = 0;
  std::uint64_t touchdowns_holding_object_ = 0;  // touch-downs with an object on the pads
  DutFaultTally dut_faults_;
  std::int64_t next_progress_wall_ns_ = kProgressPeriodNs;
  std::int64_t wall_start_ns_ = 0;
  std::uint64_t tick_ = 0;
  // Countdowns to the next control tick (0: this one) and trace row (1: after this tick), and
  // the control ticks taken: the schedule's moduli and quotient without a division per tick.
  std::uint64_t ticks_to_control_ = 0;
  std::uint64_t ticks_to_trace_ = 0;
  std::uint64_t control_ticks_ = 0;
  std::uint64_t total_ticks_ = 0;
  bool ended_ = false;
};

ScenarioRunner::Impl::Impl(const ScenarioConfig& config, const RunSinks& sinks,
                           const RunControl& control)
    : config_(config),
      sinks_(sinks),
      control_(control),
      bus_(BusConfigFor(config)),
      can_logger_(bus_.Connect("can-logger")),
      reference_(config.initial_reference, config.setpoints),
      disturbance_force_n_(EventSchedule(
          config.disturbances, [](const DisturbanceCommand& d) { return d.force_world_n; })),
      devices_(MakeSceneDevices(config, bus_)),
      plant_substep_(MakeQuadrotorStepSize(
          config.vehicle, SecondsFromNs(config.physics_step_ns) / config.plant_substeps)),
      statistics_(config.gripper.enabled) {
  if (control.realtime_clock != nullptr) {
    pacer_.emplace(*control.realtime_clock,
                   PacerSettings{config.physics_step_ns, config.late_threshold_ns});
  }
  exchange_ = MakeCommandExchange(pacer_ ? &*pacer_ : nullptr);
  StartDut();
  if (config.gripper.enabled) gripper_.emplace(config, config.hall_sensors.tactile);
  // A scenario starting in the air starts hovering, rotors spun up; on the ground it starts at
  // rest.
  const Eigen::Vector3d& start_m = config.initial_reference.position_m;
  plant_ = start_m.z() > 0
               ? MakeHoveringQuadrotor(config.vehicle, start_m, config.initial_reference.yaw_rad)
               : MakeRestingQuadrotor(config.vehicle, start_m.x(), start_m.y(),
                                      config.initial_reference.yaw_rad);
  plant_view_.emplace(PlantView{plant_, gripper_ ? gripper_->pad_forces() : kNoPadForce,
                                gripper_ ? &gripper_->chip_positions() : nullptr});
  // The navigation sensors after the scene's own devices, for a DUT that takes them.
  if (dut_started_ && dut_->TakesNavigationSensors()) {
    for (std::unique_ptr<DeviceEmulator>& device :
         MakeNavigationDevices(config.navigation, config.earth_field, config.seed)) {
      devices_.push_back(std::move(device));
    }
  }
  for (const std::unique_ptr<DeviceEmulator>& device : devices_) device_schedule_.Add(*device);
  for (DeviceEmulator* device : control.added_devices) device_schedule_.Add(*device);
  if (dut_started_) device_schedule_.Initialize(*plant_view_, *dut_);
  for (const EnvelopeSpec& envelope : config.envelopes) checks_.emplace_back(envelope);
  check_progress_.resize(checks_.size());
  if (sinks.trace_csv != nullptr) trace_writer_.emplace(*sinks.trace_csv);
  if (sinks.can_log != nullptr)
    can_writer_.emplace(*sinks.can_log, "can0", rig::DirectionMark::kRxTx);
  logged_frames_.reserve(64);
  ticks_to_trace_ = static_cast<std::uint64_t>(config.trace_every_ticks);
  total_ticks_ = TotalTicks(config);
  wall_start_ns_ = control.wall_clock->NowNs();
  next_progress_wall_ns_ = wall_start_ns_ + kProgressPeriodNs;
  ended_ = ended_ || total_ticks_ == 0;
}

// A DUT that does not start ends the run before its first tick; it is never sent a message or
// stepped, and is stopped like any other.
void ScenarioRunner::Impl::StartDut() {
  rig::Result<void> started;
  std::unique_ptr<rig::CanBus> dut_bus = bus_.Connect("dut");
  if (control_.dut_traffic != nullptr) {
    dut_bus = std::make_unique<RecordingCanBus>(std::move(dut_bus), *control_.dut_traffic);
  }
  if (auto made = MakeDut(control_.dut_factory, config_, std::move(dut_bus))) {
    dut_ = std::move(made).value();
  } else {
    started = made.error();
  }
  if (dut_ && control_.dut_traffic != nullptr) {
    // Wall times for a real-time run's exchanges; a lockstep run's mean nothing to the DUT.
    const rig::Clock* wall_clock =
        control_.realtime_clock != nullptr ? control_.wall_clock : nullptr;
    dut_ = std::make_unique<RecordingDutPort>(std::move(dut_), *control_.dut_traffic, wall_clock);
  }
  if (dut_) {
    dut_->SetRunFolder(control_.run_folder);
    started = dut_->Start();
  }
  if (started) {
    dut_started_ = true;
    return;
  }
  stop_ = StopForDutError(started.error(), StopReason::kDutFailedToStart);
  ended_ = true;
}

void ScenarioRunner::Impl::StopDut() {
  if (dut_ == nullptr || dut_stopped_) return;
  dut_stopped_ = true;
  dut_->Stop();
}

bool ScenarioRunner::Impl::ControlStep(std::uint64_t control_tick, std::int64_t now_ns) {
  current_reference_ = reference_.Evaluate(SecondsFromNs(now_ns));
  if (gripper_) {
    const GripperCommand grasp = gripper_->CommandAt(SecondsFromNs(now_ns));
    if (grasp.regulate != grasp_command_.regulate || grasp.force_n != grasp_command_.force_n) {
      grasp_command_since_s_ = SecondsFromNs(now_ns);
    }
    grasp_command_ = grasp;
  }
  // Built in place: the message is not copied into the variant on every control tick.
  dut_->Send(DutInput(std::in_place_type<SetpointMessage>, LinkStamp{setpoint_sequence_++, now_ns},
                      current_reference_.position_m, current_reference_.velocity_m_s,
                      current_reference_.acceleration_m_s2, current_reference_.yaw_rad,
                      grasp_command_.regulate, grasp_command_.force_n,
                      grasp_command_.reference_angle_rad));
  auto answered = exchange_->Ask(*dut_, control_tick, now_ns, incoming());
  if (!answered) {
    stop_ = StopForDutError(answered.error(), StopReason::kDutFailed);
    return false;
  }
  return !answered.value() || ApplyIncoming();
}

// A command the plant cannot take is refused and counted (dut_faults.h); false when the scene
// stops the run at such a fault.
bool ScenarioRunner::Impl::ApplyIncoming() {
  ActuatorMessage& command = incoming();
  if (std::optional<std::string> field = NonFiniteCommandField(command)) {
    const double now_s = SecondsFromNs(clock_.NowNs());
    if (config_.dut_fault_stops_run) {
      stop_ = {StopReason::kDutFault,
               "non-finite command " + *field + " at " + rig::NumberText(now_s) + " s"};
    }
    dut_faults_.Count(std::move(*field), now_s);
    return !config_.dut_fault_stops_run;
  }
  if (!command.armed) command.rotor_thrust_n.fill(0.0);
  std::swap(held_, incoming_);
  return true;
}

// At a control tick, before the devices and the request: the command that arrived since the
// last one (real time; lockstep has none), applied now.
bool ScenarioRunner::Impl::TakeArrivedCommand() {
  auto arrived = exchange_->Arrived(*dut_, incoming());
  if (!arrived) {
    stop_ = StopForDutError(arrived.error(), StopReason::kDutFailed);
    return false;
  }
  return !arrived.value() || ApplyIncoming();
}

// The gripper moves first, against the vehicle as it is, so that the vehicle step carries the held
// object's mass and the contacts' force of this tick.
void ScenarioRunner::Impl::StepPlant(std::int64_t now_ns) {
  const double dt_s = SecondsFromNs(config_.physics_step_ns);
  Eigen::Vector3d force_world_n = disturbance_force_n_.At(SecondsFromNs(now_ns));
  Payload payload;
  if (gripper_) {
    gripper_->Step(SecondsFromNs(now_ns), command().servo_angle_rad, plant_, dt_s);
    force_world_n += gripper_->forces().force_on_vehicle_world_n;
    payload = gripper_->payload();
  }
  for (int i = 0; i < config_.plant_substeps; ++i) {
    AdvanceQuadrotor(config_.vehicle, plant_, command().rotor_thrust_n, force_world_n,
                     plant_substep_, payload);
    if (plant_.ground_contact && gripper_ && gripper_->holds_object()) ++touchdowns_holding_object_;
  }
}

bool ScenarioRunner::Impl::SpinResolved() {
  const double substep_s = SecondsFromNs(config_.physics_step_ns) / config_.plant_substeps;
  const double rate_rad_s = plant_.body.angular_velocity_rad_s.norm();
  const double rotation_rad = rate_rad_s * substep_s;
  max_rotation_per_step_rad_ = std::max(max_rotation_per_step_rad_, rotation_rad);
  const std::optional<double> limit_rad = MaxRotationPerStepRad(config_.vehicle.integrator);
  if (!limit_rad || rotation_rad <= *limit_rad) return true;
  stop_ = {StopReason::kNumericalInstability,
           "the vehicle turns " + rig::NumberText(rotation_rad) + " rad per plant step at " +
               rig::NumberText(SecondsFromNs(clock_.NowNs())) + " s (" +
               rig::NumberText(rate_rad_s) + " rad/s), past the " + rig::NumberText(*limit_rad) +
               " rad a fixed-step integrator resolves: raise simulation.plant_substeps or use "
               "INTEGRATOR_DORMAND_PRINCE"};
  return false;
}

bool ScenarioRunner::Impl::PlantFinite() const {
  const RigidBodyState& body = plant_.body;
  return body.position_m.allFinite() && body.velocity_m_s.allFinite() &&
         body.orientation.coeffs().allFinite() && body.angular_velocity_rad_s.allFinite();
}

void ScenarioRunner::Impl::FillGraspTrace(TraceSample& sample) const {
  const GraspForces& forces = gripper_->forces();
  sample.grasp_force_n = forces.grasp_force_n;
  sample.grasp_force_estimate_n = command().grasp_force_estimate_n;
  sample.grasp_force_setpoint_n = grasp_command_.regulate ? grasp_command_.force_n : 0.0;
  sample.grasp_settled_s = sample.time_s - grasp_command_since_s_;
  sample.load_n = -gripper_->ContactForceWorld(plant_.body.orientation).z();
  sample.load_estimate_n = -command().external_force_world_n.z();
  sample.object_mass_kg = gripper_->grasp().object_mass_kg;
  sample.servo_angle_rad = gripper_->servo().angle_rad;
  sample.servo_command_rad = command().servo_angle_rad;
  sample.object_damaged = gripper_->any_damaged();
  sample.object_dropped = gripper_->any_dropped();
  const GraspState& grasp = gripper_->grasp();
  const bool in_pads = grasp.mode == GraspMode::kHeld || grasp.mode == GraspMode::kSliding;
  sample.object_held = in_pads;
  sample.slip_speed_m_s = in_pads ? std::abs(grasp.slip_rate_m_s) : 0.0;
}

bool ScenarioRunner::Impl::RecordTrace(std::int64_t now_ns) {
  TraceSample sample;
  sample.time_s = SecondsFromNs(now_ns);
  sample.position_m = plant_.body.position_m;
  sample.ground_force_n = plant_.ground_normal_force_n;
  sample.reference_m = reference_.Evaluate(sample.time_s).position_m;
  sample.velocity_m_s = plant_.body.velocity_m_s;
  sample.roll_pitch_yaw_deg = RollPitchYawDeg(plant_.body.orientation);
  sample.tilt_deg = TiltDeg(plant_.body.orientation);
  sample.rotor_thrust_n = plant_.rotors.thrust_n;
  sample.estimated_position_m = command().estimated_position_m;
  const auto& applied_n = gripper_ ? gripper_->pad_forces() : kNoPadForce;
  static_assert(kTracePadCount == kTactileSensorCount);
  for (int i = 0; i < kTactileSensorCount; ++i) {
    sample.pad_force_n[i] = applied_n[i].norm();
    sample.pad_force_estimate_n[i] = command().tactile_force_sensor_n[i].norm();
    sample.pad_force_error_n[i] = (command().tactile_force_sensor_n[i] - applied_n[i]).norm();
    sample.tactile_force_max_n =
        std::max(sample.tactile_force_max_n, sample.pad_force_estimate_n[i]);
    sample.tactile_force_error_max_n =
        std::max(sample.tactile_force_error_max_n, sample.pad_force_error_n[i]);
  }
  if (gripper_) FillGraspTrace(sample);
  if (!AllSignalsFinite(sample)) ++non_finite_samples_;
  statistics_.Add(sample);
  if (trace_writer_) trace_writer_->Write(sample);
  if (sinks_.trace_sample) sinks_.trace_sample(sample);
  bool abort = false;
  for (std::size_t i = 0; i < checks_.size(); ++i) {
    if (checks_[i].Observe(sample, check_progress_[i]) && checks_[i].spec().abort_on_violation) {
      stop_ = {StopReason::kAborted, checks_[i].spec().name};
      abort = true;
    }
  }
  return abort;
}

void ScenarioRunner::Impl::DrainCanLog(std::int64_t now_ns) {
  logged_frames_.clear();
  can_logger_->Receive(now_ns, logged_frames_);
  can_frames_logged_ += logged_frames_.size();
  if (!can_writer_) return;
  // In place: the frames are the logger's own copies, cleared before the next drain.
  for (rig::TimedCanFrame& frame : logged_frames_) frame.time_ns += kRunLogEpochNs;
  can_writer_->WriteAll(logged_frames_);
}

void ScenarioRunner::Impl::ReportProgress(std::int64_t now_ns) {
  const std::int64_t wall_ns = control_.wall_clock->NowNs();
  if (wall_ns < next_progress_wall_ns_) return;
  next_progress_wall_ns_ = wall_ns + kProgressPeriodNs;
  // The files' buffers (1 MiB in `hilrig run`, 26 s of a real-time trace) go to the files every
  // few wall seconds, so a process that is killed or dies keeps all but its last seconds.
  if (sinks_.trace_csv != nullptr) sinks_.trace_csv->flush();
  if (sinks_.can_log != nullptr) sinks_.can_log->flush();
  if (sinks_.flushed) sinks_.flushed(SecondsFromNs(now_ns));
  if (sinks_.progress == nullptr) return;
  *sinks_.progress << config_.name << ": " << SecondsFromNs(now_ns) << " / " << config_.duration_s
                   << " s simulated, real-time factor "
                   << rig::FactorText(SecondsFromNs(now_ns) /
                                      std::max(1e-9, SecondsFromNs(wall_ns - wall_start_ns_)));
  if (pacer_) {
    *sinks_.progress << ", late ticks " << pacer_->late_ticks() << ", dut commands missed "
                     << pacer_->dut_commands_missed();
  }
  *sinks_.progress << std::endl;
}

bool ScenarioRunner::Impl::Tick() {
  if (ended_) return false;
  if (!pacer_) return Step();
  pacer_->BeginTick(tick_, [this] { exchange_->Collect(*dut_); });
  const bool more = Step();
  pacer_->EndTick();
  return more;
}

bool ScenarioRunner::Impl::Step() {
  const std::int64_t now_ns = clock_.NowNs();
  const bool control_tick = ticks_to_control_ == 0;
  ticks_to_control_ = control_tick ? static_cast<std::uint64_t>(config_.control_every_ticks) - 1
                                   : ticks_to_control_ - 1;
  if (control_tick && exchange_->collects() && !TakeArrivedCommand()) {
    ended_ = true;
    return false;
  }
  device_schedule_.Tick(now_ns, *plant_view_, *dut_);
  if (control_tick && !ControlStep(control_ticks_++, now_ns)) {
    ended_ = true;
    return false;
  }
  StepPlant(now_ns);
  if (!PlantFinite()) {
    // A step size or model the integrator cannot hold: say so and stop, instead of carrying NaN
    // through the trace.
    stop_ = {StopReason::kNumericalInstability, "the plant state is not finite after " +
                                                    rig::NumberText(SecondsFromNs(now_ns)) + " s"};
    ended_ = true;
    return false;
  }
  if (!SpinResolved()) {
    ended_ = true;
    return false;
  }
  clock_.AdvanceNs(config_.physics_step_ns);
  ++tick_;
  if (--ticks_to_trace_ == 0) {
    ticks_to_trace_ = static_cast<std::uint64_t>(config_.trace_every_ticks);
    DrainCanLog(clock_.NowNs());
    if (RecordTrace(clock_.NowNs())) ended_ = true;
  }
  // The stop request is looked at every tick (one relaxed load): a tick of a DUT on QEMU takes
  // milliseconds of wall time, and Ctrl-C must end the run within a second whatever the DUT. The
  // wall clock is read every tick in real time, and every few thousand ticks in lockstep (a
  // constant modulus: no division per tick).
  if (control_.stop_requested != nullptr &&
      control_.stop_requested->load(std::memory_order_relaxed)) {
    stop_ = {StopReason::kInterrupted, {}};
    ended_ = true;
  }
  if (pacer_ || tick_ % kWallClockPollTicks == 0) ReportProgress(clock_.NowNs());
  if (tick_ >= total_ticks_) ended_ = true;
  return !ended_;
}

// Bus load, and the arbitration (queueing) latency of every id on the bus: on a loaded bus the
// lowest-priority node's frames wait longest, and this is where a report shows it.
void ScenarioRunner::Impl::AppendBusMetrics(std::int64_t now_ns, proto::Report& report) {
  bus_.AdvanceTo(now_ns);
  const rig::EmulatedBusStats stats = bus_.stats();
  AddMetric(report,
            {"can_bus_load", now_ns > 0 ? stats.LoadOver(now_ns) : 0.0, rig::Unit::kFraction});
  for (const rig::IdQueueingStats& id : stats.queueing_by_id) {
    char name[64];
    std::snprintf(name, sizeof(name), "can_queueing_%s_0x%03X", "max_s", id.id);
    AddMetric(report, {name, SecondsFromNs(id.max_queueing_ns), rig::Unit::kSeconds});
    std::snprintf(name, sizeof(name), "can_queueing_%s_0x%03X", "mean_s", id.id);
    AddMetric(report, {name, SecondsFromNs(id.mean_queueing_ns()), rig::Unit::kSeconds});
  }
}

// A lockstep run has no wall-clock timing to report or grade; its timing envelopes are listed as
// not evaluated.
void ScenarioRunner::Impl::AppendTiming(proto::Report& report, bool& passed) const {
  proto::Timing timing;
  if (pacer_) {
    timing = pacer_->Figures(dut_ ? dut_->response_latencies() : std::vector<StreamLatency>());
  } else {
    timing.set_mode("lockstep");
    timing.set_ticks(tick_);
    timing.set_period_s(SecondsFromNs(config_.physics_step_ns));
  }
  for (proto::TimingCheckResult& check : GradeTiming(config_.timing, timing)) {
    passed = passed && check.passed();
    *report.add_timing_checks() = std::move(check);
  }
  *report.mutable_timing() = std::move(timing);
}

void ScenarioRunner::Impl::AppendTarget(proto::Report& report, bool& passed) const {
  const std::optional<TargetSummary> target = dut_ ? dut_->target() : std::nullopt;
  if (target) *report.mutable_target() = TargetSection(*target, ControlPeriodS(config_));
  for (proto::TimingCheckResult& check :
       GradeTarget(config_.target, target ? &report.target() : nullptr)) {
    passed = passed && check.passed();
    *report.add_target_checks() = std::move(check);
  }
}

// Lockstep promises a trace that depends on the spec alone; a board that stepped without sensor
// bytes it was sent broke that promise. The run goes on (a real line may lose bytes), but says so.
void ScenarioRunner::Impl::WarnOfMissingSensorBytes(const DutCounters& counters) const {
  if (pacer_ || counters.sensor_bytes_missing == 0 || sinks_.progress == nullptr) return;
  *sinks_.progress << config_.name << ": warning: the dut stepped without "
                   << counters.sensor_bytes_missing
                   << " sensor bytes it was sent (dut_bridge_bytes_missing); this lockstep trace "
                      "depends on the line's timing\n";
}

proto::Report ScenarioRunner::Impl::Finish() {
  ended_ = true;
  StopDut();
  DrainCanLog(clock_.NowNs());
  const std::int64_t now_ns = clock_.NowNs();
  const std::int64_t wall_ns = control_.wall_clock->NowNs() - wall_start_ns_;
  const std::uint64_t ticks = tick_;
  proto::Report report;
  report.set_scenario(config_.name);
  report.set_seed(config_.seed);
  SetStop(stop_, report);
  report.set_simulated_s(SecondsFromNs(now_ns));
  report.set_wall_s(SecondsFromNs(wall_ns));
  report.set_real_time_factor(wall_ns > 0 ? SecondsFromNs(now_ns) / SecondsFromNs(wall_ns) : 0.0);
  report.set_ticks(ticks);
  report.set_can_frames_logged(can_frames_logged_);
  bool passed = stop_.reason == StopReason::kCompleted;
  for (std::size_t i = 0; i < checks_.size(); ++i) {
    *report.add_envelopes() = checks_[i].Result(check_progress_[i]);
    passed = passed && report.envelopes().rbegin()->meets_expectation();
  }
  AppendTiming(report, passed);
  AppendTarget(report, passed);
  if (const std::optional<proto::DutFaults> faults = dut_faults_.Report()) {
    *report.mutable_dut_faults() = *faults;
    passed = false;
  }
  report.set_passed(passed);
  statistics_.AppendMetrics(report);
  const DutCounters counters = dut_ ? dut_->counters() : DutCounters();
  WarnOfMissingSensorBytes(counters);
  for (const rig::Metric& metric :
       {rig::CountMetric("dut_imu_messages", counters.imu_messages),
        rig::CountMetric("dut_vio_messages", counters.vio_messages),
        rig::CountMetric("dut_can_frames_received", counters.can_frames_received)}) {
    AddMetric(report, metric);
  }
  // The front end's counts only from a DUT that counts them: zeros from one that does not would
  // read as a clean bus.
  if (counters.front_end_counted) {
    for (const rig::Metric& metric :
         {rig::CountMetric("dut_can_frames_rejected", counters.can_frames_rejected),
          rig::CountMetric("dut_sensor_samples", counters.sensor_samples),
          rig::CountMetric("dut_sensor_samples_lost", counters.sensor_samples_lost),
          rig::CountMetric("dut_tactile_samples_flagged", counters.tactile_samples_flagged)}) {
      AddMetric(report, metric);
    }
  }
  if (dut_) {
    for (const rig::Metric& metric : dut_->link_metrics()) AddMetric(report, metric);
  }
  AppendBusMetrics(now_ns, report);
  AddMetric(report, {"ground_impacts", double(plant_.ground_impacts), rig::Unit::kCount});
  AddMetric(report, rig::CountMetric("ground_impacts_holding_object", touchdowns_holding_object_));
  AddMetric(report,
            {"ground_impact_speed_max", plant_.max_impact_speed_m_s, rig::Unit::kMetresPerSecond});
  AddMetric(report, {"ground_force_max", plant_.max_ground_normal_force_n, rig::Unit::kNewtons});
  AddMetric(report, rig::CountMetric("non_finite_trace_samples", non_finite_samples_));
  AddMetric(report, {"plant_max_rotation_per_step_deg",
                     max_rotation_per_step_rad_ * 180 / std::numbers::pi, rig::Unit::kDegrees});
  for (const DeviceEmulator* device : device_schedule_.devices()) {
    for (const rig::Metric& metric : device->metrics()) AddMetric(report, metric);
  }
  if (gripper_) {
    for (const proto::ObjectOutcome& outcome : gripper_->Outcomes())
      *report.add_objects() = outcome;
    using rig::Unit;
    AddMetric(report,
              {"grasp_elastic_energy_peak", gripper_->peak_elastic_energy_j(), Unit::kJoules});
    AddMetric(report,
              {"grasp_elastic_energy_bound", gripper_->elastic_energy_bound_j(), Unit::kJoules});
    AddMetric(report, rig::CountMetric("grasp_pad_release_ticks", gripper_->pad_release_ticks()));
    AddMetric(report, {"grasp_pad_force_peak", gripper_->peak_pad_force_n(), Unit::kNewtons});
    AddMetric(report, {"grasp_unbalanced_horizontal_force_max",
                       gripper_->unbalanced_horizontal_max_n(), Unit::kNewtons});
  }
  AppendModelList(config_, dut_ ? dut_->description() : "none (failed to start)", report);
  return report;
}

std::uint64_t ScenarioRunner::Impl::TimelineEntriesStepped() const {
  std::uint64_t stepped =
      disturbance_force_n_.pieces_stepped() + (gripper_ ? gripper_->timeline_entries_stepped() : 0);
  for (const DeviceEmulator* device : device_schedule_.devices()) {
    stepped += device->timeline_entries_stepped();
  }
  return stepped;
}

ScenarioRunner::ScenarioRunner(const ScenarioConfig& config, const RunSinks& sinks,
                               const RunControl& control)
    : impl_(std::make_unique<Impl>(config, sinks, control)) {}

ScenarioRunner::~ScenarioRunner() = default;

bool ScenarioRunner::Tick() { return impl_->Tick(); }

proto::Report ScenarioRunner::Finish() { return impl_->Finish(); }

std::uint64_t ScenarioRunner::timeline_entries_stepped() const {
  return impl_->TimelineEntriesStepped();
}

proto::Report RunScenario(const ScenarioConfig& config, const RunSinks& sinks,
                          const RunControl& control) {
  ScenarioRunner runner(config, sinks, control);
  while (runner.Tick()) {
  }
  return runner.Finish();
}

}  // namespace hilrig::host
