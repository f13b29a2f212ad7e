// The MLX90393 Hall chip as the tactile and reference nodes see it: true flux density at the
// chip in, the three raw 16-bit result words out, exactly as they come off the chip's I2C/SPI
// read (RM command), plus a `saturated` status. Between the two, the chip's effects, each
// switchable so that a scenario can isolate one:
//
//   temperature drift  B' = (1 + tc_sens (T - T_ref)) B + offset_ref + tc_offset (T - T_ref)
//   noise              + N(0, sigma_axis^2), white, one draw per axis per sample
//   quantization       counts = round(B' / LSB(GAIN_SEL, RES)), half away from zero
//   saturation         counts beyond the RES output range are clipped to its rails (off: they
//                      wrap modulo 2^16 as a bare 16-bit register would); either way an axis at
//                      or beyond a rail sets `saturated`, the reader's only evidence of it
//   RES encoding       RES 0/1 two's complement; RES 2 unsigned around 32768 (+-22000 counts);
//                      RES 3 unsigned around 16384 (+-11000) (off: two's complement always)
//
// The sensitivity table, RES output ranges and the encoder are dut_fw/mlx90393.h's (LsbTesla,
// CodeRange, EncodeCode): the chip's output format is stated once, for the emulator that writes
// it and the firmware that reads it. GAIN_SEL 7 / RES 0 is the design's 0.150 / 0.242 uT per LSB.
//
// Noise: the datasheet gives the RMS noise as a function of DIG_FILT and OSR (a few tenths of a uT
// up to ~1-2 uT at the most sensitive gain); the defaults here (0.4 uT x/y, 0.65 uT z, the z/xy
// ratio being the sensitivity ratio 0.242 / 0.150) are of that order for a mid DIG_FILT / OSR
// setting and should be set from the datasheet row (or a bench measurement) of the configured
// filter. The noise is input-referred (tesla), so it does not change with GAIN_SEL.
//
// Temperature drift: temperature compensation (TCMP_EN) off, as on the nodes. The coefficients are
// assumed orders of magnitude for an uncompensated Hall front end (offset +0.1 / +0.15 uT/K x,y /
// z; sensitivity -0.03 %/K), not datasheet values; a bench characterisation should replace them.
//
// The wire format (which bytes go in which CAN frame) belongs to the node emulator; this model
// stops at the chip's result words.
#ifndef HILRIG_HOST_SENSORS_TACTILE_MLX90393_MODEL_H_
#define HILRIG_HOST_SENSORS_TACTILE_MLX90393_MODEL_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "dut_fw/mlx90393.h"
#include "host/sensors/random_stream.h"

namespace hilrig::host {

struct Mlx90393Params {
  // GAIN_SEL 0..7 (7 = most sensitive) and RES_XYZ 0..3, one RES for all axes as on the nodes.
  dut_fw::Mlx90393Setting setting{7, 0};

  bool saturation_enabled = true;  // clip at the RES window; off: wrap modulo 2^16
  bool encoding_enabled = true;    // RES 2/3 unsigned offsets; off: two's complement always

  bool noise_enabled = true;
  double noise_xy_t = 0.40e-6;  // 1 sigma per axis, input-referred
  double noise_z_t = 0.65e-6;

  bool drift_enabled = true;
  double reference_temperature_c = 25.0;
  Eigen::Vector3d offset_at_reference_t = Eigen::Vector3d::Zero();
  Eigen::Vector3d offset_tempco_t_per_k = {0.10e-6, 0.10e-6, 0.15e-6};
  double sensitivity_tempco_per_k = -0.0003;  // relative, per kelvin
};

struct Mlx90393State {
  RandomStream rng;
};

struct Mlx90393Sample {
  std::array<std::uint16_t, 3> code{};  // result words as read from the chip
  bool saturated = false;  // any axis at or beyond a rail of its RES range, or not finite
};

// One axis of quantization: field / lsb rounded half away from zero, clipped to
// [min_counts, max_counts]; `clipped` is set when it had to be clipped or was not finite (a NaN
// goes to min_counts).
struct Mlx90393AxisCounts {
  std::int32_t counts = 0;
  bool clipped = false;
};
Mlx90393AxisCounts QuantizeMlx90393Axis(double field_t, double lsb_t, std::int32_t min_counts,
                                        std::int32_t max_counts);

// What a conversion derives from the parameters alone (LSB sizes, output window, noise sigmas),
// built once per node instead of on every sample. Aborts on an invalid GAIN_SEL / RES setting.
struct Mlx90393Constants {
  Eigen::Vector3d lsb_t = Eigen::Vector3d::Zero();
  dut_fw::Mlx90393CodeRange range{};
  Eigen::Vector3d noise_sigma_t = Eigen::Vector3d::Zero();
};
Mlx90393Constants MakeMlx90393Constants(const Mlx90393Params& params);

// One conversion of all three axes at the given chip temperature; `constants` must come from
// MakeMlx90393Constants(params).
Mlx90393Sample SampleMlx90393(const Mlx90393Params& params, const Mlx90393Constants& constants,
                              Mlx90393State& state, const Eigen::Vector3d& field_sensor_t,
                              double temperature_c);
// The same for a one-off conversion.
Mlx90393Sample SampleMlx90393(const Mlx90393Params& params, Mlx90393State& state,
                              const Eigen::Vector3d& field_sensor_t, double temperature_c);

}  // namespace hilrig::host

#endif  // HILRIG_HOST_SENSORS_TACTILE_MLX90393_MODEL_H_
