// The International Standard Atmosphere's troposphere (below 11 km): 101325 Pa and 15 °C at mean
// sea level, falling by 6.5 K per km. The rig's barometer emulates pressure with it and the
// MAVLink link states HIL_SENSOR's pressure altitude with its inverse, so both use this one
// definition. Cannot fail; O(1); nothing allocates. Outside the troposphere the formulas are
// continued, not clamped.
#pragma once

namespace hilrig::rig {

double StandardPressurePa(double altitude_m);
double StandardTemperatureC(double altitude_m);
// The altitude at which the standard atmosphere has `pressure_pa` (> 0): StandardPressurePa's
// inverse.
double StandardAltitudeM(double pressure_pa);

}  // namespace hilrig::rig
