// The sizes a spec may have: names, free text and the spec's lists are bounded and refused with a
// located message that gives the size, never the text; a name holds only characters that read as
// text in junit.xml, the plots and the terminal.
#include "host/scenario/spec_limits.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "host/scenario/scenario_loader.h"
#include "host/scenario/scenario_validation.h"

namespace hilrig::host {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string Spec(const std::string& name, const std::string& more = "") {
  return "name: \"" + name + "\"\nsimulation { duration_s: 1 }\n" + more +
         "envelopes { name: \"alt\" signal: ALTITUDE_M upper: 2 }\n";
}

std::string ErrorOf(const std::string& text) {
  const auto result = ParseScenario(text, "spec.textproto");
  EXPECT_FALSE(result.ok()) << "expected an error";
  return result.ok() ? std::string() : result.error().message;
}

bool Accepted(const std::string& text) {
  const auto result = ParseScenario(text, "spec.textproto");
  EXPECT_TRUE(result.ok()) << result.error().message;
  return result.ok();
}

TEST(SpecLimitsTest, ALongScenarioNameIsRefusedWithItsSizeNotItsText) {
  const std::string name(10 * 1024, 'n');
  const std::string error = ErrorOf(Spec(name));
  EXPECT_EQ(error, "spec.textproto:1:1: name: a name may hold at most 200 characters, got 10240");
  EXPECT_TRUE(Accepted(Spec(std::string(kMaxNameChars, 'n'))));
}

TEST(SpecLimitsTest, ALongEnvelopeNameIsRefusedAtTheEnvelope) {
  const std::string error = ErrorOf(Spec(
      "s", "envelopes {\n  name: \"" + std::string(201, 'e') + "\" signal: TILT_DEG upper: 1 }\n"));
  EXPECT_THAT(error, HasSubstr("spec.textproto:4:3: envelopes[0].name: a name may hold at most "
                               "200 characters, got 201"));
}

// The other strings are free text, bounded; a checked one (a fixture) is not quoted back either.
TEST(SpecLimitsTest, LongFreeTextIsRefusedWithoutBeingQuoted) {
  const std::string description = "description: \"" + std::string(4097, 'd') + "\"\n";
  EXPECT_THAT(ErrorOf(Spec("s", description)),
              HasSubstr("spec.textproto:3:1: description: must be at most 4096 bytes, got 4097"));
  EXPECT_TRUE(Accepted(Spec("s", "description: \"" + std::string(4096, 'd') + "\"\n")));
  const std::string error =
      ErrorOf(Spec("s", "object { fixture: \"" + std::string(5000, 'f') + "\" }\n"));
  EXPECT_THAT(error, HasSubstr("object.fixture: must be at most 4096 bytes, got 5000"));
  EXPECT_THAT(error, Not(HasSubstr("ffff")));
}

TEST(SpecLimitsTest, NamesHoldOnlyTextCharacters) {
  EXPECT_TRUE(Accepted(Spec("grasp (egg) 1.5-2: x+y_z")));
  // A newline, an escape sequence, a quote, markup, non-ASCII and invalid UTF-8.
  for (const std::string name :
       {"a\\nb", "red\\x1b[31m", "say \\\"hi\\\"", "<b>", "caf\\303\\251", "bad\\377", "a/b"}) {
    const std::string error = ErrorOf(Spec(name));
    EXPECT_THAT(error, HasSubstr("spec.textproto:1:1: name: character ")) << name;
    EXPECT_THAT(error, HasSubstr("is not a letter, digit, space or one of _ - . : + ( )")) << name;
  }
  EXPECT_THAT(ErrorOf(Spec("s", "envelopes { name: \"ti\\tlt\" signal: TILT_DEG upper: 1 }\n")),
              HasSubstr("envelopes[0].name: character 3 is not"));
}

// A path or other string with a control character would reach the terminal, the pages and the
// commands failing.txt gives to a shell: refused where the spec is validated. The description
// alone may hold line breaks and tabs.
TEST(SpecLimitsTest, StringsWithControlCharactersAreRefused) {
  const std::string injected =
      "models { tactile { enabled: true calibration_file: \"a\\ntouch /tmp/x\" } }\n";
  EXPECT_THAT(
      ErrorOf(Spec("s", injected)),
      HasSubstr("models.tactile.calibration_file: byte 2 starts a control character (\\n)"));
  EXPECT_THAT(ErrorOf(Spec("s", "object { fixture: \"egg\\x1b[2J\" }\n")),
              HasSubstr("object.fixture: byte 4 starts a control character (\\x1b)"));
  EXPECT_THAT(ErrorOf(Spec("s", "object { fixture: \"egg\\302\\233\" }\n")),
              HasSubstr("object.fixture: byte 4 starts a control character (\\xc2\\x9b)"));
  EXPECT_TRUE(Accepted(Spec("s", "description: \"line one\\n\\tline two\"\n")));
  EXPECT_THAT(ErrorOf(Spec("s", "description: \"bell\\a\"\n")),
              HasSubstr("description: byte 5 starts a control character (\\x07)"));
}

TEST(SpecLimitsTest, TimelinePastItsBoundIsOneProblemAtTheFirstEntryPastIt) {
  proto::Scenario spec;
  spec.set_name("long");
  spec.mutable_simulation()->set_duration_s(1);
  for (int i = 0; i <= kMaxTimelineEntries; ++i) spec.add_timeline()->set_at_s(2);  // each invalid
  const std::vector<FieldProblem> problems = ValidateScenario(spec);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].field_path, "timeline[100000]");
  EXPECT_EQ(problems[0].message,
            "is past the bound of 100000 timeline entries (the spec has 100001)");
}

TEST(SpecLimitsTest, EnvelopesPastTheirBoundAreRefused) {
  proto::Scenario spec;
  spec.set_name("many");
  spec.mutable_simulation()->set_duration_s(1);
  for (int i = 0; i <= kMaxEnvelopes; ++i) {
    proto::Envelope& envelope = *spec.add_envelopes();
    envelope.set_name(std::string("e").append(std::to_string(i)));
    envelope.set_signal(proto::TILT_DEG);
    envelope.set_upper(1);
  }
  const std::vector<FieldProblem> problems = ValidateScenario(spec);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].field_path, "envelopes[1000]");
  spec.mutable_envelopes()->RemoveLast();
  EXPECT_TRUE(ValidateScenario(spec).empty());
}

// Each mean window keeps every trace sample it spans, at most the run's: in a 6000 s run at
// 100 Hz, windows of 4000 s and 1000 s are within the bound, and one more of 9000 s (the whole
// run) makes 1.1e6 samples, past it.
TEST(SpecLimitsTest, MeanWindowsPastTheirBoundAreRefusedAtTheEnvelopeThatPassesIt) {
  const std::string spec = R"(name: "s"
simulation { duration_s: 6000 }
envelopes { name: "a" signal: TILT_DEG upper: 1 mean_over_s: 4000 }
envelopes { name: "b" signal: TILT_DEG upper: 1 mean_over_s: 1000 }
)";
  EXPECT_TRUE(Accepted(spec));
  EXPECT_THAT(ErrorOf(spec + "envelopes { name: \"c\" signal: TILT_DEG upper: 1\n"
                             "  mean_over_s: 9000 }\n"),
              HasSubstr("spec.textproto:6:3: envelopes[2].mean_over_s: the mean windows up to "
                        "here hold 1.1e+06 trace samples, past the bound of 1e+06"));
}

}  // namespace
}  // namespace hilrig::host
