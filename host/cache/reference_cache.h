// A cache of reference traces, so that every `hilrig run` can report the error of its chosen
// fidelity against the reference without paying for the reference run each time (Dormand-Prince
// at 1e-10 with 8 plant steps per tick on a 64 x 64 tiled film costs ~25 s for balloon_grasp). A
// reference trace depends only on the reference spec, the seed, the DUT calibration and the code
// that ran it, so the key hashes all four: the spec and calibration as deterministic protobuf
// bytes, and the code as the bytes of the running executable (a rebuild is a new key). Entries
// are written to a temporary file and renamed, so a crash or Ctrl-C never leaves a half entry
// that a later run would read. An entry is checked against its checksum (cache_files.h) and as a
// trace a completed run gives (time stamps in order, finite positions, the scene's sample count):
// a damaged or foreign file is a miss, said, and the reference is run again; never numbers.
// An entry is also written as its reference runs (ReferenceWriter) and read a block of samples at
// a time (ReferenceReader), all of it checked in a first pass, so a run compared with its
// reference never holds either trace whole: memory does not grow with the simulated duration.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/cache/cache_files.h"
#include "host/trace/trace_capture.h"
#include "proto/calibration.pb.h"
#include "proto/scenario.pb.h"
#include "rig/result.h"

namespace hilrig::host {

// A reference run as the cache keeps it: its trace and how long it took to make.
struct CachedReference {
  CapturedTrace trace;
  double wall_s = 0;
};

// 64-bit FNV-1a over the bytes of the executable this process runs (/proc/self/exe), as 16 hex
// digits; an error when it cannot be read.
rig::Result<std::string> ExecutableIdentity();

// The cache key (16 hex digits) of a reference run.
std::string ReferenceCacheKey(const proto::Scenario& reference_spec, std::uint64_t seed,
                              const std::optional<proto::Calibration>& calibration,
                              const std::string& code_identity);

// The folder a run caches references in when not told: $HILRIG_REFERENCE_CACHE, else
// $XDG_CACHE_HOME/hilrig/reference, else $HOME/.cache/hilrig/reference, else
// ./hilrig_out/reference_cache.
std::string DefaultReferenceCacheDir();

// The byte form of an entry's content, and back; Parse refuses anything that is not exactly one
// whole trace (a count that does not match the size), or not one a completed run gives: time
// stamps that are not finite and increasing, a position that is not finite, a wall time that is
// not a finite, non-negative duration.
std::string SerializeReference(const CachedReference& reference);
rig::Result<CachedReference> ParseReference(const std::string& bytes);

// A reference entry read a sample at a time, in time order. Open checks it whole first (the
// checksum, then as a trace a completed run gives, as ParseReference does) and then reads it
// again a block of samples at a time.
class ReferenceReader {
 public:
  // `entry` as a reference of `expected_samples` samples (when given), or why it is not one.
  static rig::Result<ReferenceReader> Open(CacheEntryReader entry,
                                           std::optional<std::uint64_t> expected_samples);

  std::uint64_t size() const { return count_; }
  double wall_s() const { return wall_s_; }
  // The next sample; nullopt past the last, or when the file can no longer be read or no longer
  // holds what was checked (failure() then says why).
  std::optional<ComparedSample> Next();
  const std::optional<rig::Error>& failure() const { return failure_; }

 private:
  ReferenceReader(CacheEntryReader entry, std::uint64_t count, double wall_s);
  // Every sample in order, checked: an error naming the first that no completed run gives.
  rig::Result<void> CheckAll();
  // The sample at `index` (< count_), reading its block when needed; nullopt with failure_ set.
  std::optional<ComparedSample> ReadSample(std::uint64_t index);

  CacheEntryReader entry_;
  std::uint64_t count_ = 0;
  double wall_s_ = 0;
  std::uint64_t next_ = 0;
  double last_time_s_ = 0;
  std::vector<char> block_;
  std::uint64_t block_first_ = 0, block_count_ = 0;
  std::optional<rig::Error> failure_;
};

// A reference entry written as its run goes: its samples in order, then its count and wall time.
class ReferenceWriter {
 public:
  explicit ReferenceWriter(CacheEntryWriter entry);
  void Add(const ComparedSample& sample);
  // Finishes the entry (still to be committed to a cache, or read back from its file).
  rig::Result<void> Finish(double wall_s);
  CacheEntryWriter& entry() { return entry_; }

  // A writer with no cache: an unnamed temporary file.
  static rig::Result<ReferenceWriter> Unnamed();

 private:
  CacheEntryWriter entry_;
  std::uint64_t count_ = 0;
};

class ReferenceCache {
 public:
  // `notes` (may be null) hears of entries that were there but could not be used.
  explicit ReferenceCache(std::string directory, std::ostream* notes = nullptr);

  // The entry under `key`, or nullopt on a miss (absent, unreadable or damaged, or not of
  // `expected_samples` samples when that is given: CompletedRunTraceSamples of the scene).
  std::optional<CachedReference> Load(
      const std::string& key, std::optional<std::uint64_t> expected_samples = std::nullopt) const;
  // Stores atomically (write to a temporary name, then rename).
  rig::Result<void> Store(const std::string& key, const CachedReference& reference) const;

  // The entry under `key` for reading a sample at a time, checked as Load checks it; nullopt on
  // a miss (said as Load says it).
  std::optional<ReferenceReader> Open(
      const std::string& key, std::optional<std::uint64_t> expected_samples = std::nullopt) const;
  // Starts the entry under `key`, written as its run goes; nothing is under `key` until Commit.
  rig::Result<ReferenceWriter> Begin(const std::string& key) const;
  // Puts a finished entry in place atomically.
  rig::Result<void> Commit(ReferenceWriter& writer) const;

  const std::string& directory() const { return folder_.directory(); }

 private:
  CacheFolder folder_;
};

}  // namespace hilrig::host
