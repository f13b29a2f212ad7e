#include "host/report/xml_text.h"

#include <gtest/gtest.h>

#include <string>

namespace hilrig::host {
namespace {

TEST(EscapeXmlTextTest, EscapesTheFiveSpecialCharacters) {
  EXPECT_EQ(EscapeXmlText("a&b<c>d\"e'f"), "a&amp;b&lt;c&gt;d&quot;e&apos;f");
}

TEST(EscapeXmlTextTest, ReplacesControlCharactersButKeepsWhiteSpace) {
  EXPECT_EQ(EscapeXmlText(std::string("a\x01"
                                      "b\tc\nd\x7f")),
            "a?b\tc\nd?");
}

TEST(EscapeXmlTextTest, LeavesUtf8Alone) {
  EXPECT_EQ(EscapeXmlText("0.25\u20130.65 N"), "0.25\u20130.65 N");
}

}  // namespace
}  // namespace hilrig::host
