// The entry point every fuzz target defines, as libFuzzer declares it: the replay driver that
// stands in for libFuzzer when the compiler has none (fuzz_replay_main.cc) calls it with each file
// of the target's corpus and with inputs mutated from them.
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
