#include "host/cache/reference_cache.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

namespace hilrig::host {
namespace {

// Up to about 0.4 MB each, so the bound is every shipped scene over many builds and seeds. 48 bytes
// a sample: 256 MiB is over 15 hours of a 100 Hz trace, and a longer reference is run every time.
constexpr CacheFormat kReferenceFormat{.extension = ".ref",
                                       .magic = "HRCACHER",
                                       .legacy_magic = "HRREF001",
                                       .max_entries = 200,
                                       .max_entry_bytes = std::size_t{256} << 20};

namespace fs = std::filesystem;

// Per sample: time, position x/y/z, grasp force, load.
constexpr std::size_t kDoublesPerSample = 6;
constexpr std::size_t kSampleBytes = kDoublesPerSample * sizeof(double);
// The sample count and the run's wall time.
constexpr std::size_t kHeadBytes = sizeof(std::uint64_t) + sizeof(double);
// Samples read at a time (48 KiB).
constexpr std::uint64_t kSamplesPerBlock = 1024;

void AppendDouble(std::string& out, double value) {
  char bytes[sizeof(double)];
  std::memcpy(bytes, &value, sizeof(double));
  out.append(bytes, sizeof(double));
}

double ReadDouble(const char* at) {
  double value;
  std::memcpy(&value, at, sizeof(double));
  return value;
}

void EncodeSample(const ComparedSample& sample, char* out) {
  const double values[kDoublesPerSample] = {sample.time_s,         sample.position_m.x(),
                                            sample.position_m.y(), sample.position_m.z(),
                                            sample.grasp_force_n,  sample.load_n};
  std::memcpy(out, values, kSampleBytes);
}

ComparedSample DecodeSample(const char* at) {
  return {ReadDouble(at),
          Eigen::Vector3d(ReadDouble(at + 8), ReadDouble(at + 16), ReadDouble(at + 24)),
          ReadDouble(at + 32), ReadDouble(at + 40)};
}

std::string EncodeHead(std::uint64_t count, double wall_s) {
  std::string head(reinterpret_cast<const char*>(&count), sizeof(count));
  AppendDouble(head, wall_s);
  return head;
}

// The count and wall time of a content of `content_bytes` bytes that opens with `head`, or why
// it is not a whole reference trace of a completed run.
rig::Result<std::pair<std::uint64_t, double>> DecodeHead(const char* head,
                                                         std::uint64_t content_bytes) {
  std::uint64_t count = 0;
  if (content_bytes >= kHeadBytes) std::memcpy(&count, head, sizeof(count));
  if (content_bytes < kHeadBytes || count > (content_bytes - kHeadBytes) / kSampleBytes ||
      content_bytes != kHeadBytes + count * kSampleBytes) {
    return rig::MakeError("not a whole reference trace");
  }
  const double wall_s = ReadDouble(head + sizeof(count));
  if (!std::isfinite(wall_s) || wall_s < 0) {
    return rig::MakeError("the run's wall time is not a duration");
  }
  return std::make_pair(count, wall_s);
}

// Why sample `index` is not one a completed run gives after a sample at `previous_time_s`. A
// completed run's plant state is finite at every tick (the runner stops on one that is not), and
// the comparison matches samples by time, in order. Forces and loads may be NaN: a signal the
// scene does not have.
rig::Result<void> CheckSample(std::uint64_t index, const ComparedSample& sample,
                              double previous_time_s) {
  if (!std::isfinite(sample.time_s) || (index > 0 && !(sample.time_s > previous_time_s))) {
    return rig::MakeError("sample " + std::to_string(index) +
                          "'s time does not follow the one before");
  }
  if (!sample.position_m.allFinite()) {
    return rig::MakeError("sample " + std::to_string(index) + "'s position is not finite");
  }
  return {};
}

rig::Error CountMismatch(std::uint64_t count, std::uint64_t expected_samples) {
  return rig::MakeError(std::to_string(count) + " samples, the scene's run records " +
                        std::to_string(expected_samples));
}

rig::Error NotStored(const std::string& directory, const rig::Error& why) {
  return rig::MakeError("cannot store the reference in " + directory + " (" + why.message + ")");
}

rig::Result<std::string> HashOwnExecutable() {
  std::ifstream exe("/proc/self/exe", std::ios::binary);
  if (!exe) return rig::MakeError("cannot read /proc/self/exe");
  Fnv1a64 hash;
  char buffer[1 << 16];
  while (exe.read(buffer, sizeof(buffer)) || exe.gcount() > 0) {
    hash.Add(buffer, static_cast<std::size_t>(exe.gcount()));
  }
  return hash.Hex();
}

}  // namespace

// The running executable's bytes cannot change under it, so they are hashed once per process
// (`hilrig run` asks for the reference cache and again for the setup caches).
rig::Result<std::string> ExecutableIdentity() {
  static const rig::Result<std::string> identity = HashOwnExecutable();
  return identity;
}

std::string ReferenceCacheKey(const proto::Scenario& reference_spec, std::uint64_t seed,
                              const std::optional<proto::Calibration>& calibration,
                              const std::string& code_identity) {
  Fnv1a64 hash;
  hash.Add(DeterministicBytes(reference_spec));
  hash.Add(&seed, sizeof(seed));
  hash.Add(calibration ? DeterministicBytes(*calibration) : std::string("no calibration"));
  hash.Add(code_identity);
  return hash.Hex();
}

std::string DefaultReferenceCacheDir() {
  if (const char* dir = std::getenv("HILRIG_REFERENCE_CACHE"); dir != nullptr && *dir != '\0') {
    return dir;
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return (fs::path(xdg) / "hilrig" / "reference").string();
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return (fs::path(home) / ".cache" / "hilrig" / "reference").string();
  }
  return (fs::path("hilrig_out") / "reference_cache").string();
}

std::string SerializeReference(const CachedReference& reference) {
  const CapturedTrace& trace = reference.trace;
  std::string bytes = EncodeHead(trace.size(), reference.wall_s);
  char sample[kSampleBytes];
  for (std::size_t i = 0; i < trace.size(); ++i) {
    EncodeSample(trace.At(i), sample);
    bytes.append(sample, kSampleBytes);
  }
  return bytes;
}

rig::Result<CachedReference> ParseReference(const std::string& bytes) {
  const auto head = DecodeHead(bytes.data(), bytes.size());
  if (!head) return head.error();
  CachedReference reference;
  reference.wall_s = head.value().second;
  const char* at = bytes.data() + kHeadBytes;
  for (std::uint64_t i = 0; i < head.value().first; ++i, at += kSampleBytes) {
    const ComparedSample sample = DecodeSample(at);
    const double previous_time_s = i > 0 ? reference.trace.time_s.back() : 0.0;
    if (auto checked = CheckSample(i, sample, previous_time_s); !checked) return checked.error();
    reference.trace.AddCompared(sample);
  }
  return reference;
}

rig::Result<ReferenceReader> ReferenceReader::Open(CacheEntryReader entry,
                                                   std::optional<std::uint64_t> expected_samples) {
  char head_bytes[kHeadBytes] = {};
  if (entry.content_bytes() >= kHeadBytes) {
    if (auto read = entry.ReadAt(0, head_bytes, kHeadBytes); !read) return read.error();
  }
  const std::string path = entry.path();
  const auto head = DecodeHead(head_bytes, entry.content_bytes());
  if (!head) return rig::MakeError(path + ": " + head.error().message);
  if (expected_samples && head.value().first != *expected_samples) {
    return rig::MakeError(path + ": " +
                          CountMismatch(head.value().first, *expected_samples).message);
  }
  ReferenceReader reader(std::move(entry), head.value().first, head.value().second);
  if (auto checked = reader.CheckAll(); !checked) {
    return rig::MakeError(path + ": " + checked.error().message);
  }
  return reader;
}

ReferenceReader::ReferenceReader(CacheEntryReader entry, std::uint64_t count, double wall_s)
    : entry_(std::move(entry)), count_(count), wall_s_(wall_s) {}

std::optional<ComparedSample> ReferenceReader::ReadSample(std::uint64_t index) {
  if (index < block_first_ || index >= block_first_ + block_count_) {
    block_first_ = index;
    block_count_ = std::min(kSamplesPerBlock, count_ - index);
    block_.resize(block_count_ * kSampleBytes);
    if (auto read = entry_.ReadAt(kHeadBytes + index * kSampleBytes, block_.data(), block_.size());
        !read) {
      block_count_ = 0;
      failure_ = read.error();
      return std::nullopt;
    }
  }
  return DecodeSample(block_.data() + (index - block_first_) * kSampleBytes);
}

rig::Result<void> ReferenceReader::CheckAll() {
  while (std::optional<ComparedSample> sample = Next()) {
  }
  if (failure_) return *failure_;
  next_ = 0;
  return {};
}

std::optional<ComparedSample> ReferenceReader::Next() {
  if (failure_ || next_ >= count_) return std::nullopt;
  std::optional<ComparedSample> sample = ReadSample(next_);
  if (!sample) return std::nullopt;
  // Checked again as it is read: the file is the one that was checked, and this costs nothing.
  if (auto checked = CheckSample(next_, *sample, last_time_s_); !checked) {
    failure_ = checked.error();
    return std::nullopt;
  }
  last_time_s_ = sample->time_s;
  ++next_;
  return sample;
}

ReferenceWriter::ReferenceWriter(CacheEntryWriter entry) : entry_(std::move(entry)) {
  const std::string head = EncodeHead(0, 0);  // settled by Finish
  entry_.Append(head.data(), head.size());
}

rig::Result<ReferenceWriter> ReferenceWriter::Unnamed() {
  auto entry = CacheEntryWriter::Unnamed(kReferenceFormat);
  if (!entry) return entry.error();
  return ReferenceWriter(std::move(entry).value());
}

void ReferenceWriter::Add(const ComparedSample& sample) {
  char bytes[kSampleBytes];
  EncodeSample(sample, bytes);
  entry_.Append(bytes, kSampleBytes);
  ++count_;
}

rig::Result<void> ReferenceWriter::Finish(double wall_s) {
  return entry_.Finish(EncodeHead(count_, wall_s));
}

ReferenceCache::ReferenceCache(std::string directory, std::ostream* notes)
    : folder_(std::move(directory), kReferenceFormat, notes) {}

std::optional<ReferenceReader> ReferenceCache::Open(
    const std::string& key, std::optional<std::uint64_t> expected_samples) const {
  auto entry = folder_.Open(key);
  if (!entry) {
    folder_.SayUnused(entry.error());
    return std::nullopt;
  }
  if (!entry.value()) return std::nullopt;
  const std::string path = entry.value()->path();
  auto reader = ReferenceReader::Open(std::move(*entry.value()), expected_samples);
  if (!reader) {
    folder_.SayUnused(reader.error());
    return std::nullopt;
  }
  CacheFolder::MarkUsed(path);
  return std::move(reader).value();
}

std::optional<CachedReference> ReferenceCache::Load(
    const std::string& key, std::optional<std::uint64_t> expected_samples) const {
  std::optional<ReferenceReader> reader = Open(key, expected_samples);
  if (!reader) return std::nullopt;
  CachedReference reference;
  reference.wall_s = reader->wall_s();
  while (std::optional<ComparedSample> sample = reader->Next())
    reference.trace.AddCompared(*sample);
  if (reader->failure()) {
    folder_.SayUnused(*reader->failure());
    return std::nullopt;
  }
  return reference;
}

rig::Result<ReferenceWriter> ReferenceCache::Begin(const std::string& key) const {
  auto entry = folder_.Begin(key);
  if (!entry) return NotStored(folder_.directory(), entry.error());
  return ReferenceWriter(std::move(entry).value());
}

rig::Result<void> ReferenceCache::Commit(ReferenceWriter& writer) const {
  if (auto committed = folder_.Commit(writer.entry()); !committed) {
    return NotStored(folder_.directory(), committed.error());
  }
  return {};
}

rig::Result<void> ReferenceCache::Store(const std::string& key,
                                        const CachedReference& reference) const {
  auto writer = Begin(key);
  if (!writer) return writer.error();
  for (std::size_t i = 0; i < reference.trace.size(); ++i)
    writer.value().Add(reference.trace.At(i));
  if (auto finished = writer.value().Finish(reference.wall_s); !finished) {
    return NotStored(folder_.directory(), finished.error());
  }
  return Commit(writer.value());
}

}  // namespace hilrig::host
