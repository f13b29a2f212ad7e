// One piece of emulated hardware the runner ticks on its own schedule: a sensor that talks to the
// DUT over its port (IMU, VIO) or a node on the CAN bus (the Hall sensor nodes). Like a system that
// declares its own periodic events, each device says when its next event is; the runner ticks it at
// the first physics tick at or after that time with a read-only view of the plant at that tick and
// the DUT port. A CAN-side device sends on the bus endpoint it was built with, not through the
// port. DeviceSchedule keeps the devices' next event times, so a tick with nothing due costs one
// compare.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "host/dut/dut_port.h"
#include "host/plant/gripper_frame.h"
#include "host/plant/quadrotor.h"

namespace hilrig::host {

// The plant as a device sees it at a tick: the vehicle (body state, rotors, specific force) and the
// force on each gripper pad (zero without a gripper).
struct PlantView {
  const QuadrotorState& vehicle;
  const std::array<Eigen::Vector3d, kGripperPadCount>& pad_force_n;
  // The tactile chips where the gripper frame has them now (body frame); null without a gripper.
  const std::array<Eigen::Vector3d, kGripperPadCount>* chip_position_body_m = nullptr;
};

class DeviceEmulator {
 public:
  virtual ~DeviceEmulator() = default;

  // Once, before the first tick and after the DUT started: what the device has to say from the
  // start (nothing by default). Returns the simulated time of its first event.
  virtual std::int64_t Initialize(const PlantView& plant, DutPort& dut);
  // Runs the device's events due at `now_ns` and returns the time of its next event.
  virtual std::int64_t Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) = 0;
  // Named counters for the run report.
  virtual std::vector<rig::Metric> metrics() const { return {}; }
  // Timeline entries the device has stepped over (a device that follows the scene's timeline), each
  // at most once over a run.
  virtual std::uint64_t timeline_entries_stepped() const { return 0; }
};

// The devices of a run in the order they tick within one physics tick (not owned).
class DeviceSchedule {
 public:
  void Add(DeviceEmulator& device);
  void Initialize(const PlantView& plant, DutPort& dut);
  // Ticks the devices due at `now_ns`, in the order they were added.
  void Tick(std::int64_t now_ns, const PlantView& plant, DutPort& dut) {
    if (now_ns >= earliest_event_ns_) TickDue(now_ns, plant, dut);
  }
  const std::vector<DeviceEmulator*>& devices() const { return devices_; }

 private:
  void TickDue(std::int64_t now_ns, const PlantView& plant, DutPort& dut);

  std::vector<DeviceEmulator*> devices_;
  std::vector<std::int64_t> next_event_ns_;  // devices_[i]'s next event
  std::int64_t earliest_event_ns_ = std::numeric_limits<std::int64_t>::max();
};

}  // namespace hilrig::host
