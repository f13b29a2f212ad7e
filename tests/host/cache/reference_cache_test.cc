#include "host/cache/reference_cache.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "tests/support/test_files.h"

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

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

  ASSERT_TRUE(parsed);
  const CachedReference& read = parsed.value();
  EXPECT_EQ(read.wall_s, 12.5);
  ASSERT_EQ(read.trace.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(read.trace.time_s[i], reference.trace.time_s[i]);
    EXPECT_EQ(read.trace.position_m[i], reference.trace.position_m[i]);
    EXPECT_EQ(read.trace.grasp_force_n[i], reference.trace.grasp_force_n[i]);
  }
  EXPECT_TRUE(std::isnan(read.trace.load_n[2]));  // a signal the run did not have stays so
}

TEST(ReferenceCacheTest, TruncatedForeignOrPaddedBytesAreAMiss) {
  const std::string bytes = SerializeReference(ThreeSamples());

  EXPECT_FALSE(ParseReference(bytes.substr(0, bytes.size() - 1)));
  EXPECT_FALSE(ParseReference(bytes + "x"));
  EXPECT_FALSE(ParseReference("not a reference at all, just text"));
  EXPECT_FALSE(ParseReference(""));
  std::string huge_count = bytes;
  huge_count[0] = '\xff';  // the sample count's low byte
  EXPECT_FALSE(ParseReference(huge_count));
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

// One byte changed in a stored value is a miss: it used to be compared against as the reference.
TEST(ReferenceCacheTest, AChangedByteIsAMiss) {
  const fs::path dir = FreshTestDir("reference_cache_");
  const ReferenceCache cache(dir.string());
  ASSERT_TRUE(cache.Store("0123456789abcdef", ThreeSamples()).ok());
  ASSERT_TRUE(cache.Load("0123456789abcdef").has_value());

  ChangeByteFromEnd(dir / "0123456789abcdef.ref", 17);  // the last sample's z, in its exponent

  EXPECT_FALSE(cache.Load("0123456789abcdef").has_value());
}

// Whole bytes that no completed run gives are a miss: time stamps that do not increase, a position
// or a wall time that is not finite.
TEST(ReferenceCacheTest, ATraceNoRunGivesIsAMiss) {
  const fs::path dir = FreshTestDir("reference_cache_");
  const ReferenceCache cache(dir.string());
  CachedReference backwards = ThreeSamples();
  backwards.trace.time_s[2] = backwards.trace.time_s[0];
  CachedReference lost = ThreeSamples();
  lost.trace.position_m[1].x() = std::numeric_limits<double>::quiet_NaN();
  CachedReference timeless = ThreeSamples();
  timeless.wall_s = -std::numeric_limits<double>::infinity();

  for (const CachedReference& refused : {backwards, lost, timeless}) {
    ASSERT_TRUE(cache.Store("0123456789abcdef", refused).ok());
    EXPECT_FALSE(cache.Load("0123456789abcdef").has_value());
  }
}

// A miss on an entry that is there is said, with the entry's path and the cause; an absent entry
// is a plain miss. A reference of another length than the scene's run gives is a miss too.
TEST(ReferenceCacheTest, AMissOnAnEntryThatIsThereIsSaid) {
  const fs::path dir = FreshTestDir("reference_cache_");
  std::ostringstream notes;
  const ReferenceCache cache(dir.string(), &notes);
  const std::string path = (dir / "0123456789abcdef.ref").string();

  EXPECT_FALSE(cache.Load("0123456789abcdef").has_value());
  EXPECT_EQ(notes.str(), "");
  ASSERT_TRUE(cache.Store("0123456789abcdef", ThreeSamples()).ok());
  EXPECT_TRUE(cache.Load("0123456789abcdef", 3).has_value());
  EXPECT_FALSE(cache.Load("0123456789abcdef", 4).has_value());
  EXPECT_NE(notes.str().find(path + ": 3 samples, the scene's run records 4"), std::string::npos)
      << notes.str();
  ChangeByteFromEnd(path, 17);
  EXPECT_FALSE(cache.Load("0123456789abcdef").has_value());
  EXPECT_NE(notes.str().find(path + ": the checksum does not match"), std::string::npos)
      << notes.str();
  fs::remove(path);
  fs::create_directory(path);
  EXPECT_FALSE(cache.Load("0123456789abcdef").has_value());
  EXPECT_NE(notes.str().find("cannot read " + path + ": a folder, not a regular file"),
            std::string::npos)
      << notes.str();
  auto stored = cache.Store("0123456789abcdef", ThreeSamples());
  ASSERT_FALSE(stored);
  EXPECT_NE(stored.error().message.find("cannot write " + path), std::string::npos);
}

// A folder that holds files of the user's (more *.ref files than the bound, files named like an
// entry that the cache did not write) loses none of them to a store: it used to remove every
// *.ref file past the 200 most recent.
TEST(ReferenceCacheTest, AStoreLeavesFilesTheCacheDidNotWrite) {
  const fs::path dir = FreshTestDir("reference_cache_");
  const std::vector<fs::path> users = PlantUserFiles(dir, ".ref", 250);
  const ReferenceCache cache(dir.string());

  ASSERT_TRUE(cache.Store("0123456789abcdef", ThreeSamples()).ok());

  for (const fs::path& user : users) EXPECT_TRUE(fs::exists(user)) << user;
}

// A writer that crashed leaves its temporary file beside the entry it was writing. A store
// removes those that are an hour older than the entry it just wrote, and no other file.
TEST(ReferenceCacheTest, AStoreRemovesOldTemporaryFilesOfItsOwnEntriesOnly) {
  const fs::path dir = FreshTestDir("reference_cache_");
  const fs::path old_temporary = dir / "fedcba9876543210.ref.tmp-00112233445566ff";
  const fs::path young_temporary = dir / "fedcba9876543210.ref.tmp-00112233445566ee";
  const fs::path foreign_temporary = dir / "scan.ref.tmp-00112233445566dd";
  for (const fs::path& file : {old_temporary, young_temporary, foreign_temporary}) {
    std::ofstream(file) << "half an entry";
  }
  for (const fs::path& file : {old_temporary, foreign_temporary}) {
    fs::last_write_time(file, fs::last_write_time(file) - std::chrono::minutes(61));
  }
  fs::last_write_time(young_temporary,
                      fs::last_write_time(young_temporary) - std::chrono::minutes(59));
  const ReferenceCache cache(dir.string());

  ASSERT_TRUE(cache.Store("0123456789abcdef", ThreeSamples()).ok());

  EXPECT_FALSE(fs::exists(old_temporary));
  EXPECT_TRUE(fs::exists(young_temporary)) << "a writer may still be at it";
  EXPECT_TRUE(fs::exists(foreign_temporary)) << "not the temporary file of an entry";
}

// An entry written as its run goes reads back sample by sample, as a stored one does, and is
// under its key only once committed.
TEST(ReferenceCacheTest, AnEntryWrittenAsItGoesIsReadBackSampleBySample) {
  const fs::path dir = FreshTestDir("reference_cache_");
  const ReferenceCache cache(dir.string());
  const CachedReference reference = ThreeSamples();
  auto writer = cache.Begin("0123456789abcdef");
  ASSERT_TRUE(writer) << writer.error().message;
  for (std::size_t i = 0; i < reference.trace.size(); ++i)
    writer.value().Add(reference.trace.At(i));
  ASSERT_TRUE(writer.value().Finish(reference.wall_s));
  EXPECT_FALSE(cache.Open("0123456789abcdef").has_value()) << "not committed yet";

  ASSERT_TRUE(cache.Commit(writer.value()));
  std::optional<ReferenceReader> reader = cache.Open("0123456789abcdef", 3);

  ASSERT_TRUE(reader.has_value());
  EXPECT_EQ(reader->size(), 3u);
  EXPECT_EQ(reader->wall_s(), 12.5);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<ComparedSample> sample = reader->Next();
    ASSERT_TRUE(sample.has_value());
    EXPECT_EQ(sample->time_s, reference.trace.time_s[i]);
    EXPECT_EQ(sample->position_m, reference.trace.position_m[i]);
  }
  EXPECT_FALSE(reader->Next().has_value());
  EXPECT_FALSE(reader->failure().has_value());
}

// A reference run that stopped short (Ctrl-C) drops its writer: nothing is left under the key
// and no file is left in the folder for a later run to trust.
TEST(ReferenceCacheTest, AWriterDroppedBeforeItsCommitLeavesNothing) {
  const fs::path dir = FreshTestDir("reference_cache_");
  const ReferenceCache cache(dir.string());
  {
    auto writer = cache.Begin("0123456789abcdef");
    ASSERT_TRUE(writer);
    writer.value().Add(ThreeSamples().trace.At(0));
  }

  EXPECT_FALSE(cache.Open("0123456789abcdef").has_value());
  EXPECT_TRUE(fs::is_empty(dir));
}

// A cut entry (a disk that filled, a copy that stopped) is a miss that says so, read whole or as
// it goes: never a shorter reference.
TEST(ReferenceCacheTest, ACutEntryIsAMissThatSaysSo) {
  const fs::path dir = FreshTestDir("reference_cache_");
  std::ostringstream notes;
  const ReferenceCache cache(dir.string(), &notes);
  ASSERT_TRUE(cache.Store("0123456789abcdef", ThreeSamples()).ok());
  const fs::path path = dir / "0123456789abcdef.ref";
  fs::resize_file(path, fs::file_size(path) - 48);

  EXPECT_FALSE(cache.Open("0123456789abcdef").has_value());
  EXPECT_FALSE(cache.Load("0123456789abcdef").has_value());
  EXPECT_NE(notes.str().find(path.string() + ": the content is not as long as the header says"),
            std::string::npos)
      << notes.str();
}

// Without a cache the reference is written to a temporary file that no folder shows.
TEST(ReferenceCacheTest, AnUnnamedWriterReadsBackWhatItWrote) {
  auto writer = ReferenceWriter::Unnamed();
  ASSERT_TRUE(writer) << writer.error().message;
  const CachedReference reference = ThreeSamples();
  for (std::size_t i = 0; i < reference.trace.size(); ++i)
    writer.value().Add(reference.trace.At(i));
  ASSERT_TRUE(writer.value().Finish(reference.wall_s));

  auto entry = writer.value().entry().Reader();
  ASSERT_TRUE(entry) << entry.error().message;
  auto reader = ReferenceReader::Open(std::move(entry).value(), 3);

  ASSERT_TRUE(reader) << reader.error().message;
  EXPECT_EQ(reader.value().wall_s(), 12.5);
  EXPECT_EQ(reader.value().Next()->time_s, 0.01);
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
