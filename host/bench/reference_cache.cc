#include "host/bench/reference_cache.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hilrig::host {
namespace {

// The folder's bound (CacheFolder): up to about 0.4 MB each: every shipped scene over many builds
// and seeds.
constexpr std::size_t kMaxReferenceEntries = 200;

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'H', 'R', 'R', 'E', 'F', '0', '0', '1'};
// Per sample: time, position x/y/z, grasp force, load.
constexpr std::size_t kDoublesPerSample = 6;

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
  std::string bytes(kMagic, sizeof(kMagic));
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

std::optional<CachedReference> ParseReference(const std::string& bytes) {
  constexpr std::size_t kHeader = sizeof(kMagic) + sizeof(std::uint64_t) + sizeof(double);
  if (bytes.size() < kHeader || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return std::nullopt;
  }
  std::uint64_t count;
  std::memcpy(&count, bytes.data() + sizeof(kMagic), sizeof(count));
  const std::size_t sample_bytes = kDoublesPerSample * sizeof(double);
  if (count > (bytes.size() - kHeader) / sample_bytes ||
      bytes.size() != kHeader + count * sample_bytes) {
    return std::nullopt;
  }
  CachedReference reference;
  reference.wall_s = ReadDouble(bytes.data() + sizeof(kMagic) + sizeof(count));
  const char* at = bytes.data() + kHeader;
  for (std::uint64_t i = 0; i < count; ++i, at += sample_bytes) {
    TraceSample sample;
    sample.time_s = ReadDouble(at);
    if (!std::isfinite(sample.time_s)) return std::nullopt;
    sample.position_m = {ReadDouble(at + 8), ReadDouble(at + 16), ReadDouble(at + 24)};
    sample.grasp_force_n = ReadDouble(at + 32);
    sample.load_n = ReadDouble(at + 40);
    reference.trace.Add(sample);
  }
  return reference;
}

ReferenceCache::ReferenceCache(std::string directory)
    : folder_(std::move(directory), ".ref", kMaxReferenceEntries) {}

std::optional<CachedReference> ReferenceCache::Load(const std::string& key) const {
  const std::optional<std::string> bytes = folder_.Load(key);
  if (!bytes) return std::nullopt;
  return ParseReference(*bytes);
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
