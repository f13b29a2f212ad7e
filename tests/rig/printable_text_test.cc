// Text from outside the rig made safe for a terminal line or a script's comment: control
// characters shown as escapes, in a string and through a stream buffer, whatever the write's
// boundaries.
#include "rig/printable_text.h"

#include <gtest/gtest.h>

#include <ostream>
#include <sstream>

namespace hilrig::rig {
namespace {

TEST(PrintableTextTest, EscapesControlCharactersAndKeepsTheRest) {
  EXPECT_EQ(PrintableText("board stm32 \xc3\xa9t\xc3\xa9"), "board stm32 \xc3\xa9t\xc3\xa9");
  EXPECT_EQ(PrintableText("a\nb\r\tc"), "a\\nb\\r\\tc");
  EXPECT_EQ(PrintableText("red\x1b[31m\x7f"), "red\\x1b[31m\\x7f");
  EXPECT_EQ(PrintableText("csi\xc2\x9b"
                          "2J"),
            "csi\\xc2\\x9b2J");  // a C1 control in UTF-8
  EXPECT_EQ(PrintableText(std::string("nul\0", 4)), "nul\\x00");
  EXPECT_TRUE(IsPrintableText("ok \xc2\xa0 fine"));  // U+00A0 is no control
  EXPECT_FALSE(IsPrintableText("bell\a"));
  EXPECT_FALSE(IsPrintableText("\xc2\x85"));
}

// The stream keeps line breaks and tabs (terminal output is lines) and catches a C1 control split
// across two writes.
TEST(PrintableStreamBufTest, PassesLinesAndEscapesWhatDrivesATerminal) {
  std::stringbuf target;
  PrintableStreamBuf printable(&target);
  std::ostream out(&printable);
  out << "dut failed: \x1b]0;owned\x07\tname\n";
  out << "split \xc2";
  out << "\x9b"
      << "end \xc2";
  out.flush();
  EXPECT_EQ(target.str(), "dut failed: \\x1b]0;owned\\x07\tname\nsplit \\xc2\\x9bend \xc2");
  out << 'x' << '\r';
  EXPECT_EQ(target.str().substr(target.str().size() - 3), "x\\r");
}

}  // namespace
}  // namespace hilrig::rig
