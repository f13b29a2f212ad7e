// Stand-in for libFuzzer's driver when the compiler has none (GCC): feeds the target a fixed,
// deterministic set of inputs -- pure pseudo-random bytes, and the target's seeds with random bit
// flips, byte overwrites, truncations and splices -- so CI exercises every decoder either way. A
// failed property traps, which fails the ctest test; the inputs are reproducible from the index.
#include <cstdint>
#include <cstdio>
#include <vector>

#include "fuzz/fuzz_seeds.h"

namespace {

constexpr int kInputs = 600;
constexpr std::size_t kMaxInput = 96;

// SplitMix64: a fixed generator, so the corpus is the same on every machine and compiler.
std::uint64_t Next(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::vector<std::vector<std::uint8_t>> Seeds() {
  std::vector<std::vector<std::uint8_t>> seeds;
  for (unsigned index = 0;; ++index) {
    std::vector<std::uint8_t> seed(kMaxInput);
    const std::size_t size = HilrigFuzzSeed(index, seed.data(), seed.size());
    if (size == 0) break;
    seed.resize(size);
    seeds.push_back(seed);
  }
  return seeds;
}

std::vector<std::uint8_t> RandomBytes(std::uint64_t& rng) {
  std::vector<std::uint8_t> input(Next(rng) % kMaxInput);
  for (std::uint8_t& byte : input) byte = static_cast<std::uint8_t>(Next(rng));
  return input;
}

std::vector<std::uint8_t> Mutated(const std::vector<std::vector<std::uint8_t>>& seeds,
                                  std::uint64_t& rng) {
  std::vector<std::uint8_t> input = seeds[Next(rng) % seeds.size()];
  const int mutations = 1 + static_cast<int>(Next(rng) % 3);
  for (int m = 0; m < mutations && !input.empty(); ++m) {
    const std::size_t at = Next(rng) % input.size();
    switch (Next(rng) % 4) {
      case 0:
        input[at] ^= static_cast<std::uint8_t>(1u << (Next(rng) % 8));
        break;
      case 1:
        input[at] = static_cast<std::uint8_t>(Next(rng));
        break;
      case 2:
        input.resize(at);
        break;
      default: {
        const std::vector<std::uint8_t>& other = seeds[Next(rng) % seeds.size()];
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), other.begin(), other.end());
      }
    }
  }
  return input;
}

}  // namespace

int main() {
  const std::vector<std::vector<std::uint8_t>> seeds = Seeds();
  std::uint64_t rng = 20240601;
  std::size_t bytes = 0;
  for (const std::vector<std::uint8_t>& seed : seeds) {
    LLVMFuzzerTestOneInput(seed.data(), seed.size());
  }
  for (int i = 0; i < kInputs; ++i) {
    const std::vector<std::uint8_t> input =
        (seeds.empty() || i % 2 == 0) ? RandomBytes(rng) : Mutated(seeds, rng);
    LLVMFuzzerTestOneInput(input.data(), input.size());
    bytes += input.size();
  }
  std::printf("replayed %zu seeds and %d generated inputs (%zu bytes)\n", seeds.size(), kInputs,
              bytes);
  return 0;
}
