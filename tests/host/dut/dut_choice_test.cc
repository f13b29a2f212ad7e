#include "host/dut/dut_choice.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;

DutArguments Dut(const char* word) {
  DutArguments arguments;
  arguments.dut = word;
  return arguments;
}

std::string ErrorOf(const DutArguments& arguments) {
  const auto choice = ParseDutChoice(arguments);
  return choice.ok() ? "" : choice.error().message;
}

TEST(DutChoiceTest, EachWordNamesItsKind) {
  EXPECT_EQ(ParseDutChoice(DutArguments{}).value().kind, DutKind::kInProcess);
  for (DutKind kind :
       {DutKind::kInProcess, DutKind::kInProcessFloat, DutKind::kProcess, DutKind::kQemu}) {
    EXPECT_EQ(ParseDutChoice(Dut(DutKindName(kind))).value().kind, kind) << DutKindName(kind);
  }
  const DutChoice serial = ParseDutChoice(Dut("serial:/dev/ttyACM0,baud=115200")).value();
  EXPECT_EQ(serial.kind, DutKind::kSerial);
  EXPECT_EQ(serial.port.device, "/dev/ttyACM0");
  EXPECT_EQ(serial.port.baud, 115200u);
}

TEST(DutChoiceTest, AnUnknownWordListsTheKinds) {
  EXPECT_THAT(ErrorOf(Dut("px4")), HasSubstr("--dut \"px4\": expected inproc, inproc-float"));
  EXPECT_THAT(ErrorOf(Dut("serial:")), HasSubstr("--dut "));
}

TEST(DutChoiceTest, AnOptionTheKindDoesNotTakeIsRefusedByName) {
  DutArguments image = Dut("process");
  image.target_image = "fw.elf";
  EXPECT_EQ(ErrorOf(image), "--target-image needs --dut qemu");
  DutArguments timeout = Dut("inproc-float");
  timeout.timeout_s = "2";
  EXPECT_EQ(ErrorOf(timeout), "--dut-timeout-s needs --dut process, qemu or serial:");
  DutArguments link = Dut("qemu");
  link.link = "tcp";
  EXPECT_EQ(ErrorOf(link), "--dut-link needs --dut process");
  DutArguments can = Dut("serial:/dev/ttyACM0");
  can.can = "socketcan:can0";
  EXPECT_EQ(ErrorOf(can), "--can socketcan:can0 needs --dut process");
}

TEST(DutChoiceTest, BadValuesNameTheirOption) {
  DutArguments link = Dut("process");
  link.link = "pipe";
  EXPECT_EQ(ErrorOf(link), "--dut-link \"pipe\": expected shm or tcp");
  DutArguments words = Dut("process");
  words.timeout_s = "soon";
  EXPECT_EQ(ErrorOf(words), "--dut-timeout-s \"soon\" is not a number");
  DutArguments negative = Dut("qemu");
  negative.timeout_s = "-1";
  EXPECT_THAT(ErrorOf(negative), HasSubstr("--dut-timeout-s: "));
  DutArguments can = Dut("process");
  can.can = "emulated";
  EXPECT_THAT(ErrorOf(can), HasSubstr("--can: "));
}

TEST(DutChoiceTest, EachKindGetsItsOwnDefaultsAndTheGivenOptions) {
  const DutChoice qemu = ParseDutChoice(Dut("qemu")).value();
  EXPECT_EQ(qemu.serial.answer_timeout_s, 10.0);  // an emulated core on a busy host is slow
  EXPECT_EQ(qemu.serial.step_retry_s, 1.0);
  DutArguments short_watchdog = Dut("serial:/dev/ttyACM0");
  short_watchdog.timeout_s = "0.04";
  const DutChoice serial = ParseDutChoice(short_watchdog).value();
  EXPECT_EQ(serial.serial.answer_timeout_s, 0.04);
  EXPECT_EQ(serial.serial.step_retry_s, 0.02);  // room for a retry before the watchdog
  DutArguments process = Dut("process");
  process.link = "tcp";
  process.timeout_s = "3";
  const DutChoice chosen = ParseDutChoice(process).value();
  EXPECT_EQ(chosen.process.transport, DutLinkTransport::kTcp);
  EXPECT_EQ(chosen.process.answer_timeout_s, 3.0);
}

TEST(MakeDutFactoryTest, TheDefaultIsTheRunnersOwnInProcessDut) {
  EXPECT_FALSE(static_cast<bool>(MakeDutFactory(DutChoice{}, false).value()));
  DutChoice single;
  single.kind = DutKind::kInProcessFloat;
  EXPECT_TRUE(static_cast<bool>(MakeDutFactory(single, false).value()));
}

TEST(MakeDutFactoryTest, AQemuImageThatIsNotThereIsNamed) {
  DutArguments arguments = Dut("qemu");
  arguments.target_image = "/nonexistent/dut_fw_stm32f405.elf";
  const auto factory = MakeDutFactory(ParseDutChoice(arguments).value(), false);
  ASSERT_FALSE(factory.ok());
  EXPECT_THAT(factory.error().message, HasSubstr("--dut qemu: "));
  EXPECT_THAT(factory.error().message, HasSubstr("/nonexistent/dut_fw_stm32f405.elf"));
}

}  // namespace
}  // namespace hilrig::host
