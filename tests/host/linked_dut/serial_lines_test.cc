// The lines of a serial DUT as `--dut` names them: the serial: spec and its errors, the firmware
// image's search, and QEMU's start-up failures (with a stand-in for qemu-system-arm, so it runs
// where QEMU is not installed).
#include "host/linked_dut/serial_lines.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

TEST(SerialPortSpecTest, ReadsTheDeviceTheBaudAndTheBridge) {
  auto plain = ParseSerialPortSpec("serial:/dev/ttyACM0");
  ASSERT_TRUE(plain) << plain.error().message;
  EXPECT_EQ(plain.value().device, "/dev/ttyACM0");
  EXPECT_EQ(plain.value().baud, 2'000'000u);  // the firmware image's rates
  EXPECT_EQ(plain.value().bridge_device, "");
  EXPECT_EQ(plain.value().bridge_baud, 921'600u);
  auto full = ParseSerialPortSpec(
      "serial:/dev/ttyACM0,bridge=/dev/ttyUSB0,baud=3000000,bridge_baud=115200");
  ASSERT_TRUE(full) << full.error().message;
  EXPECT_EQ(full.value().baud, 3'000'000u);
  EXPECT_EQ(full.value().bridge_device, "/dev/ttyUSB0");
  EXPECT_EQ(full.value().bridge_baud, 115'200u);
}

TEST(SerialPortSpecTest, NamesWhatIsWrongWithABadSpec) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"serial:", "no device after serial:"},
      {"tty:/dev/ttyACM0", "expected serial:DEVICE"},
      {"serial:/dev/a,baud=fast", "baud \"fast\" is not a whole number"},
      {"serial:/dev/a,baud=0", "baud \"0\" is not a whole number"},
      {"serial:/dev/a,baud=115200x", "baud \"115200x\""},
      {"serial:/dev/a,baud=", "baud \"\""},
      {"serial:/dev/a,baud=9600,baud=9600", "baud= given twice"},
      {"serial:/dev/a,bridge=/dev/b,bridge=/dev/c", "bridge= given twice"},
      {"serial:/dev/a,bridge_baud=0", "baud \"0\" is not a whole number"},
      {"serial:/dev/a,bridge_baud=1,bridge_baud=2", "bridge_baud= given twice"},
      {"serial:/dev/a,bridge=", "no device after bridge="},
      {"serial:/dev/a,bridge=/dev/a", "the bridge is the link's own device"},
      {"serial:/dev/a,parity=even", "unknown option \"parity=even\""},
      {"serial:/dev/a,", "unknown option \"\""},
  };
  for (const auto& [spec, why] : cases) {
    auto parsed = ParseSerialPortSpec(spec);
    ASSERT_FALSE(parsed) << spec;
    EXPECT_NE(parsed.error().message.find("\"" + spec + "\": "), std::string::npos)
        << parsed.error().message;
    EXPECT_NE(parsed.error().message.find(why), std::string::npos) << parsed.error().message;
  }
}

TEST(SerialPortLinesTest, NamesTheDeviceThatDoesNotOpen) {
  auto lines = SerialPortLines({"/dev/hilrig-no-such-tty", 115200, "", 115200, ""})(1.0);
  ASSERT_FALSE(lines);
  EXPECT_NE(lines.error().message.find("/dev/hilrig-no-such-tty: open: No such file"),
            std::string::npos)
      << lines.error().message;
}

TEST(TargetImageTest, NamesAMissingImageAndHowToBuildOne) {
  auto named = FindTargetImage(std::string("/nonexistent/image.elf"));
  ASSERT_FALSE(named);
  EXPECT_NE(named.error().message.find("no target image at /nonexistent/image.elf"),
            std::string::npos);
  const std::filesystem::path dir = FreshTestDir("target_image");
  const std::filesystem::path image = dir / "fw.elf";
  std::ofstream(image) << "ELF";
  auto found = FindTargetImage(image.string());
  ASSERT_TRUE(found) << found.error().message;
  EXPECT_EQ(found.value(), image.string());
  // Without a name: the image ./scripts/build-target makes, or the advice to make it.
  auto searched = FindTargetImage(std::nullopt);
  if (!searched) {
    EXPECT_NE(searched.error().message.find("run ./scripts/build-target"), std::string::npos)
        << searched.error().message;
  } else {
    EXPECT_NE(searched.value().find(kTargetImageName), std::string::npos);
  }
}

// A stand-in for qemu-system-arm: a script that records its arguments and exits with `status`.
std::string FakeQemu(const std::filesystem::path& dir, int status) {
  const std::filesystem::path script = dir / "qemu-system-arm";
  std::ofstream(script) << "#!/bin/sh\necho \"$@\" > " << (dir / "argv").string() << "\nexit "
                        << status << "\n";
  ::chmod(script.c_str(), 0755);
  return script.string();
}

TEST(QemuLinesTest, NamesAnEmulatorThatExitsBeforeOpeningItsPorts) {
  const std::filesystem::path dir = FreshTestDir("fake_qemu");
  auto lines = QemuLines({"/images/fw.elf", FakeQemu(dir, 3)})(10.0);
  ASSERT_FALSE(lines);
  EXPECT_NE(
      lines.error().message.find("qemu-system-arm exited with status 3 before opening USART1"),
      std::string::npos)
      << lines.error().message;
  const std::string argv = ReadFile(dir / "argv");
  EXPECT_NE(argv.find("-M netduinoplus2 -display none -monitor none -icount shift=0 -kernel "
                      "/images/fw.elf -serial tcp:127.0.0.1:"),
            std::string::npos)
      << argv;
  EXPECT_NE(argv.find(",server=on,wait=off,nodelay=on -serial tcp:127.0.0.1:"), std::string::npos)
      << argv;
}

TEST(QemuLinesTest, NamesAMissingEmulator) {
  auto lines = QemuLines({"/images/fw.elf", "/nonexistent/qemu-system-arm"})(1.0);
  ASSERT_FALSE(lines);
  EXPECT_NE(lines.error().message.find("/nonexistent/qemu-system-arm"), std::string::npos)
      << lines.error().message;
}

}  // namespace
}  // namespace hilrig::host
