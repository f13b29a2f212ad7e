#include "dut_fw/flight_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <limits>
#include <new>
#include <vector>

// Counts heap allocations so a test can prove the control path makes none. Replacing the global
// operators affects the whole test binary; they only count and forward to malloc/free.
namespace {
int g_allocations = 0;
}  // namespace
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t align) {
  ++g_allocations;
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
// The nothrow forms too (std::stable_sort's buffer takes one): a sanitizer's own operator new
// must never meet the free() above.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new(std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  ++g_allocations;
  const std::size_t a = static_cast<std::size_t>(align);
  return std::aligned_alloc(a, (size + a - 1) / a * a);
}
// Once one of these is inlined where a test deletes what `new` made, GCC pairs that `new` with
// this free() and calls them mismatched; the operator new above took the memory from malloc.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace hilrig::dut_fw {
namespace {

constexpr double kMassKg = 0.556;
constexpr double kG = 9.81;
constexpr double kRotorLagS = 0.03;
constexpr double kArmM = 0.1;
constexpr double kKappaM = 0.016;
constexpr std::int64_t kTickNs = 1'000'000;        // control, IMU and plant at 1 kHz
constexpr std::int64_t kVioPeriodNs = 33'333'333;  // 30 Hz
constexpr std::int64_t kVioLatencyNs = 40'000'000;

// A tiny rigid-body quadrotor written from the shared conventions (not from the mixer), with
// first-order rotor lag and a ground at z = 0, integrated at 1 kHz. The IMU reads exactly the rate
// and specific force the step used, so the estimator sees a perfect sensor.
struct Plant {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d rate_rad_s = Eigen::Vector3d::Zero();
  std::array<double, 4> rotor_n = {0, 0, 0, 0};

  struct Imu {
    Eigen::Vector3d gyro_rad_s, accel_m_s2;
  };

  Imu Step(const std::array<double, 4>& command_n, const Eigen::Vector3d& external_force_n,
           double dt_s) {
    const double a = kArmM / std::sqrt(2.0);
    const double x[4] = {a, -a, a, -a};
    const double y[4] = {-a, a, a, -a};
    const double yaw_sign[4] = {-1, -1, 1, 1};
    double thrust_n = 0;
    Eigen::Vector3d torque_nm = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) {
      const double t = rotor_n[i];
      thrust_n += t;
      torque_nm += Eigen::Vector3d(y[i] * t, -x[i] * t, yaw_sign[i] * kKappaM * t);
    }
    const Eigen::Vector3d inertia(3e-3, 3e-3, 5e-3);

    Eigen::Vector3d accel =
        (orientation * Eigen::Vector3d(0, 0, thrust_n) + external_force_n) / kMassKg -
        Eigen::Vector3d(0, 0, kG);
    const bool on_ground = position_m.z() <= 0.0 && accel.z() <= 0.0 && velocity_m_s.z() <= 0.0;
    if (on_ground) {  // the ground holds the vehicle and friction stops it
      accel.setZero();
      velocity_m_s.setZero();
    }
    const Imu imu{rate_rad_s, orientation.conjugate() * (accel + Eigen::Vector3d(0, 0, kG))};
    position_m += velocity_m_s * dt_s + 0.5 * accel * dt_s * dt_s;
    velocity_m_s += accel * dt_s;
    orientation = (orientation * QuatExp<double>(rate_rad_s * dt_s)).normalized();
    const Eigen::Vector3d rate_dot =
        (torque_nm - rate_rad_s.cross(inertia.cwiseProduct(rate_rad_s))).cwiseQuotient(inertia);
    rate_rad_s += rate_dot * dt_s;
    const double k = 1.0 - std::exp(-dt_s / kRotorLagS);
    for (int i = 0; i < 4; ++i) rotor_n[i] += k * (command_n[i] - rotor_n[i]);
    return imu;
  }
};

struct Sample {
  double time_s;
  Eigen::Vector3d position_m;
  Eigen::Vector3d desired_m;
  bool armed;
};

// Closed loop: plant + perfect IMU + VIO (30 Hz, 40 ms late) + controller in scalar S. The
// external force acts on the plant and is measured exactly by the controller.
template <typename S>
std::vector<Sample> Fly(const Reference<S>& reference, double duration_s,
                        const Eigen::Vector3d& external_force_n = Eigen::Vector3d::Zero(),
                        double force_from_s = 0.0, bool load_feedforward = true) {
  FlightControllerParams<S> params = DefaultFlightControllerParams<S>(S(kMassKg));
  params.load_feedforward = load_feedforward;
  const FlightController<S> controller(params);
  FlightControllerState<S> state;
  Plant plant;
  struct Pose {
    std::int64_t capture_ns;
    Eigen::Vector3d position_m;
    Eigen::Quaterniond orientation;
  };
  std::deque<Pose> pending;
  std::int64_t next_capture_ns = 0;
  std::array<double, 4> command_n = {0, 0, 0, 0};
  std::vector<Sample> trace;

  const std::int64_t end_ns = std::int64_t(duration_s * 1e9);
  for (std::int64_t t = 0; t < end_ns; t += kTickNs) {
    if (t >= next_capture_ns) {
      pending.push_back({t, plant.position_m, plant.orientation});
      next_capture_ns += kVioPeriodNs;
    }
    const Eigen::Vector3d force_n =
        double(t) * 1e-9 >= force_from_s ? external_force_n : Eigen::Vector3d::Zero();
    const Plant::Imu imu = plant.Step(command_n, force_n, 1e-3);
    const std::int64_t now = t + kTickNs;
    controller.OnImu(state, imu.gyro_rad_s.cast<S>(), imu.accel_m_s2.cast<S>(), now);
    while (!pending.empty() && pending.front().capture_ns + kVioLatencyNs <= now) {
      controller.OnVio(state, pending.front().position_m.template cast<S>(),
                       pending.front().orientation.template cast<S>(), pending.front().capture_ns);
      pending.pop_front();
    }
    const FlightControllerOutput<S> out =
        controller.Step(state, reference, force_n.cast<S>(), S(1e-3));
    for (int i = 0; i < 4; ++i) command_n[i] = double(out.rotor_thrust_n[i]);
    trace.push_back({double(now) * 1e-9, plant.position_m,
                     out.desired.position_m.template cast<double>(), out.armed});
  }
  return trace;
}

// At rest at (0, 0, 1): an IMU sample, a VIO pose and a second IMU sample one tick later, after
// which the estimator knows where it is and the controller arms.
template <typename S>
void SettleAtHover(const FlightController<S>& controller, FlightControllerState<S>& state) {
  controller.OnImu(state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)), 0);
  controller.OnVio(state, Vec3<S>(S(0), S(0), S(1)), Quat<S>::Identity(), 0);
  controller.OnImu(state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)), kTickNs);
}

template <typename S>
Reference<S> HoverAt(double x, double y, double z) {
  Reference<S> r;
  r.position_m = Vec3<S>(S(x), S(y), S(z));
  return r;
}

template <typename S>
class FlightControllerTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(FlightControllerTest, Scalars);

TYPED_TEST(FlightControllerTest, DisarmedUntilTheEstimatorIsInitialized) {
  using S = TypeParam;
  const FlightController<S> controller(DefaultFlightControllerParams<S>(S(kMassKg)));
  FlightControllerState<S> state;
  controller.OnImu(state, Vec3<S>::Zero(), Vec3<S>(S(0), S(0), S(kG)), kTickNs);

  const FlightControllerOutput<S> out =
      controller.Step(state, HoverAt<S>(0, 0, 1), Vec3<S>::Zero(), S(1e-3));

  EXPECT_FALSE(out.armed);
  for (S t : out.rotor_thrust_n) EXPECT_EQ(t, S(0));
}

TYPED_TEST(FlightControllerTest, InPlaceStepOverwritesAStaleArmedOutput) {
  using S = TypeParam;
  const FlightController<S> controller(DefaultFlightControllerParams<S>(S(kMassKg)));
  FlightControllerState<S> armed_state;
  SettleAtHover(controller, armed_state);
  FlightControllerOutput<S> out;
  controller.Step(armed_state, HoverAt<S>(0, 0, 1), Vec3<S>::Zero(), S(1e-3), out);
  ASSERT_TRUE(out.armed);
  FlightControllerState<S> fresh_state;

  controller.Step(fresh_state, HoverAt<S>(0, 0, 2), Vec3<S>::Zero(), S(1e-3), out);

  EXPECT_FALSE(out.armed);
  for (S t : out.rotor_thrust_n) EXPECT_EQ(t, S(0));
  EXPECT_EQ(out.collective_thrust_n, S(0));
  EXPECT_EQ(out.desired.position_m.z(), S(2));
}

TYPED_TEST(FlightControllerTest, HoverStepSplitsTheWeightEqually) {
  using S = TypeParam;
  const FlightController<S> controller(DefaultFlightControllerParams<S>(S(kMassKg)));
  FlightControllerState<S> state;
  SettleAtHover(controller, state);

  const FlightControllerOutput<S> out =
      controller.Step(state, HoverAt<S>(0, 0, 1), Vec3<S>::Zero(), S(1e-3));

  EXPECT_TRUE(out.armed);
  for (S t : out.rotor_thrust_n) EXPECT_NEAR(t, kMassKg * kG / 4.0, 1e-5);
  EXPECT_NEAR(out.torque_body_nm.norm(), 0.0, 1e-6);
}

TYPED_TEST(FlightControllerTest, YawChangeBetweenStepsReachesTheDesiredAttitude) {
  using S = TypeParam;
  const FlightController<S> controller(DefaultFlightControllerParams<S>(S(kMassKg)));
  FlightControllerState<S> state;
  SettleAtHover(controller, state);
  Reference<S> reference = HoverAt<S>(0, 0, 1);
  controller.Step(state, reference, Vec3<S>::Zero(), S(1e-3));
  reference.yaw_rad = S(0.8);

  const FlightControllerOutput<S> out = controller.Step(state, reference, Vec3<S>::Zero(), S(1e-3));

  // At the hover point the thrust is vertical: the desired attitude is the yaw alone.
  EXPECT_NEAR(out.attitude_desired.w(), std::cos(0.4), 1e-5);
  EXPECT_NEAR(out.attitude_desired.z(), std::sin(0.4), 1e-5);
}

TYPED_TEST(FlightControllerTest, ControlPathDoesNotAllocate) {
  using S = TypeParam;
  const FlightController<S> controller(DefaultFlightControllerParams<S>(S(kMassKg)));
  FlightControllerState<S> state;
  const Vec3<S> gravity(S(0), S(0), S(kG));

  const int before = g_allocations;
  controller.OnImu(state, Vec3<S>::Zero(), gravity, 0);
  controller.OnVio(state, Vec3<S>(S(0), S(0), S(1)), Quat<S>::Identity(), 0);
  S sum = 0;
  for (int i = 1; i <= 100; ++i) {
    controller.OnImu(state, Vec3<S>(S(0.01), S(0), S(0)), gravity, i * kTickNs);
    if (i % 33 == 0) {
      controller.OnVio(state, Vec3<S>(S(0), S(0), S(1)), Quat<S>::Identity(), (i - 20) * kTickNs);
    }
    sum += controller.Step(state, HoverAt<S>(0.1, 0, 1), Vec3<S>(S(0.2), S(0), S(0)), S(1e-3))
               .rotor_thrust_n[0];
  }
  const int after = g_allocations;

  EXPECT_EQ(after, before);
  EXPECT_GT(sum, S(0));
}

TYPED_TEST(FlightControllerTest, TakesOffToOneMetreAndHolds) {
  using S = TypeParam;

  const std::vector<Sample> trace = Fly<S>(HoverAt<S>(0, 0, 1), 10.0);

  double max_z = 0, max_error_late = 0;
  for (const Sample& s : trace) {
    max_z = std::max(max_z, s.position_m.z());
    if (s.time_s >= 5.0) {
      max_error_late = std::max(max_error_late, (s.position_m - Eigen::Vector3d(0, 0, 1)).norm());
    }
  }
  EXPECT_GT(trace[2000].position_m.z(), 0.9);  // airborne and near the target after 2 s
  EXPECT_LT(max_z, 1.05);                      // no large overshoot
  EXPECT_LT(max_error_late, 0.02);
  EXPECT_LT(max_error_late, 1e-3);  // in fact it holds to a millimetre
}

TYPED_TEST(FlightControllerTest, ExternalForceIsAbsorbedByTheAdmittance) {
  using S = TypeParam;
  const Eigen::Vector3d push_n(0.3, 0.0, 0.0);

  const std::vector<Sample> trace = Fly<S>(HoverAt<S>(0, 0, 1), 12.0, push_n, 4.0);

  // Desired moves by f/K; the thrust cancels the measured push, so the PD has no static error
  // and the vehicle sits on the desired position.
  const Sample& last = trace.back();
  EXPECT_NEAR(last.desired_m.x(), 0.3 / 36.0, 1e-4);
  EXPECT_NEAR(last.position_m.x(), 0.3 / 36.0, 1e-3);
  EXPECT_NEAR(last.position_m.z(), 1.0, 2e-3);
}

// The weight of a held 180 g bottle, as the pads measure it: the contacts pull the vehicle down.
const Eigen::Vector3d kBottleForceN(0.0, 0.0, -1.77);

TYPED_TEST(FlightControllerTest, HeldLoadSagsOnlyByTheAdmittanceOffset) {
  using S = TypeParam;

  const std::vector<Sample> trace = Fly<S>(HoverAt<S>(0, 0, 1), 12.0, kBottleForceN, 4.0);

  // z admittance K = 100 N/m: desired drops by f/K; the fed-forward thrust carries the load.
  const Sample& last = trace.back();
  EXPECT_NEAR(last.desired_m.z(), 1.0 - 1.77 / 100.0, 1e-4);
  EXPECT_NEAR(last.position_m.z(), 1.0 - 1.77 / 100.0, 1e-3);
}

TYPED_TEST(FlightControllerTest, WithoutLoadFeedForwardThePdSagsUnderTheLoad) {
  using S = TypeParam;

  const std::vector<Sample> trace =
      Fly<S>(HoverAt<S>(0, 0, 1), 12.0, kBottleForceN, 4.0, /*load_feedforward=*/false);

  // The admittance still gives f/K; the PD (no integrator) adds f/(m kp_z), 0.35 m.
  const Sample& last = trace.back();
  EXPECT_NEAR(last.desired_m.z(), 1.0 - 1.77 / 100.0, 1e-4);
  EXPECT_NEAR(last.position_m.z(), 1.0 - 1.77 / 100.0 - 1.77 / (kMassKg * 9.0), 2e-3);
}

// One armed step hovering level at (0, 0, 1), with `force_n` measured.
template <typename S>
FlightControllerOutput<S> HoverStep(const FlightControllerParams<S>& params, const Vec3<S>& force_n,
                                    FlightControllerState<S>& state) {
  const FlightController<S> controller(params);
  SettleAtHover(controller, state);
  return controller.Step(state, HoverAt<S>(0, 0, 1), force_n, S(1e-3));
}

TYPED_TEST(FlightControllerTest, LoadFeedForwardSwitchRemovesExactlyTheMeasuredLoad) {
  using S = TypeParam;
  const FlightControllerParams<S> with = DefaultFlightControllerParams<S>(S(kMassKg));
  FlightControllerParams<S> without = with;
  without.load_feedforward = false;
  const Vec3<S> force_n = kBottleForceN.cast<S>();
  FlightControllerState<S> state_with, state_without;

  const FlightControllerOutput<S> on = HoverStep<S>(with, force_n, state_with);
  const FlightControllerOutput<S> off = HoverStep<S>(without, force_n, state_without);

  // Same admittance step in both (it sees the force either way); level, so collective = F_z.
  EXPECT_EQ(state_with.admittance.offset_m, state_without.admittance.offset_m);
  EXPECT_NEAR(on.collective_thrust_n - off.collective_thrust_n, 1.77, 1e-5);
}

TYPED_TEST(FlightControllerTest, NonFiniteForceReachesNeitherLoop) {
  using S = TypeParam;
  const FlightControllerParams<S> params = DefaultFlightControllerParams<S>(S(kMassKg));
  const Vec3<S> nan_n(S(0), S(0), std::numeric_limits<S>::quiet_NaN());
  FlightControllerState<S> state_nan, state_zero;

  const FlightControllerOutput<S> bad = HoverStep<S>(params, nan_n, state_nan);
  const FlightControllerOutput<S> zero = HoverStep<S>(params, Vec3<S>::Zero(), state_zero);

  EXPECT_EQ(bad.collective_thrust_n, zero.collective_thrust_n);
  EXPECT_EQ(bad.rotor_thrust_n, zero.rotor_thrust_n);
  EXPECT_EQ(state_nan.admittance.offset_m, Vec3<S>::Zero());
  EXPECT_EQ(state_nan.admittance.rejected_inputs, 1u);
}

TEST(FlightControllerPrecision, FloatAndDoubleAgree) {
  const std::vector<Sample> d = Fly<double>(HoverAt<double>(0, 0, 1), 6.0);
  const std::vector<Sample> f = Fly<float>(HoverAt<float>(0, 0, 1), 6.0);

  ASSERT_EQ(d.size(), f.size());
  double max_diff = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    max_diff = std::max(max_diff, (d[i].position_m - f[i].position_m).norm());
  }
  EXPECT_LT(max_diff, 1e-4);
}

}  // namespace
}  // namespace hilrig::dut_fw
