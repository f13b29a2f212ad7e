#include "host/cache/reference_cache.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

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
// The sample count and the run's wall time.
constexpr std::size_t kHeadBytes = sizeof(std::uint64_t) + sizeof(double);

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
  std::string bytes;
  const std::uint64_t count = trace.size();
  bytes.append(reinterpret_cast<const char*>(&count), sizeof(count));
  AppendDouble(bytes, reference.wall_s);
  for (std::size_t i = 0; i < trace.size(); ++i) {
    AppendDouble(bytes, trace.time_s[i]);
    for (int axis = 0; axis < 3; ++axis) AppendDouble(bytes, trace.position_m[i][axis]);
    AppendDouble(bytes, trace.grasp_force_n[i]);
    AppendDouble(bytes, trace.load_n[i]);
  }
  return bytes;
}

rig::Result<CachedReference> ParseReference(const std::string& bytes) {
  std::uint64_t count = 0;
  if (bytes.size() >= kHeadBytes) std::memcpy(&count, bytes.data(), sizeof(count));
  const std::size_t sample_bytes = kDoublesPerSample * sizeof(double);
  if (bytes.size() < kHeadBytes || count > (bytes.size() - kHeadBytes) / sample_bytes ||
      bytes.size() != kHeadBytes + count * sample_bytes) {
    return rig::MakeError("not a whole reference trace");
  }
  CachedReference reference;
  reference.wall_s = ReadDouble(bytes.data() + sizeof(count));
  if (!std::isfinite(reference.wall_s) || reference.wall_s < 0) {
    return rig::MakeError("the run's wall time is not a duration");
  }
  const char* at = bytes.data() + kHeadBytes;
  for (std::uint64_t i = 0; i < count; ++i, at += sample_bytes) {
    const double time_s = ReadDouble(at);
    // A completed run's plant state is finite at every tick (the runner stops on one that is not),
    // and the comparison matches samples by time, in order. Forces and loads may be NaN: a signal
    // the scene does not have.
    if (!std::isfinite(time_s) || (i > 0 && !(time_s > reference.trace.time_s.back()))) {
      return rig::MakeError("sample " + std::to_string(i) +
                            "'s time does not follow the one before");
    }
    const Eigen::Vector3d position_m(ReadDouble(at + 8), ReadDouble(at + 16), ReadDouble(at + 24));
    if (!position_m.allFinite()) {
      return rig::MakeError("sample " + std::to_string(i) + "'s position is not finite");
    }
    reference.trace.AddCompared(time_s, position_m, ReadDouble(at + 32), ReadDouble(at + 40));
  }
  return reference;
}

ReferenceCache::ReferenceCache(std::string directory, std::ostream* notes)
    : folder_(std::move(directory), kReferenceFormat, notes) {}

std::optional<CachedReference> ReferenceCache::Load(
    const std::string& key, std::optional<std::uint64_t> expected_samples) const {
  const auto parse = [expected_samples](const std::string& content) {
    auto reference = ParseReference(content);
    if (reference && expected_samples && reference.value().trace.size() != *expected_samples) {
      return rig::Result<CachedReference>(
          rig::MakeError(std::to_string(reference.value().trace.size()) +
                         " samples, the scene's run records " + std::to_string(*expected_samples)));
    }
    return reference;
  };
  return folder_.Load(key, parse);
}

rig::Result<void> ReferenceCache::Store(const std::string& key,
                                        const CachedReference& reference) const {
  if (auto stored = folder_.Store(key, SerializeReference(reference)); !stored) {
    return rig::MakeError("cannot store the reference in " + folder_.directory() + " (" +
                          stored.error().message + ")");
  }
  return {};
}

}  // namespace hilrig::host
