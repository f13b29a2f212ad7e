// Reads what every controller needs of the run's DutConfig (proto/hil_link.proto): the control
// period and the vehicle's mass, inertia and rotor geometry. The rest of the message (a
// controller's gains, the tactile front end) is the controller's to read from RunDescription's
// `config`. Portable: no allocation; O(message bytes).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "dut_link/controller.h"
#include "dut_link/wire_codec.h"
#include "proto/hil_link_tags.h"

namespace hilrig::dut_link {

namespace run_description_internal {

// A Vector3 message's x, y, z; absent components are 0.
inline std::array<double, 3> ReadVector3(wire::Reader vector, bool& ok) {
  std::array<double, 3> out = {0, 0, 0};
  while (const auto tag = vector.Next()) {
    if (tag->field >= proto_tags::Vector3::kX && tag->field <= proto_tags::Vector3::kZ) {
      out[tag->field - proto_tags::Vector3::kX] = vector.Double();
    }
  }
  ok = ok && vector.ok();
  return out;
}

inline bool ReadVehicle(wire::Reader flight, VehicleDescription& vehicle) {
  namespace field = proto_tags::FlightFirmware;
  bool ok = true;
  while (const auto tag = flight.Next()) {
    switch (tag->field) {
      case field::kPositionMassKg:
        vehicle.mass_kg = flight.Double();
        break;
      case field::kPositionGravityMS2:
        vehicle.gravity_m_s2 = flight.Double();
        break;
      case field::kAttitudeInertiaKgM2:
        vehicle.inertia_kg_m2 = ReadVector3(flight.Message(), ok);
        break;
      case field::kMixerArmLengthM:
        vehicle.arm_length_m = flight.Double();
        break;
      case field::kMixerTorquePerThrustM:
        vehicle.torque_per_thrust_m = flight.Double();
        break;
      case field::kMixerMaxThrustPerRotorN:
        vehicle.max_thrust_per_rotor_n = flight.Double();
        break;
      default:
        break;
    }
  }
  return ok && flight.ok();
}

}  // namespace run_description_internal

// Fills `run` from a DutConfig message; false when the message is not well formed (then `run` is
// partly filled and must not be used). Cannot fail otherwise: the ranges are the controller's to
// judge.
inline bool DecodeRunDescription(std::span<const std::uint8_t> config, RunDescription& run) {
  run = RunDescription{};
  run.config = config;
  wire::Reader reader(config);
  bool ok = true;
  while (const auto tag = reader.Next()) {
    if (tag->field == proto_tags::DutConfig::kControlPeriodS) {
      run.control_period_s = reader.Double();
    } else if (tag->field == proto_tags::DutConfig::kFlight) {
      ok = run_description_internal::ReadVehicle(reader.Message(), run.vehicle) && ok;
    }
  }
  return ok && reader.ok();
}

}  // namespace hilrig::dut_link
