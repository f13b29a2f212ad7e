#include "host/report/signal_unit.h"

namespace hilrig::host {

const char* SignalUnit(proto::Signal signal) {
  switch (signal) {
    case proto::POSITION_ERROR_M:
    case proto::HORIZONTAL_ERROR_M:
    case proto::ALTITUDE_ERROR_M:
    case proto::ALTITUDE_M:
      return "m";
    case proto::TILT_DEG:
      return "deg";
    case proto::SPEED_M_S:
    case proto::SLIP_SPEED_M_S:
      return "m/s";
    case proto::TACTILE_FORCE_N:
    case proto::TACTILE_FORCE_ERROR_N:
    case proto::GRASP_FORCE_N:
    case proto::GRASP_FORCE_ESTIMATE_N:
    case proto::GRASP_FORCE_ERROR_N:
    case proto::LOAD_N:
    case proto::LOAD_ESTIMATE_ERROR_N:
    case proto::GROUND_FORCE_N:
    case proto::PAD_FORCE_N:
    case proto::PAD_FORCE_ESTIMATE_N:
    case proto::PAD_FORCE_ERROR_N:
      return "N";
    case proto::SERVO_ANGLE_RAD:
      return "rad";
    default:
      return "";
  }
}

}  // namespace hilrig::host
