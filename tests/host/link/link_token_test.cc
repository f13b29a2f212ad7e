#include "host/link/link_token.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <string>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

constexpr const char* kHex = "00112233445566778899aabbccddeeff";

TEST(LinkTokenTest, NewTokensDifferAndRoundTripThroughTheirText) {
  const LinkToken first = NewLinkToken().value();
  const LinkToken second = NewLinkToken().value();
  EXPECT_NE(first.Hex(), second.Hex());
  EXPECT_EQ(first.Hex().size(), 32u);
  EXPECT_EQ(ParseLinkToken(first.Hex()).value().bytes, first.bytes);
}

TEST(LinkTokenTest, ParsesHexWithATrailingNewline) {
  const LinkToken token = ParseLinkToken(std::string(kHex) + "\n").value();
  EXPECT_EQ(token.bytes[0], 0x00);
  EXPECT_EQ(token.bytes[15], 0xff);
  EXPECT_EQ(ParseLinkToken("00112233445566778899AABBCCDDEEFF").value().bytes, token.bytes);
}

TEST(LinkTokenTest, RefusesTextThatIsNoTokenWithoutRepeatingIt) {
  for (const std::string text :
       {"", "0011", "00112233445566778899aabbccddeeff00", "secretsecretsecretsecretsecret!!"}) {
    const auto token = ParseLinkToken(text);
    ASSERT_FALSE(token.ok()) << text;
    if (!text.empty()) {
      EXPECT_EQ(token.error().message.find(text), std::string::npos);
    }
  }
}

TEST(LinkTokenTest, ProofMustBeTheWholeToken) {
  const LinkToken token = ParseLinkToken(kHex).value();
  EXPECT_TRUE(ProvesLinkToken(token, token.Proof()));
  std::string flipped = token.Proof();
  flipped[15] ^= 1;
  EXPECT_FALSE(ProvesLinkToken(token, flipped));
  EXPECT_FALSE(ProvesLinkToken(token, token.Proof().substr(0, 15)));
  EXPECT_FALSE(ProvesLinkToken(token, token.Proof() + "x"));
  EXPECT_FALSE(ProvesLinkToken(token, ""));
}

TEST(LinkTokenFileTest, ReadsTheTokenFromARegularFile) {
  const auto path = FreshTestDir("link_token_") / "token";
  std::ofstream(path) << kHex << "\n";
  EXPECT_EQ(ReadLinkTokenFile(path.string()).value().Hex(), kHex);
}

TEST(LinkTokenFileTest, ErrorsNameThePathAndTheCause) {
  const auto dir = FreshTestDir("link_token_");
  const auto missing = ReadLinkTokenFile((dir / "missing").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message,
            "link token file " + (dir / "missing").string() + ": No such file or directory");
  const auto folder = ReadLinkTokenFile(dir.string());
  ASSERT_FALSE(folder.ok());
  EXPECT_EQ(folder.error().message, "link token file " + dir.string() + ": not a regular file");
  std::ofstream(dir / "big") << std::string(4096, 'a');
  const auto big = ReadLinkTokenFile((dir / "big").string());
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().message.find("larger than 256 bytes"), std::string::npos);
  std::ofstream(dir / "wrong") << "not a token at all";
  const auto wrong = ReadLinkTokenFile((dir / "wrong").string());
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find((dir / "wrong").string()), std::string::npos);
  EXPECT_EQ(wrong.error().message.find("not a token at all"), std::string::npos);
}

TEST(LinkTokenFileTest, FifoIsRefusedWithoutBlocking) {
  const auto fifo = FreshTestDir("link_token_") / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto token = ReadLinkTokenFile(fifo.string());
  ASSERT_FALSE(token.ok());
  EXPECT_EQ(token.error().message, "link token file " + fifo.string() + ": not a regular file");
}

TEST(LinkTokenFileTest, DeviceIsRefused) { EXPECT_FALSE(ReadLinkTokenFile("/dev/zero").ok()); }

// The user's own token file is read, never replaced; one that is no token is refused by name.
TEST(LinkTokenFileTest, AMissingFileGetsANewOwnerOnlyTokenAndAnExistingOneIsRead) {
  const auto dir = FreshTestDir("link_token_");
  const std::string path = (dir / "token").string();
  bool created = false;
  const LinkToken first = ReadOrCreateLinkTokenFile(path, &created).value();
  EXPECT_TRUE(created);
  struct stat status {};
  ASSERT_EQ(::stat(path.c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 0777, 0600u);
  EXPECT_EQ(ReadLinkTokenFile(path).value().Hex(), first.Hex());
  const LinkToken again = ReadOrCreateLinkTokenFile(path, &created).value();
  EXPECT_FALSE(created);
  EXPECT_EQ(again.Hex(), first.Hex());
  std::ofstream(path) << "not a token\n";
  const auto bad = ReadOrCreateLinkTokenFile(path, &created);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("link token file " + path), std::string::npos);
}

}  // namespace
}  // namespace hilrig::host
