#include "host/sensors/random_stream.h"

#include <cmath>

namespace hilrig::host {
namespace {

constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

// The splitmix64 finalizer: a bijection with good avalanche.
constexpr std::uint64_t Mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

constexpr std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

// Deterministic elementary functions: plain double arithmetic only, usable in constant
// expressions (ziggurat tables) and at run time (the ziggurat's rare slow paths).
constexpr double kLn2 = 0.69314718055994530942;

// exp(x) for |x| < ~700: x = k ln2 + r with |r| <= ln2 / 2, Taylor series for exp(r).
constexpr double DetExp(double x) {
  const double kf = x / kLn2;
  const long long k = static_cast<long long>(kf < 0 ? kf - 0.5 : kf + 0.5);
  // ln2 split so that k * kLn2Hi is exact for the |k| used here.
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  const double r = (x - static_cast<double>(k) * kLn2Hi) - static_cast<double>(k) * kLn2Lo;
  // Horner form of sum r^n / n!, dividing by n as a multiply by a correctly rounded 1/n.
  constexpr std::array<double, 21> kInverse = [] {
    std::array<double, 21> inv{};
    for (int n = 1; n <= 20; ++n) inv[n] = 1.0 / n;
    return inv;
  }();
  double sum = 1.0;
  for (int n = 20; n >= 1; --n) sum = 1.0 + sum * r * kInverse[n];
  double scale = 1.0;
  for (long long i = 0; i < (k < 0 ? -k : k); ++i) scale *= 2.0;
  return k < 0 ? sum / scale : sum * scale;
}

// log(x) for finite x > 0: x = m 2^e with m in [sqrt(1/2), sqrt(2)), log(m) = 2 atanh(z).
constexpr double DetLog(double x) {
  int e = 0;
  while (x >= 1.4142135623730951) {
    x *= 0.5;
    ++e;
  }
  while (x < 0.70710678118654752) {
    x *= 2.0;
    --e;
  }
  const double z = (x - 1.0) / (x + 1.0);
  const double z2 = z * z;
  double sum = 0.0;
  for (int n = 31; n >= 1; n -= 2) sum = 1.0 / n + z2 * sum;
  return 2.0 * z * sum + e * kLn2;
}

constexpr double DetSqrt(double x) {
  if (x <= 0.0) return 0.0;
  double y = x > 1.0 ? x : 1.0;
  for (int i = 0; i < 200; ++i) {
    const double next = 0.5 * (y + x / y);
    if (next == y) break;
    y = next;
  }
  return y;
}

// 256-layer ziggurat for the standard normal (Marsaglia & Tsang 2000): layer edges x[i] with
// x[1] = R, x[256] = 0 and x[0] = V / f(R) standing in for the base layer with its tail.
constexpr int kZigLayers = 256;
constexpr double kZigR = 3.6541528853610088;
constexpr double kZigV = 4.92867323399e-3;

struct ZigguratTables {
  std::array<double, kZigLayers + 1> x{};
  std::array<double, kZigLayers + 1> f{};  // exp(-x^2 / 2)
  // The common path in integers. A draw is a signed 53-bit integer j and a layer i; its value is
  // u x[i] with u = j 2^-52, and it lies inside the layer's rectangle when |u x[i]| < x[i + 1].
  // Since u x[i] = j (x[i] 2^-52) exactly (scaling by a power of two) and rounding is monotone
  // and symmetric, that holds exactly when |j| < inside_below[i]: one integer compare instead of
  // a convert, a multiply and a floating compare, with bit-identical accepted values.
  std::array<double, kZigLayers> scaled_x{};  // x[i] 2^-52
  std::array<std::uint64_t, kZigLayers> inside_below{};
  // |j| < B as one unsigned compare without taking |j|: with B >= 1, -(B - 1) <= j <= B - 1
  // exactly when j + (B - 1), wrapped to 64 bits, is below 2B - 1 (a j under -(B - 1) wraps to
  // at least 2^64 - 2^52 - 1). A layer with B = 0 (the top one, x[256] = 0) accepts nothing,
  // which a limit of 0 encodes.
  std::array<std::uint64_t, kZigLayers> inside_bias{};   // B - 1, or 0 when B = 0
  std::array<std::uint64_t, kZigLayers> inside_limit{};  // 2B - 1, or 0 when B = 0
};

// The least j >= 0 whose value in layer i is not inside the rectangle, found by testing the
// double expression itself around its real-valued estimate, so it is exact by construction.
constexpr std::uint64_t InsideBelow(const ZigguratTables& t, int i) {
  const auto inside = [&](std::uint64_t j) {
    return (static_cast<double>(j) * 0x1.0p-52) * t.x[i] < t.x[i + 1];
  };
  std::uint64_t j = static_cast<std::uint64_t>(t.x[i + 1] / t.x[i] * 0x1.0p52);
  while (j > 0 && !inside(j - 1)) --j;
  while (inside(j)) ++j;
  return j;
}

constexpr ZigguratTables MakeZigguratTables() {
  ZigguratTables t;
  const double f_r = DetExp(-0.5 * kZigR * kZigR);
  t.x[0] = kZigV / f_r;
  t.x[1] = kZigR;
  for (int i = 2; i < kZigLayers; ++i) {
    t.x[i] = DetSqrt(-2.0 * DetLog(kZigV / t.x[i - 1] + DetExp(-0.5 * t.x[i - 1] * t.x[i - 1])));
  }
  t.x[kZigLayers] = 0.0;
  for (int i = 0; i <= kZigLayers; ++i) t.f[i] = DetExp(-0.5 * t.x[i] * t.x[i]);
  for (int i = 0; i < kZigLayers; ++i) {
    t.scaled_x[i] = t.x[i] * 0x1.0p-52;
    t.inside_below[i] = InsideBelow(t, i);
    const std::uint64_t b = t.inside_below[i];
    t.inside_bias[i] = b > 0 ? b - 1 : 0;
    t.inside_limit[i] = b > 0 ? 2 * b - 1 : 0;
  }
  return t;
}

constexpr ZigguratTables kZig = MakeZigguratTables();

// The biased compare equals |j| < inside_below at every boundary of every layer and at the ends
// of the 53-bit range, checked at compile time.
constexpr bool BiasedCompareMatchesMagnitude() {
  constexpr std::int64_t kMin = -(std::int64_t{1} << 52), kMax = (std::int64_t{1} << 52) - 1;
  for (int i = 0; i < kZigLayers; ++i) {
    const auto b = static_cast<std::int64_t>(kZig.inside_below[i]);
    for (const std::int64_t j : {kMin, kMin + 1, -b - 1, -b, -b + 1, std::int64_t{-1},
                                 std::int64_t{0}, std::int64_t{1}, b - 1, b, b + 1, kMax}) {
      if (j < kMin || j > kMax) continue;
      const bool biased =
          static_cast<std::uint64_t>(j) + kZig.inside_bias[i] < kZig.inside_limit[i];
      const std::uint64_t magnitude = j < 0 ? std::uint64_t(-j) : std::uint64_t(j);
      if (biased != (magnitude < kZig.inside_below[i])) return false;
    }
  }
  return true;
}
static_assert(BiasedCompareMatchesMagnitude());

using State = std::array<std::uint64_t, 4>;

// xoshiro256** on a state the caller holds, so that a run of draws can keep it in registers.
inline std::uint64_t Next(State& s) {
  const std::uint64_t result = Rotl(s[1] * 5, 7) * 9;
  const std::uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = Rotl(s[3], 45);
  return result;
}

double Uniform01From(State& s) { return static_cast<double>(Next(s) >> 11) * 0x1.0p-53; }

// Splits one 64-bit draw: low 8 bits pick the layer, the top 53 (disjoint from them) give a
// signed uniform in [-1, 1).
struct ZigguratDraw {
  int layer;
  double u;
  double x;
};

inline ZigguratDraw SplitDraw(std::uint64_t bits) {
  const int layer = static_cast<int>(bits & 0xff);
  const double u = static_cast<double>(static_cast<std::int64_t>(bits) >> 11) * 0x1.0p-52;
  return {layer, u, u * kZig.x[layer]};
}

struct SlowDraw {
  double value;
  State s;
};

// Wedge and tail of the ziggurat, out of line so the common path stays a few instructions. The
// state goes in and out by value so that the caller's copy never has its address taken and can
// stay in registers.
[[gnu::noinline]] SlowDraw GaussianSlowPath(State s, std::uint64_t bits) {
  ZigguratDraw d = SplitDraw(bits);
  for (;;) {
    if (d.layer == 0) {
      // Beyond R in the base layer: Marsaglia's exact tail method.
      double tail_x, tail_y;
      do {
        tail_x = -DetLog(1.0 - Uniform01From(s)) / kZigR;  // 1 - U lies in (0, 1]
        tail_y = -DetLog(1.0 - Uniform01From(s));
      } while (2.0 * tail_y < tail_x * tail_x);
      return {d.u < 0.0 ? -(kZigR + tail_x) : kZigR + tail_x, s};
    }
    // In the wedge between the rectangle and the curve: accept under the density.
    const double y = kZig.f[d.layer] + (kZig.f[d.layer + 1] - kZig.f[d.layer]) * Uniform01From(s);
    if (y < DetExp(-0.5 * d.x * d.x)) return {d.x, s};

    d = SplitDraw(Next(s));
    if (std::fabs(d.x) < kZig.x[d.layer + 1]) return {d.x, s};
  }
}

inline double GaussianFrom(State& s) {
  const std::uint64_t bits = Next(s);
  const auto layer = static_cast<std::size_t>(bits & 0xff);
  const std::int64_t j = static_cast<std::int64_t>(bits) >> 11;
  // |j| < inside_below[layer], see ZigguratTables::inside_bias.
  if (static_cast<std::uint64_t>(j) + kZig.inside_bias[layer] < kZig.inside_limit[layer])
      [[likely]] {
    return static_cast<double>(j) * kZig.scaled_x[layer];  // inside the layer's rectangle
  }
  const SlowDraw slow = GaussianSlowPath(s, bits);
  s = slow.s;
  return slow.value;
}

}  // namespace

RandomStream RandomStream::FromSeed(std::uint64_t scenario_seed, std::uint64_t stream_id) {
  // Asymmetric combination so (seed a, stream b) and (seed b, stream a) differ.
  std::uint64_t sm = Mix64(scenario_seed + kGolden) ^ Mix64(Mix64(stream_id) + 2 * kGolden);
  State s;
  for (auto& word : s) {
    sm += kGolden;
    word = Mix64(sm);
  }
  // xoshiro's only forbidden state; four consecutive splitmix outputs cannot all be zero, but
  // the guard costs nothing and documents the invariant.
  if ((s[0] | s[1] | s[2] | s[3]) == 0) s[0] = kGolden;
  return RandomStream(s);
}

RandomStream::RandomStream() : RandomStream(FromSeed(0, 0)) {}

std::uint64_t RandomStream::NextU64() { return Next(s_); }

double RandomStream::Uniform01() { return Uniform01From(s_); }

double RandomStream::Gaussian() {
  State s = s_;
  const double value = GaussianFrom(s);
  s_ = s;
  return value;
}

Eigen::Vector3d StandardGaussianVector(RandomStream& rng) {
  RandomStream::State s = rng.s_;
  const double x = GaussianFrom(s);
  const double y = GaussianFrom(s);
  const double z = GaussianFrom(s);
  rng.s_ = s;
  return {x, y, z};
}

void FillStandardGaussians(RandomStream& rng, std::span<double> out) {
  RandomStream::State s = rng.s_;
  for (double& draw : out) draw = GaussianFrom(s);
  rng.s_ = s;
}

}  // namespace hilrig::host
