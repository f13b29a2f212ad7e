// A small grasp scene for the tests of field paths and sweeps: a water bottle, a setpoint entry
// and then a grasp entry in the timeline (so `timeline[1].grasp` exists and `timeline[0].grasp`
// names the wrong action), and one envelope.
#pragma once

namespace hilrig::host {

inline constexpr const char* kBottleSceneText = R"(name: "bottle"
simulation { duration_s: 2 }
vehicle { initial_position_m { z: 1 } }
models { tactile { enabled: true } }
object { fixture: "water_bottle" }
timeline { at_s: 0.5 setpoint { position_m { z: 1 } } }
timeline { at_s: 1 grasp { force_n: 3.5 } }
envelopes { name: "not_dropped" signal: OBJECT_DROPPED upper: 0 }
)";

}  // namespace hilrig::host
