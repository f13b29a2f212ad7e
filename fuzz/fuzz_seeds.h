// The seam between a fuzz target and the replay driver that stands in for libFuzzer when the
// compiler has none: each target provides a few well-formed inputs (valid frames), which the
// replay driver mutates, so a plain ctest run reaches the decoders' deep paths and not only their
// first rejection. Under libFuzzer the seeds are unused; libFuzzer finds its own way in.
#pragma once

#include <cstddef>
#include <cstdint>

// Writes seed number `index` into `out` (at most `capacity` bytes) and returns its size; 0 when
// the target has no seed of that number.
extern "C" std::size_t HilrigFuzzSeed(unsigned index, std::uint8_t* out, std::size_t capacity);
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
