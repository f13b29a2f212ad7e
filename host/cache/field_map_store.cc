#include "host/cache/field_map_store.h"

#include <cstdint>
#include <cstring>

namespace hilrig::host {
namespace {

// About 45 KB each, so the bound is every map level of about a dozen builds. The finest grid the
// bench measures (17 x 17 x 13 nodes) makes 130 KB; 16 MiB leaves room for grids 100 times finer.
constexpr CacheFormat kFieldMapFormat{.extension = ".map",
                                      .magic = "HRCACHEM",
                                      .legacy_magic = "HRMAP001",
                                      .max_entries = 64,
                                      .max_entry_bytes = std::size_t{16} << 20};

constexpr std::size_t kCountBytes = sizeof(std::uint64_t);
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
  std::string bytes;
  const std::uint64_t count = table.size();
  bytes.append(reinterpret_cast<const char*>(&count), sizeof(count));
  for (const Eigen::Vector3d& node : table) {
    bytes.append(reinterpret_cast<const char*>(node.data()), kNodeBytes);
  }
  return bytes;
}

rig::Result<std::vector<Eigen::Vector3d>> ParseFieldMapTable(const std::string& bytes) {
  std::uint64_t count = 0;
  if (bytes.size() >= kCountBytes) std::memcpy(&count, bytes.data(), sizeof(count));
  if (bytes.size() < kCountBytes || count > (bytes.size() - kCountBytes) / kNodeBytes ||
      bytes.size() != kCountBytes + count * kNodeBytes) {
    return rig::MakeError("not a whole field map table");
  }
  std::vector<Eigen::Vector3d> table(count);
  const char* at = bytes.data() + kCountBytes;
  for (Eigen::Vector3d& node : table) {
    std::memcpy(node.data(), at, kNodeBytes);
    at += kNodeBytes;
  }
  return table;
}

FileFieldMapStore::FileFieldMapStore(std::string directory, std::string code_identity,
                                     std::ostream* notes)
    : folder_(std::move(directory), kFieldMapFormat, notes),
      code_identity_(std::move(code_identity)) {}

std::string FileFieldMapStore::PathOf(const FilmFidelity& level, const FieldMapGrid& grid) const {
  return folder_.PathOf(FieldMapCacheKey(level, grid, code_identity_));
}

std::optional<std::vector<Eigen::Vector3d>> FileFieldMapStore::Load(
    const FilmFidelity& level, const FieldMapGrid& grid) const {
  // The table of another grid, or with a non-finite value, is no map of this level.
  const auto parse =
      [&grid](const std::string& content) -> rig::Result<std::vector<Eigen::Vector3d>> {
    auto table = ParseFieldMapTable(content);
    if (!table) return table;
    if (auto fits = FieldMapFilmField::CheckTable(grid, table.value()); !fits) return fits.error();
    return table;
  };
  return folder_.Load(FieldMapCacheKey(level, grid, code_identity_), parse);
}

void FileFieldMapStore::Store(const FilmFidelity& level, const FieldMapGrid& grid,
                              const std::vector<Eigen::Vector3d>& table) const {
  SayIfNotKept(
      folder_.Store(FieldMapCacheKey(level, grid, code_identity_), SerializeFieldMapTable(table)),
      FilmFidelityName(level) + " field map", folder_.notes());
}

}  // namespace hilrig::host
