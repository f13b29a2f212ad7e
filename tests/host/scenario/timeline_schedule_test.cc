// The timeline as a run reads it: the cursor over a time-sorted list and the tabulated sums of
// interval events give what a scan of every entry would, and a run's worth of ticks steps over
// each entry once however many ticks there are.
#include "host/scenario/timeline_schedule.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace hilrig::host {
namespace {

using Schedule = IntervalSumSchedule<Eigen::Vector3d>;

// What the schedule stands for: every interval that holds at `time_s`, added up from zero.
Eigen::Vector3d ScannedSum(const std::vector<Schedule::Interval>& intervals, double time_s) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Schedule::Interval& interval : intervals) {
    if (time_s >= interval.start_s && time_s < interval.end_s) sum += interval.value;
  }
  return sum;
}

TEST(TimelineScheduleTest, SumIsWhatHoldsAtEachTime) {
  const std::vector<Schedule::Interval> intervals = {
      {1.0, 2.0, {1, 0, 0}},    {1.5, 3.0, {0, 2, 0}},  // overlapping
      {2.0, 2.5, {0, 0, 4}},                            // starts as the first ends
      {4.0, 4.0, {8, 8, 8}},                            // empty: never holds
      {5.0, 4.5, {16, 0, 0}},                           // reversed: never holds
      {6.0, 7.0, {-0.0, 0, 0}},                         // a lone -0 reads as +0, as from zero
  };
  Schedule schedule(intervals);
  for (const double time_s : {0.0, 0.999, 1.0, 1.2, 1.5, 1.99, 2.0, 2.2, 2.5, 2.99, 3.0, 4.0, 4.7,
                              5.0, 6.0, 6.5, 7.0, 100.0}) {
    const Eigen::Vector3d expected = ScannedSum(intervals, time_s);
    const Eigen::Vector3d got = schedule.At(time_s);
    EXPECT_EQ(got, expected) << "at " << time_s << " s";
    EXPECT_EQ(std::signbit(got.x()), std::signbit(expected.x())) << "at " << time_s << " s";
  }
}

TEST(TimelineScheduleTest, AnEarlierTimeIsLookedUpAgain) {
  const std::vector<Schedule::Interval> intervals = {{1.0, 2.0, {1, 0, 0}}, {3.0, 4.0, {2, 0, 0}}};
  Schedule schedule(intervals);
  EXPECT_EQ(schedule.At(3.5).x(), 2);
  EXPECT_EQ(schedule.At(1.5).x(), 1);
  EXPECT_EQ(schedule.At(0.5).x(), 0);
  EXPECT_EQ(schedule.At(3.0).x(), 2);
}

TEST(TimelineScheduleTest, ScalarValuesSumToo) {
  IntervalSumSchedule<double> rates({{0.0, 2.0, 0.25}, {1.0, 3.0, 0.5}});
  EXPECT_EQ(rates.At(0.5), 0.25);
  EXPECT_EQ(rates.At(1.5), 0.75);
  EXPECT_EQ(rates.At(2.5), 0.5);
  EXPECT_EQ(rates.At(3.5), 0.0);
}

// 200 000 short disturbances over a 20 s run at 1 kHz: a scan per tick would look at 4e9 entries;
// the schedule steps over each of its pieces once, and agrees with the scan where it is checked.
TEST(TimelineScheduleTest, ARunStepsOverEachPieceOnceHoweverManyTicks) {
  constexpr int kIntervals = 200'000;
  constexpr std::int64_t kTicks = 20'000;
  std::vector<Schedule::Interval> intervals;
  for (int i = 0; i < kIntervals; ++i) {
    const double start_s = 20.0 * i / kIntervals;
    intervals.push_back({start_s, start_s + 0.01, {1e-3 * (i % 7), 0, 0}});
  }
  Schedule schedule(intervals);
  ASSERT_LE(schedule.piece_count(), 2u * kIntervals);
  for (std::int64_t tick = 0; tick <= kTicks; ++tick) {
    const double time_s = static_cast<double>(tick) / 1e3;
    const Eigen::Vector3d& sum = schedule.At(time_s);
    if (tick % 997 == 0) {
      EXPECT_NEAR(sum.x(), ScannedSum(intervals, time_s).x(), 1e-12);
    }
  }
  EXPECT_LE(schedule.pieces_stepped(), schedule.piece_count());
}

TEST(TimelineScheduleTest, CursorCountsTheEntriesAtOrBeforeATime) {
  const std::vector<double> times_s = {0.5, 1.0, 1.0, 2.0};
  const auto time_of = [&](std::size_t i) { return times_s[i]; };
  TimeCursor cursor;
  EXPECT_EQ(cursor.Seek(0.0, times_s.size(), time_of), 0u);
  EXPECT_EQ(cursor.Seek(1.0, times_s.size(), time_of), 3u);
  EXPECT_EQ(cursor.Seek(1.0, times_s.size(), time_of), 3u);
  EXPECT_EQ(cursor.Seek(9.0, times_s.size(), time_of), 4u);
  EXPECT_EQ(cursor.steps(), 4u);
  EXPECT_EQ(cursor.Seek(0.7, times_s.size(), time_of), 1u);
}

}  // namespace
}  // namespace hilrig::host
