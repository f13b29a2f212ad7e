// Where dut_emu finds the link token it proves to the runner: a file for a DUT started by hand,
// else the environment the runner gives the dut_emu it starts.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "dut_emu/dut_emu_server.h"
#include "tests/support/test_files.h"
#include "tests/support/test_paths.h"

namespace hilrig::dut_emu {
namespace {

constexpr const char* kHex = "00112233445566778899aabbccddeeff";

TEST(LoadLinkTokenTest, TakesTheEnvironmentValue) {
  EXPECT_EQ(LoadLinkToken({}, kHex).value().Hex(), kHex);
}

TEST(LoadLinkTokenTest, TokenFileComesFirst) {
  DutEmuOptions options;
  options.token_file = (host::FreshTestDir("dut_emu_token_") / "token").string();
  std::ofstream(options.token_file) << kHex << "\n";
  EXPECT_EQ(LoadLinkToken(options, "ffffffffffffffffffffffffffffffff").value().Hex(), kHex);
}

TEST(LoadLinkTokenTest, MissingTokenSaysWhereToPutIt) {
  const auto token = LoadLinkToken({}, nullptr);
  ASSERT_FALSE(token.ok());
  EXPECT_EQ(token.error().message,
            "no link token: pass --token-file PATH or set HILRIG_LINK_TOKEN (the runner sets it "
            "for the dut_emu it starts)");
}

TEST(LoadLinkTokenTest, MalformedTokenNamesItsSourceNotItsValue) {
  const auto from_environment = LoadLinkToken({}, "hunter2");
  ASSERT_FALSE(from_environment.ok());
  EXPECT_EQ(from_environment.error().message.rfind("HILRIG_LINK_TOKEN: ", 0), 0u);
  EXPECT_EQ(from_environment.error().message.find("hunter2"), std::string::npos);
  DutEmuOptions options;
  options.token_file = "/nonexistent/token";
  EXPECT_EQ(LoadLinkToken(options, kHex).error().message,
            "link token file /nonexistent/token: No such file or directory");
}

TEST(DutEmuMainTest, WithoutATokenItExitsWithAUsageError) {
  const auto err = host::FreshTestDir("dut_emu_token_") / "err";
  const std::string command = "env -u HILRIG_LINK_TOKEN " + ::hilrig::test_support::BinDir() +
                              "/dut_emu --link 127.0.0.1:9 --can udp:30000 2> " + err.string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), kExitUsage);
  EXPECT_NE(host::ReadFile(err).find("dut_emu: no link token: pass --token-file PATH"),
            std::string::npos)
      << host::ReadFile(err);
}

}  // namespace
}  // namespace hilrig::dut_emu
