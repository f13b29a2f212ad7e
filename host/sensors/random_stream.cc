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
};

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
  return t;
}

constexpr ZigguratTables kZig = MakeZigguratTables();

}  // namespace

RandomStream RandomStream::FromSeed(std::uint64_t scenario_seed, std::uint64_t stream_id) {
  // Asymmetric combination so (seed a, stream b) and (seed b, stream a) differ.
  std::uint64_t sm = Mix64(scenario_seed + kGolden) ^ Mix64(Mix64(stream_id) + 2 * kGolden);
  std::array<std::uint64_t, 4> s;
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

std::uint64_t RandomStream::NextU64() {
  const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = Rotl(s_[3], 45);
  return result;
}

double RandomStream::Uniform01() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }

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

double RandomStream::Gaussian() {
  const ZigguratDraw d = SplitDraw(NextU64());
  if (std::fabs(d.x) < kZig.x[d.layer + 1]) [[likely]] {
    return d.x;  // inside the layer's rectangle: ~99% of draws
  }
  return GaussianSlowPath(d.layer, d.u, d.x);
}

double RandomStream::GaussianSlowPath(int layer, double u, double x) {
  for (;;) {
    if (layer == 0) {
      // Beyond R in the base layer: Marsaglia's exact tail method.
      double tail_x, tail_y;
      do {
        tail_x = -DetLog(1.0 - Uniform01()) / kZigR;  // 1 - U lies in (0, 1]
        tail_y = -DetLog(1.0 - Uniform01());
      } while (2.0 * tail_y < tail_x * tail_x);
      return u < 0.0 ? -(kZigR + tail_x) : kZigR + tail_x;
    }
    // In the wedge between the rectangle and the curve: accept under the density.
    const double y = kZig.f[layer] + (kZig.f[layer + 1] - kZig.f[layer]) * Uniform01();
    if (y < DetExp(-0.5 * x * x)) return x;

    const ZigguratDraw d = SplitDraw(NextU64());
    if (std::fabs(d.x) < kZig.x[d.layer + 1]) return d.x;
    layer = d.layer;
    u = d.u;
    x = d.x;
  }
}

Eigen::Vector3d StandardGaussianVector(RandomStream& rng) {
  const double x = rng.Gaussian();
  const double y = rng.Gaussian();
  const double z = rng.Gaussian();
  return {x, y, z};
}

}  // namespace hilrig::host
