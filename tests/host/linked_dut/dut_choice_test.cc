#include "host/linked_dut/dut_choice.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

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

TEST(DutChoiceTest, ExecNamesAProgramAndItsArguments) {
  DutArguments arguments = Dut("exec:./my_dut,--gain,2");
  arguments.link = "tcp";
  arguments.can = "socketcan:can0";
  const DutChoice choice = ParseDutChoice(arguments).value();
  EXPECT_EQ(choice.kind, DutKind::kExec);
  EXPECT_EQ(choice.process.program, "./my_dut");
  EXPECT_EQ(choice.process.program_args, (std::vector<std::string>{"--gain", "2"}));
  EXPECT_EQ(choice.process.transport, DutLinkTransport::kTcp);
  EXPECT_EQ(choice.process.can_uri, "socketcan:can0");
  EXPECT_TRUE(ParseDutChoice(Dut("exec:my_dut")).value().process.program_args.empty());
  EXPECT_EQ(ErrorOf(Dut("exec:")),
            "--dut \"exec:\": exec: needs a program (exec:PROGRAM[,ARG...])");
  EXPECT_EQ(ErrorOf(Dut("exec:,--gain")),
            "--dut \"exec:,--gain\": exec: needs a program (exec:PROGRAM[,ARG...])");
}

TEST(DutChoiceTest, ListenNamesWhereToWaitAndTheTokensFile) {
  const DutChoice plain = ParseDutChoice(Dut("listen:127.0.0.1:4600")).value();
  EXPECT_EQ(plain.kind, DutKind::kListen);
  EXPECT_TRUE(plain.process.listen);
  EXPECT_EQ(plain.process.transport, DutLinkTransport::kTcp);
  EXPECT_EQ(plain.process.listen_address, "127.0.0.1");
  EXPECT_EQ(plain.process.listen_port, 4600);
  EXPECT_EQ(plain.process.token_file, "hilrig_link_token");
  EXPECT_EQ(plain.process.start_timeout_s, 60.0);  // a person starts the DUT
  DutArguments named = Dut("listen:::1:4600,token=/run/user/1000/dut_token");
  named.can = "socketcan:can0";
  const DutChoice chosen = ParseDutChoice(named).value();
  EXPECT_EQ(chosen.process.listen_address, "::1");
  EXPECT_EQ(chosen.process.token_file, "/run/user/1000/dut_token");
  EXPECT_EQ(chosen.process.can_uri, "socketcan:can0");
}

TEST(DutChoiceTest, ABadListenWordIsRefusedByName) {
  EXPECT_EQ(ErrorOf(Dut("listen:4600")),
            "--dut \"listen:4600\": needs an address and a port "
            "(listen:ADDRESS:PORT[,token=FILE])");
  for (const char* port : {"0", "65535", "http", ""}) {
    EXPECT_THAT(ErrorOf(Dut((std::string("listen:127.0.0.1:") + port).c_str())),
                HasSubstr("is not a whole number from 1 to 65534"))
        << port;
  }
  EXPECT_THAT(ErrorOf(Dut("listen:127.0.0.1:4600,tok=x")), HasSubstr("unknown \"tok=x\""));
  EXPECT_THAT(ErrorOf(Dut("listen:127.0.0.1:4600,token=")), HasSubstr("unknown \"token=\""));
  DutArguments link = Dut("listen:127.0.0.1:4600");
  link.link = "shm";  // a DUT that dials in does so over TCP
  EXPECT_EQ(ErrorOf(link), "--dut-link needs --dut process or exec:");
}

TEST(DutChoiceTest, TheLineLinkIsForAProgramThatDialsTheRig) {
  DutArguments exec = Dut("exec:./my_dut,--gain,2");
  exec.link = "line";
  const DutChoice started = ParseDutChoice(exec).value();
  EXPECT_TRUE(started.line);
  EXPECT_EQ(started.dialed.program, "./my_dut");
  EXPECT_EQ(started.dialed.program_args, (std::vector<std::string>{"--gain", "2"}));
  EXPECT_EQ(started.serial.start_timeout_s, SerialDutOptions().start_timeout_s);

  DutArguments listen = Dut("listen:0.0.0.0:4600,token=dut_token");
  listen.link = "line";
  listen.timeout_s = "3";
  const DutChoice dialled = ParseDutChoice(listen).value();
  EXPECT_TRUE(dialled.line);
  EXPECT_FALSE(dialled.dialed.program);
  EXPECT_EQ(dialled.dialed.address, "0.0.0.0");
  EXPECT_EQ(dialled.dialed.port, 4600);
  EXPECT_EQ(dialled.dialed.token_file, "dut_token");
  EXPECT_EQ(dialled.serial.start_timeout_s, 60);  // a person starts the DUT
  EXPECT_EQ(dialled.serial.answer_timeout_s, 3);

  for (const char* word : {"process", "qemu", "serial:/dev/ttyACM0"}) {
    DutArguments other = Dut(word);
    other.link = "line";
    EXPECT_EQ(ErrorOf(other), "--dut-link line needs --dut exec: or listen:") << word;
  }
  DutArguments can = exec;
  can.can = "socketcan:can0";  // the tactile frames ride the bridge line
  EXPECT_EQ(ErrorOf(can), "--can does not go with --dut-link line");
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
  EXPECT_EQ(ErrorOf(timeout),
            "--dut-timeout-s needs --dut process, exec:, listen:, qemu, serial:, mavlink-emu, "
            "px4-sitl, mavlink-emu-hitl or px4-hitl:");
  DutArguments link = Dut("qemu");
  link.link = "tcp";
  EXPECT_EQ(ErrorOf(link), "--dut-link needs --dut process or exec:");
  DutArguments can = Dut("qemu");
  can.can = "socketcan:can0";
  EXPECT_EQ(ErrorOf(can), "--can socketcan:can0 needs --dut process, exec: or serial:");
}

TEST(DutChoiceTest, ABoardOnSerialDevicesMayReadItsSensorsOnItsOwnCanPort) {
  DutArguments board = Dut("serial:/dev/ttyACM0");
  board.can = "socketcan:can0";
  EXPECT_EQ(ParseDutChoice(board).value().port.can_uri, "socketcan:can0");
  EXPECT_TRUE(ParseDutChoice(Dut("serial:/dev/ttyACM0")).value().port.can_uri.empty());
  board.can = "emulated";
  EXPECT_THAT(ErrorOf(board), HasSubstr("--can: "));
}

TEST(DutChoiceTest, BadValuesNameTheirOption) {
  DutArguments link = Dut("process");
  link.link = "pipe";
  EXPECT_EQ(ErrorOf(link), "--dut-link \"pipe\": expected shm, tcp or line");
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

TEST(DutChoiceTest, Px4SitlIsWaitedForOnPx4sPorts) {
  auto choice = ParseDutChoice(Dut("px4-sitl"));
  ASSERT_TRUE(choice.ok()) << choice.error().message;
  EXPECT_EQ(choice.value().kind, DutKind::kPx4Sitl);
  const MavlinkDutOptions& link = choice.value().mavlink.link;
  EXPECT_FALSE(link.start_stand_in);
  EXPECT_TRUE(link.first_answers_late);
  EXPECT_EQ(link.sim_port, 4560);
  EXPECT_EQ(link.api_port, 14540);
  EXPECT_EQ(link.start_timeout_s, 60);
  choice = ParseDutChoice(Dut("px4-sitl:4561"));
  ASSERT_TRUE(choice.ok());
  EXPECT_EQ(choice.value().mavlink.link.sim_port, 4561);
  EXPECT_THAT(ErrorOf(Dut("px4-sitl:x")), HasSubstr("port \"x\" is not a whole number"));
  EXPECT_FALSE(MakeDutFactory(choice.value(), /*realtime=*/true).ok());
}

TEST(DutChoiceTest, Px4HitlIsABoardOnItsSerialPortInRealTime) {
  auto choice = ParseDutChoice(Dut("px4-hitl:/dev/ttyACM0"));
  ASSERT_TRUE(choice.ok()) << choice.error().message;
  EXPECT_EQ(choice.value().kind, DutKind::kPx4Hitl);
  EXPECT_STREQ(DutKindName(choice.value().kind), "px4-hitl");
  const MavlinkDutOptions& link = choice.value().mavlink.link;
  EXPECT_TRUE(link.hitl);
  EXPECT_FALSE(link.start_stand_in);
  EXPECT_EQ(link.serial_device, "/dev/ttyACM0");
  EXPECT_EQ(link.baud, 921600u);
  choice = ParseDutChoice(Dut("px4-hitl:/dev/ttyUSB1,baud=460800"));
  ASSERT_TRUE(choice.ok()) << choice.error().message;
  EXPECT_EQ(choice.value().mavlink.link.baud, 460800u);
  EXPECT_THAT(ErrorOf(Dut("px4-hitl:/dev/ttyUSB1,baud=57600")), HasSubstr("too slow for HITL"));
  EXPECT_THAT(ErrorOf(Dut("px4-hitl:")), HasSubstr("no device"));
  EXPECT_THAT(ErrorOf(Dut("px4-hitl:/dev/ttyUSB1,speed=1")), HasSubstr("unknown option"));
  const auto lockstep = MakeDutFactory(choice.value(), /*realtime=*/false);
  ASSERT_FALSE(lockstep.ok());
  EXPECT_THAT(lockstep.error().message, HasSubstr("real time only"));
  EXPECT_TRUE(MakeDutFactory(choice.value(), /*realtime=*/true).ok());
  choice = ParseDutChoice(Dut("mavlink-emu-hitl"));
  ASSERT_TRUE(choice.ok()) << choice.error().message;
  EXPECT_TRUE(choice.value().mavlink.link.hitl);
  EXPECT_TRUE(choice.value().mavlink.link.start_stand_in);
}

TEST(MakeDutFactoryTest, MavlinkIsLockstepOnlyAndTakesTheWatchdog) {
  DutArguments arguments = Dut("mavlink-emu");
  arguments.timeout_s = "2.5";
  const auto choice = ParseDutChoice(arguments);
  ASSERT_TRUE(choice.ok()) << choice.error().message;
  EXPECT_EQ(choice.value().kind, DutKind::kMavlinkEmu);
  EXPECT_STREQ(DutKindName(choice.value().kind), "mavlink-emu");
  EXPECT_EQ(choice.value().mavlink.session.answer_timeout_s, 2.5);
  EXPECT_TRUE(MakeDutFactory(choice.value(), false).ok());
  const auto realtime = MakeDutFactory(choice.value(), true);
  ASSERT_FALSE(realtime.ok());
  EXPECT_THAT(realtime.error().message, HasSubstr("lockstep only"));
}

}  // namespace
}  // namespace hilrig::host
