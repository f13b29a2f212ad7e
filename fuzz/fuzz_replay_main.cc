// Stand-in for libFuzzer's driver when the compiler has none (GCC): `TARGET CORPUS_DIR` feeds the
// target every file of its corpus (the inputs libFuzzer runs kept because they reached new code),
// then a fixed, deterministic set of generated inputs -- pure pseudo-random bytes, and corpus files
// with random bit flips, byte overwrites, truncations and splices -- so CI exercises every decoder
// either way. A failed property traps, which fails the ctest test; the inputs are reproducible
// from the index.
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "fuzz/fuzz_target.h"

namespace {

namespace fs = std::filesystem;

using Input = std::vector<std::uint8_t>;

constexpr int kInputs = 600;
constexpr std::size_t kMaxInput = 96;

// SplitMix64: a fixed generator, so the generated inputs are the same on every machine and
// compiler.
std::uint64_t Next(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::optional<Input> ReadFile(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  Input bytes;
  if (file) bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  if (!file.is_open() || file.bad()) {
    std::fprintf(stderr, "fuzz replay: cannot read %s: %s\n", path.c_str(), std::strerror(errno));
    return std::nullopt;
  }
  return bytes;
}

// The corpus files in name order, so a failure names the same index everywhere; nullopt (after
// saying why) when the folder cannot be listed or read, or holds no file.
std::optional<std::vector<Input>> ReadCorpus(const fs::path& dir) {
  std::error_code error;
  std::vector<fs::path> paths;
  for (fs::directory_iterator it(dir, error), end; !error && it != end; it.increment(error)) {
    if (it->is_regular_file(error)) paths.push_back(it->path());
  }
  if (error) {
    std::fprintf(stderr, "fuzz replay: cannot list %s: %s\n", dir.c_str(), error.message().c_str());
    return std::nullopt;
  }
  if (paths.empty()) {
    std::fprintf(stderr, "fuzz replay: %s holds no corpus file\n", dir.c_str());
    return std::nullopt;
  }
  std::sort(paths.begin(), paths.end());
  std::vector<Input> corpus;
  for (const fs::path& path : paths) {
    std::optional<Input> bytes = ReadFile(path);
    if (!bytes) return std::nullopt;
    corpus.push_back(std::move(*bytes));
  }
  return corpus;
}

Input RandomBytes(std::uint64_t& rng) {
  Input input(Next(rng) % kMaxInput);
  for (std::uint8_t& byte : input) byte = static_cast<std::uint8_t>(Next(rng));
  return input;
}

Input Mutated(const std::vector<Input>& seeds, std::uint64_t& rng) {
  Input input = seeds[Next(rng) % seeds.size()];
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
        const Input& other = seeds[Next(rng) % seeds.size()];
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), other.begin(), other.end());
      }
    }
  }
  return input;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const std::optional<std::vector<Input>> corpus = ReadCorpus(argv[1]);
  if (!corpus) return 2;
  for (const Input& input : *corpus) LLVMFuzzerTestOneInput(input.data(), input.size());
  std::uint64_t rng = 20240601;
  std::size_t bytes = 0;
  for (int i = 0; i < kInputs; ++i) {
    const Input input = i % 2 == 0 ? RandomBytes(rng) : Mutated(*corpus, rng);
    LLVMFuzzerTestOneInput(input.data(), input.size());
    bytes += input.size();
  }
  std::printf("replayed %zu corpus files and %d generated inputs (%zu bytes)\n", corpus->size(),
              kInputs, bytes);
  return 0;
}
