// Tabulated field maps kept in files between processes: a map level (opmap:32 evaluates 11^3 film
// poses on 1 024 tiles, ~0.9 s; map:32 ~1.5 s) is tabulated once per build and read back in about
// a millisecond by every later run. A table depends on the level, the grid and the code that
// tabulated it, so its key hashes the level's name, the grid's box and node counts and the
// executable's identity (ExecutableIdentity: a rebuild is a new key). An entry is checked against
// its checksum (cache_files.h) and its grid (FieldMapFilmField::CheckTable: the grid's node count,
// finite values): a damaged, cut or foreign entry is a miss, said, and the map is tabulated again;
// a store that fails (a read-only folder) only costs the next run the tabulation, and is said.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/cache/cache_files.h"
#include "host/sensors/tactile/film_field_factory.h"

namespace hilrig::host {

// The key (16 hex digits) of a level's table.
std::string FieldMapCacheKey(const FilmFidelity& level, const FieldMapGrid& grid,
                             const std::string& code_identity);

// The byte form of a table (an entry's content), and back; Parse refuses anything that is not
// exactly one whole table.
std::string SerializeFieldMapTable(const std::vector<Eigen::Vector3d>& table);
rig::Result<std::vector<Eigen::Vector3d>> ParseFieldMapTable(const std::string& bytes);

class FileFieldMapStore final : public FieldMapTableStore {
 public:
  // `notes` (may be null) hears of entries that could not be used and of stores that failed.
  FileFieldMapStore(std::string directory, std::string code_identity, std::ostream* notes);

  std::optional<std::vector<Eigen::Vector3d>> Load(const FilmFidelity& level,
                                                   const FieldMapGrid& grid) const override;
  void Store(const FilmFidelity& level, const FieldMapGrid& grid,
             const std::vector<Eigen::Vector3d>& table) const override;

  std::string PathOf(const FilmFidelity& level, const FieldMapGrid& grid) const;

 private:
  CacheFolder folder_;
  std::string code_identity_;
};

}  // namespace hilrig::host
