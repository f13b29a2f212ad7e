#include "host/sweep/sweep_folder.h"

#include <system_error>

namespace hilrig::host {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSweepOutputs[] = {
    kResolvedSweepName, "shards",       "runs",    "slurm",     "runs.csv",
    "failing.txt",      "summary.json", "map.svg", "index.html"};

bool Exists(const fs::path& path) {
  std::error_code error;
  return fs::exists(fs::symlink_status(path, error));
}

}  // namespace

EarlierSweepAside::EarlierSweepAside(const std::string& out_dir)
    : folder_(out_dir), previous_(folder_ / ".previous-sweep") {}

rig::Result<EarlierSweepAside> EarlierSweepAside::Move(const std::string& out_dir) {
  EarlierSweepAside aside(out_dir);
  std::error_code error;
  fs::remove_all(aside.previous_, error);
  if (!error) fs::create_directory(aside.previous_, error);
  if (error) {
    return rig::MakeError("cannot make " + aside.previous_.string() + ": " + error.message());
  }
  for (const char* name : kSweepOutputs) {
    const fs::path from = aside.folder_ / name;
    if (!Exists(from)) continue;
    fs::rename(from, aside.previous_ / name, error);
    if (error) {
      aside.PutBack();
      return rig::MakeError("cannot move " + from.string() + " aside: " + error.message());
    }
  }
  aside.moved_all_ = true;
  return aside;
}

void EarlierSweepAside::Drop() {
  std::error_code error;
  fs::remove_all(previous_, error);
}

void EarlierSweepAside::PutBack() {
  std::error_code error;
  for (const char* name : kSweepOutputs) {
    // Once every earlier output is aside, whatever stands at a name is the new sweep's.
    if (moved_all_) fs::remove_all(folder_ / name, error);
    const fs::path kept = previous_ / name;
    if (Exists(kept)) fs::rename(kept, folder_ / name, error);
  }
  fs::remove_all(previous_, error);
}

}  // namespace hilrig::host
