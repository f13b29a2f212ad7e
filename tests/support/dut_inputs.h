// Tests that cover every DutInput alternative build them by index, so that a new stream is in
// them without being named.
#pragma once

#include <cstddef>
#include <optional>
#include <utility>

#include "host/link/hil_messages.h"

namespace hilrig::test {

// Alternative `index` of DutInput, default-constructed.
inline host::DutInput DutInputAt(std::size_t index) {
  std::optional<host::DutInput> input;
  [&]<std::size_t... kIndex>(std::index_sequence<kIndex...>) {
    (void)((index == kIndex ? (input.emplace(std::in_place_index<kIndex>), true) : false) || ...);
  }
  (std::make_index_sequence<host::kDutInputStreams>());
  return *input;
}

}  // namespace hilrig::test
