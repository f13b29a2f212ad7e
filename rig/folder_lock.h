// One process at a time writes into an output folder: two runs into the same folder would splice
// their traces and both report success. FolderLock::Acquire takes an exclusive flock(2) on a lock
// file in the folder, without waiting; a second process gets an error that names the holder's
// pid and command. The lock belongs to the open file, so it ends with the process however the
// process ends (a SIGKILLed holder never blocks the next run), and the lock file stays behind:
// unlinking it would let a process that opened the old file and one that creates a new one both
// think they hold the folder.
#pragma once

#include <string>

#include "rig/result.h"

namespace hilrig::rig {

// The lock file's name inside a locked folder.
inline constexpr const char* kFolderLockFileName = ".hilrig.lock";

class FolderLock {
 public:
  // Creates `folder` (and its parents) if needed and locks it. Fails, naming the folder, when
  // another process holds it ("... is in use by another hilrig: pid 1234 (hilrig run ...)") or
  // when the lock file cannot be made (a symbolic link or a non-regular file planted at its name
  // is refused, never followed). The file then holds "pid N" and "command C" lines for people;
  // an error never quotes it (it may have been planted) and names the holder from /proc.
  static Result<FolderLock> Acquire(const std::string& folder);

  FolderLock(FolderLock&& other) noexcept;
  FolderLock& operator=(FolderLock&& other) noexcept;
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  ~FolderLock();  // releases the lock

 private:
  explicit FolderLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace hilrig::rig
