// Every number of a spec that sets nearly every field, replaced in turn by a hostile value (NaN,
// the infinities, -1, 0, tiny, huge, 2^32): the spec is either refused with a message that names
// the field, or it runs (cut to 0.3 s) to a report with a stop reason. It keeps closed the class
// of numbers that kill a run (a trace rate of 1e-300 Hz, a VIO at 1e300 Hz: divisions by zero) or
// run as something else (a zeroing window of 1e300 s that zeroes over one sample). The tactile
// nodes are left out: each spec would need a calibration of its own (seconds each); their numbers
// are covered by the scenario validation tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <regex>
#include <sstream>
#include <string>

#include "host/runner/runner.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "rig/clock.h"

namespace hilrig::host {
namespace {

constexpr const char* kEveryField = R"(name: "every_field"
seed: 3
vehicle {
  mass_kg: 0.556
  inertia_kg_m2 { x: 0.003 y: 0.003 z: 0.005 }
  arm_length_m: 0.1
  max_thrust_per_rotor_n: 4.0
  torque_per_thrust_m: 0.016
  rotor_time_constant_s: 0.03
  linear_drag_n_s_per_m: 0.05
  initial_position_m { x: 0.01 y: 0.02 z: 0.5 }
  initial_yaw_deg: 5
}
models {
  integrator: INTEGRATOR_DORMAND_PRINCE
  integrator_tolerance: 1e-6
  imu { rate_hz: 1000 gyro_noise_density_rad_s_sqrt_hz: 0.0002 gyro_bias_sigma_rad_s: 0.001
        accel_noise_density_m_s2_sqrt_hz: 0.002 accel_bias_sigma_m_s2: 0.01 }
  vio { rate_hz: 30 latency_s: 0.03 position_noise_m: 0.003 attitude_noise_rad: 0.002 }
  gripper { stall_torque_nm: 0.25 max_rate_rad_s: 6 servo_time_constant_s: 0.03 }
}
simulation { duration_s: 6 physics_rate_hz: 1000 control_rate_hz: 500 trace_rate_hz: 100
             can_bitrate_bps: 1000000 plant_substeps: 2 }
environment { gravity_m_s2: 9.81 earth_field_world_t { x: 0 y: 2.4e-5 z: -4.16e-5 } }
object { fixture: "balloon" stiffness_scale: 1 mass_kg: 0.005 stand_height_m: 0.5 }
grasp_controller { mass: 0.01 damping: 0.5 stiffness: 0.1 }
timeline { at_s: 0.05 grasp { open: true } }
timeline { at_s: 0.1 setpoint { position_m { x: 0.01 y: 0.02 z: 0.55 } yaw_deg: 10
                                transition_s: 0.1 } }
timeline { at_s: 0.12 disturbance { force_world_n { x: 0.1 y: 0.1 z: 0.1 } duration_s: 0.05 } }
timeline { at_s: 0.15 pour { mass_kg: 0.001 duration_s: 0.1 } }
timeline { at_s: 0.2 present_object { fixture: "balloon" stiffness_scale: 1 mass_kg: 0.005
                                      stand_height_m: 0.55 } }
timeline { at_s: 0.25 remove_support {} }
envelopes { name: "a" signal: ALTITUDE_ERROR_M lower: 0 upper: 0.05 from_s: 0.01 until_s: 5
            mean_over_s: 0.1 }
timing { late_threshold_s: 0.002 loop_period_p99_max_s: 0.002 loop_period_max_s: 0.01
         late_tick_fraction_max: 0.1 dut_latency_p99_max_s: 0.005
         dut_commands_missed_fraction_max: 0.1 }
)";

constexpr std::array<const char*, 11> kHostileValues = {
    "nan", "inf", "-inf", "-1", "0", "1e-300", "1e300", "4294967296", "-0.5", "1e9", "1e-9"};

constexpr double kCutToS = 0.3;

TEST(HostileNumbersTest, EveryNumberOfASpecIsRefusedOrRunsToAReport) {
  // A field name, the colon, then a number: the spec above has no numbers anywhere else.
  const std::regex number(R"(([a-z_0-9]+):\s*(-?[0-9][0-9.e+-]*))");
  const std::string spec = kEveryField;
  int refused = 0;
  int ran = 0;
  for (auto it = std::sregex_iterator(spec.begin(), spec.end(), number);
       it != std::sregex_iterator(); ++it) {
    const std::smatch& match = *it;
    for (const char* value : kHostileValues) {
      const std::string text = spec.substr(0, match.position(2)) + value +
                               spec.substr(match.position(2) + match.length(2));
      SCOPED_TRACE(match.str(1) + " (offset " + std::to_string(match.position(1)) + ") = " + value);
      const auto parsed = ParseScenario(text, "every_field.textproto");
      if (!parsed.ok()) {
        // Located (file:line:column), whether the text format or the validation refused it; the
        // line may be another field's that the number made wrong (an at_s past a shorter run).
        EXPECT_NE(parsed.error().message.find("every_field.textproto:"), std::string::npos)
            << parsed.error().message;
        ++refused;
        continue;
      }
      ScenarioConfig config = ResolveScenario(parsed.value(), 1);
      config.duration_s = std::min(config.duration_s, kCutToS);
      std::ostringstream trace, can_log;
      const rig::SimClock wall_clock;
      const proto::Report report = RunScenario(config, {.trace_csv = &trace, .can_log = &can_log},
                                               {.wall_clock = &wall_clock});
      EXPECT_FALSE(report.stop_reason().empty());
      EXPECT_GT(report.ticks(), 0u);
      ++ran;
    }
  }
  // Both outcomes happen: the test is not passing by refusing (or by running) everything.
  EXPECT_GT(refused, 100);
  EXPECT_GT(ran, 100);
}

}  // namespace
}  // namespace hilrig::host
