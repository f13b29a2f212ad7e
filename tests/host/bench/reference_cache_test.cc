#include "host/bench/reference_cache.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace hilrig::host {
namespace {

CachedReference ThreeSamples() {
  CachedReference reference;
  reference.wall_s = 12.5;
  for (int i = 0; i < 3; ++i) {
    TraceSample sample;
    sample.time_s = 0.01 * (i + 1);
    sample.position_m = {0.1 * i, -0.2, 1.0 + 1e-17 * i};
    sample.grasp_force_n = 0.6 / 3.0 * i;
    sample.load_n = i == 2 ? std::numeric_limits<double>::quiet_NaN() : 0.5;
    reference.trace.Add(sample);
  }
  return reference;
}

TEST(ReferenceCacheTest, AnEntryReadsBackBitForBit) {
  const CachedReference reference = ThreeSamples();

  const auto parsed = ParseReference(SerializeReference(reference));

  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(parsed->wall_s, 12.5);
  ASSERT_EQ(parsed->trace.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(parsed->trace.time_s[i], reference.trace.time_s[i]);
    EXPECT_EQ(parsed->trace.position_m[i], reference.trace.position_m[i]);
    EXPECT_EQ(parsed->trace.grasp_force_n[i], reference.trace.grasp_force_n[i]);
  }
  EXPECT_TRUE(std::isnan(parsed->trace.load_n[2]));  // a signal the run did not have stays so
}

TEST(ReferenceCacheTest, TruncatedForeignOrPaddedBytesAreAMiss) {
  const std::string bytes = SerializeReference(ThreeSamples());

  EXPECT_FALSE(ParseReference(bytes.substr(0, bytes.size() - 1)).has_value());
  EXPECT_FALSE(ParseReference(bytes + "x").has_value());
  EXPECT_FALSE(ParseReference("not a reference at all, just text").has_value());
  EXPECT_FALSE(ParseReference("").has_value());
  std::string huge_count = bytes;
  huge_count[8] = '\xff';  // the sample count's low byte
  EXPECT_FALSE(ParseReference(huge_count).has_value());
}

TEST(ReferenceCacheTest, StoreThenLoadAndMissesForOtherKeysOrDamagedFiles) {
  const std::string dir = ::testing::TempDir() + "/reference_cache_test";
  std::filesystem::remove_all(dir);
  const ReferenceCache cache(dir + "/nested");

  ASSERT_TRUE(cache.Store("abc", ThreeSamples()).ok());
  const auto loaded = cache.Load("abc");
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->trace.size(), 3u);
  EXPECT_FALSE(cache.Load("abd").has_value());
  std::ofstream(dir + "/nested/abc.ref", std::ios::trunc) << "garbage";
  EXPECT_FALSE(cache.Load("abc").has_value());
  std::filesystem::remove_all(dir);
}

TEST(ReferenceCacheTest, TheKeyChangesWithSpecSeedCalibrationAndCode) {
  proto::Scenario spec;
  spec.set_name("scene");
  proto::Calibration calibration;
  const std::string base = ReferenceCacheKey(spec, 1, calibration, "code");
  EXPECT_EQ(base.size(), 16u);
  EXPECT_EQ(ReferenceCacheKey(spec, 1, calibration, "code"), base);

  proto::Scenario other_spec = spec;
  other_spec.mutable_simulation()->set_duration_s(3);
  proto::Calibration other_calibration;
  other_calibration.set_seed(5);
  EXPECT_NE(ReferenceCacheKey(other_spec, 1, calibration, "code"), base);
  EXPECT_NE(ReferenceCacheKey(spec, 2, calibration, "code"), base);
  EXPECT_NE(ReferenceCacheKey(spec, 1, other_calibration, "code"), base);
  EXPECT_NE(ReferenceCacheKey(spec, 1, std::nullopt, "code"), base);
  EXPECT_NE(ReferenceCacheKey(spec, 1, calibration, "code2"), base);
}

TEST(ReferenceCacheTest, TheExecutableHasAStableIdentity) {
  const auto first = ExecutableIdentity();
  const auto second = ExecutableIdentity();
  ASSERT_TRUE(first.ok() && second.ok());
  EXPECT_EQ(first.value(), second.value());
  EXPECT_EQ(first.value().size(), 16u);
}

}  // namespace
}  // namespace hilrig::host
