// The unit of each signal an envelope can watch (proto/scenario.proto's Signal), for the pages and
// plots that show worst values and limits next to their numbers.
#pragma once

#include "proto/scenario.pb.h"

namespace hilrig::host {

// "m", "deg", "m/s", "N", "rad"; "" for the 0/1 flags (object damaged, dropped) and an unknown
// signal.
const char* SignalUnit(proto::Signal signal);

}  // namespace hilrig::host
