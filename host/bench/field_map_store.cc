#include "host/bench/field_map_store.h"

#include <cstdint>
#include <cstring>

namespace hilrig::host {
namespace {

// The folder's bound (CacheFolder): about 45 KB each, every map level of about a dozen builds.
constexpr std::size_t kMaxFieldMapEntries = 64;

constexpr char kMagic[8] = {'H', 'R', 'M', 'A', 'P', '0', '0', '1'};
constexpr std::size_t kHeaderBytes = sizeof(kMagic) + sizeof(std::uint64_t);
constexpr std::size_t kNodeBytes = 3 * sizeof(double);

void AddVector(Fnv1a64& hash, const Eigen::Vector3d& v) { hash.Add(v.data(), 3 * sizeof(double)); }

}  // namespace

std::string FieldMapCacheKey(const FilmFidelity& level, const FieldMapGrid& grid,
                             const std::string& code_identity) {
  Fnv1a64 hash;
  hash.Add(FilmFidelityName(level));
  AddVector(hash, grid.box.min_m);
  AddVector(hash, grid.box.max_m);
  const std::int32_t nodes[3] = {grid.nodes.x(), grid.nodes.y(), grid.nodes.z()};
  hash.Add(nodes, sizeof(nodes));
  hash.Add(code_identity);
  return hash.Hex();
}

std::string SerializeFieldMapTable(const std::vector<Eigen::Vector3d>& table) {
  std::string bytes(kMagic, sizeof(kMagic));
  const std::uint64_t count = table.size();
  bytes.append(reinterpret_cast<const char*>(&count), sizeof(count));
  for (const Eigen::Vector3d& node : table) {
    bytes.append(reinterpret_cast<const char*>(node.data()), kNodeBytes);
  }
  return bytes;
}

std::optional<std::vector<Eigen::Vector3d>> ParseFieldMapTable(const std::string& bytes) {
  if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return std::nullopt;
  }
  std::uint64_t count;
  std::memcpy(&count, bytes.data() + sizeof(kMagic), sizeof(count));
  if (count > (bytes.size() - kHeaderBytes) / kNodeBytes ||
      bytes.size() != kHeaderBytes + count * kNodeBytes) {
    return std::nullopt;
  }
  std::vector<Eigen::Vector3d> table(count);
  const char* at = bytes.data() + kHeaderBytes;
  for (Eigen::Vector3d& node : table) {
    std::memcpy(node.data(), at, kNodeBytes);
    at += kNodeBytes;
  }
  return table;
}

FileFieldMapStore::FileFieldMapStore(std::string directory, std::string code_identity,
                                     std::ostream* notes)
    : folder_(std::move(directory), ".map", kMaxFieldMapEntries),
      code_identity_(std::move(code_identity)),
      notes_(notes) {}

std::string FileFieldMapStore::PathOf(const FilmFidelity& level, const FieldMapGrid& grid) const {
  return folder_.PathOf(FieldMapCacheKey(level, grid, code_identity_));
}

std::optional<std::vector<Eigen::Vector3d>> FileFieldMapStore::Load(
    const FilmFidelity& level, const FieldMapGrid& grid) const {
  const std::optional<std::string> bytes =
      folder_.Load(FieldMapCacheKey(level, grid, code_identity_));
  if (!bytes) return std::nullopt;
  return ParseFieldMapTable(*bytes);
}

void FileFieldMapStore::Store(const FilmFidelity& level, const FieldMapGrid& grid,
                              const std::vector<Eigen::Vector3d>& table) const {
  SayIfNotKept(
      folder_.Store(FieldMapCacheKey(level, grid, code_identity_), SerializeFieldMapTable(table)),
      FilmFidelityName(level) + " field map", notes_);
}

}  // namespace hilrig::host
