// The link's firmware check (host/link/firmware_check.h) must refuse only what no scenario makes,
// so that a run with the DUT in its own process starts wherever the in-process run does.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "host/dut/firmware_config.h"
#include "host/link/firmware_check.h"
#include "host/scenario/scenario_config.h"
#include "host/scenario/scenario_loader.h"
#include "tests/support/test_paths.h"

namespace hilrig::host {
namespace {

ScenarioConfig Shipped(const std::string& path) {
  const auto spec = LoadScenario(path);
  EXPECT_TRUE(spec.ok()) << spec.error().message;
  return ResolveScenario(spec.value(), std::nullopt,
                         ::hilrig::test_support::SourceDir() + "/scenarios");
}

// The flight and grasp parts of every shipped scene. The tactile part needs a calibration, which
// takes a while per scene; ProcessDutAcceptanceTest runs a calibrated tactile scene through the
// check end to end.
TEST(ShippedFirmwareTest, EveryShippedSceneFlightAndGraspFirmwarePasses) {
  int scenes = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(::hilrig::test_support::SourceDir() + "/scenarios")) {
    if (entry.path().extension() != ".textproto") continue;
    ScenarioConfig config = Shipped(entry.path().string());
    config.hall_sensors.tactile_enabled = false;
    const auto checked = CheckDutFirmware(FirmwareFor(config));
    EXPECT_TRUE(checked.ok()) << entry.path() << ": " << checked.error().message;
    ++scenes;
  }
  EXPECT_GE(scenes, 5);
}

}  // namespace
}  // namespace hilrig::host
