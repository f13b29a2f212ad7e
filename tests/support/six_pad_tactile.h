// The tactile front end of a six-pad test DUT that needs no calibration run: nodes 1..6 with the
// firmware bench's gains and the paper's film.
#pragma once

#include <cstdint>

#include "dut_fw/tactile_processor.h"

namespace hilrig::dut_fw {

template <typename S>
TactileProcessorParams<S> SixPadTactile(std::uint32_t zeroing_samples) {
  TactileProcessorParams<S> params;
  for (std::size_t i = 0; i < params.nodes.size(); ++i) {
    params.nodes[i].node_id = std::uint8_t(i + 1);
    params.nodes[i].gain_a = Vec3<S>(S(0.5), S(0.5), S(2.0));
  }
  params.film = FilmConstants<S>::Published();
  params.zeroing_samples = zeroing_samples;
  return params;
}

}  // namespace hilrig::dut_fw
