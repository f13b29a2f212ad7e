// Two trace.csv streams compared signal by signal: the largest difference and the first time
// beyond tolerance, NaN against a number, columns one side lacks, times that part, and traces that
// cannot be read, which end the comparison with a problem instead of a number.
#include "host/compare/trace_difference.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace hilrig::host {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

proto::CompareTolerances Tolerances() {
  proto::CompareTolerances tolerances;
  tolerances.set_trace_abs(1e-6);
  tolerances.set_trace_rel(0);
  return tolerances;
}

proto::TraceComparison Compare(const std::string& base, const std::string& candidate) {
  std::istringstream base_in(base);
  std::istringstream candidate_in(candidate);
  return CompareTraces(base_in, candidate_in, Tolerances());
}

const std::string kBase =
    "time_s,x_m,force_n\n"
    "0.01,1,0.5\n"
    "0.02,1,0.5\n"
    "0.03,1,0.5\n";

TEST(CompareTracesTest, IdenticalTracesDifferNowhere) {
  const auto comparison = Compare(kBase, kBase);
  EXPECT_TRUE(comparison.compared());
  EXPECT_EQ(comparison.rows_compared(), 3u);
  EXPECT_EQ(comparison.signals_compared(), 2u);
  EXPECT_EQ(comparison.difference_size(), 0);
  EXPECT_EQ(comparison.problem(), "");
}

TEST(CompareTracesTest, FindsTheLargestDifferenceAndTheFirstTimeBeyondTolerance) {
  const auto comparison = Compare(kBase,
                                  "time_s,x_m,force_n\n"
                                  "0.01,1.0000001,0.5\n"
                                  "0.02,1.0000001,0.7\n"
                                  "0.03,1.0000005,0.4\n");
  ASSERT_EQ(comparison.difference_size(), 2);
  const auto& force = comparison.difference(0);  // diverges first
  EXPECT_EQ(force.signal(), "force_n");
  EXPECT_DOUBLE_EQ(force.diverges_at_s(), 0.02);
  EXPECT_NEAR(force.max_abs_difference(), 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(force.max_at_s(), 0.02);
  const auto& x = comparison.difference(1);  // differs, within 1e-6
  EXPECT_EQ(x.signal(), "x_m");
  EXPECT_FALSE(x.has_diverges_at_s());
  EXPECT_NEAR(x.max_abs_difference(), 5e-7, 1e-12);
  EXPECT_DOUBLE_EQ(x.max_at_s(), 0.03);
}

TEST(CompareTracesTest, ANaNAgainstANumberDivergesTwoNaNsDoNot) {
  const auto comparison =
      Compare("time_s,a,b\n0.01,nan,nan\n0.02,1,1\n", "time_s,a,b\n0.01,nan,2\n0.02,1,1\n");
  ASSERT_EQ(comparison.difference_size(), 1);
  EXPECT_EQ(comparison.difference(0).signal(), "b");
  EXPECT_TRUE(std::isinf(comparison.difference(0).max_abs_difference()));
  EXPECT_DOUBLE_EQ(comparison.difference(0).diverges_at_s(), 0.01);
}

TEST(CompareTracesTest, MatchesColumnsByNameAndListsTheOnesOneSideLacks) {
  const auto comparison =
      Compare(kBase, "time_s,force_n,z_m\n0.01,0.5,3\n0.02,0.5,3\n0.03,0.5,3\n");
  EXPECT_EQ(comparison.signals_compared(), 1u);
  EXPECT_EQ(comparison.difference_size(), 0);
  EXPECT_THAT(comparison.only_in_base(), ElementsAre("x_m"));
  EXPECT_THAT(comparison.only_in_candidate(), ElementsAre("z_m"));
}

TEST(CompareTracesTest, StopsWhereTheTimesPartAndCountsEveryRow) {
  const auto comparison = Compare(kBase,
                                  "time_s,x_m,force_n\n"
                                  "0.01,1,0.5\n"
                                  "0.025,1,0.5\n"
                                  "0.03,1,0.5\n"
                                  "0.04,1,0.5\n");
  EXPECT_EQ(comparison.rows_compared(), 1u);
  EXPECT_DOUBLE_EQ(comparison.times_part_at_s(), 0.02);
  EXPECT_EQ(comparison.base_rows(), 3u);
  EXPECT_EQ(comparison.candidate_rows(), 4u);
}

TEST(CompareTracesTest, AShorterTraceIsComparedOverTheRowsBothHave) {
  const auto comparison = Compare(kBase, "time_s,x_m,force_n\n0.01,1,0.5\n");
  EXPECT_EQ(comparison.rows_compared(), 1u);
  EXPECT_EQ(comparison.base_rows(), 3u);
  EXPECT_EQ(comparison.candidate_rows(), 1u);
  EXPECT_FALSE(comparison.has_times_part_at_s());
}

TEST(CompareTracesTest, AnUnreadableTraceIsAProblemNotANumber) {
  const auto no_header = Compare("", kBase);
  EXPECT_FALSE(no_header.compared());
  EXPECT_THAT(no_header.problem(), HasSubstr("the base trace has no header row"));
  const auto no_time = Compare(kBase, "x_m,force_n\n1,2\n");
  EXPECT_FALSE(no_time.compared());
  EXPECT_THAT(no_time.problem(), HasSubstr("candidate trace's first column is not time_s"));
  const auto garbage = Compare(kBase, "time_s,x_m,force_n\n0.01,1,0.5\n0.02,1,zz\n0.03,1,0.5\n");
  EXPECT_TRUE(garbage.compared());
  EXPECT_EQ(garbage.rows_compared(), 1u);
  EXPECT_THAT(garbage.problem(), HasSubstr("the candidate trace's line 3 is not 3 numbers"));
  const auto narrow = Compare("time_s,x_m,force_n\n0.01,1\n", kBase);
  EXPECT_EQ(narrow.rows_compared(), 0u);
  EXPECT_THAT(narrow.problem(), HasSubstr("the base trace's line 2 is not 3 numbers"));
}

// A tolerance relative to an infinity allows anything; a value that turns infinite where the
// other side stays finite parts the traces all the same.
TEST(CompareTracesTest, AnInfinityAgainstANumberDivergesEvenWithARelativeTolerance) {
  std::istringstream base("time_s,a,b\n0.01,1,inf\n0.02,1,1\n");
  std::istringstream candidate("time_s,a,b\n0.01,inf,inf\n0.02,1,-inf\n");
  proto::CompareTolerances loose;
  loose.set_trace_abs(1e-6);
  loose.set_trace_rel(0.5);
  const auto comparison = CompareTraces(base, candidate, loose);
  ASSERT_EQ(comparison.difference_size(), 2);
  for (const auto& difference : comparison.difference()) {
    EXPECT_TRUE(std::isinf(difference.max_abs_difference())) << difference.signal();
    EXPECT_TRUE(difference.has_diverges_at_s()) << difference.signal();
  }
  EXPECT_DOUBLE_EQ(comparison.difference(0).diverges_at_s(), 0.01);  // a
  EXPECT_DOUBLE_EQ(comparison.difference(1).diverges_at_s(), 0.02);  // b: +inf against -inf
}

// A line without an end (a file of one endless line, /dev/zero behind a name) is never held
// whole: the comparison stops there with a problem.
TEST(CompareTracesTest, ALineFarLongerThanARowEndsTheComparison) {
  const auto comparison = Compare(kBase, "time_s,x_m,force_n\n" + std::string(1 << 20, '0'));
  EXPECT_EQ(comparison.rows_compared(), 0u);
  EXPECT_THAT(comparison.problem(), HasSubstr("the candidate trace's line 2 is longer than 65536"));
}

}  // namespace
}  // namespace hilrig::host
