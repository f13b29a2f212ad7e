#include "host/bench/cache_files.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/message.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

#include "host/report/report_files.h"

namespace hilrig::host {

namespace fs = std::filesystem;

void Fnv1a64::Add(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash_ ^= bytes[i];
    hash_ *= 0x100000001b3ULL;
  }
}

void Fnv1a64::Add(const std::string& text) {
  const std::uint64_t size = text.size();
  Add(&size, sizeof(size));
  Add(text.data(), text.size());
}

std::string Fnv1a64::Hex() const {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash_));
  return text;
}

std::string DeterministicBytes(const google::protobuf::Message& message) {
  std::string bytes;
  google::protobuf::io::StringOutputStream stream(&bytes);
  google::protobuf::io::CodedOutputStream coded(&stream);
  coded.SetSerializationDeterministic(true);
  message.SerializeToCodedStream(&coded);
  coded.Trim();
  return bytes;
}

CacheFolder::CacheFolder(std::string directory, std::string extension, std::size_t max_entries)
    : directory_(std::move(directory)),
      extension_(std::move(extension)),
      max_entries_(std::max<std::size_t>(1, max_entries)) {}

std::string CacheFolder::PathOf(const std::string& key) const {
  return (fs::path(directory_) / (key + extension_)).string();
}

std::optional<std::string> CacheFolder::Load(const std::string& key) const {
  const std::string path = PathOf(key);
  std::ifstream file(path, std::ios::binary);
  if (!file) return std::nullopt;
  std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  // Used now: the modification time is what the trimming orders by (a failure only makes the
  // entry look older).
  std::error_code error;
  fs::last_write_time(path, fs::file_time_type::clock::now(), error);
  return bytes;
}

void CacheFolder::RemoveLeastRecentlyUsed() const {
  std::vector<std::pair<fs::file_time_type, fs::path>> entries;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory_, error)) {
    if (entry.path().extension() != extension_) continue;
    std::error_code time_error;
    const fs::file_time_type used = entry.last_write_time(time_error);
    if (!time_error) entries.emplace_back(used, entry.path());
  }
  if (entries.size() <= max_entries_) return;
  std::sort(entries.begin(), entries.end());
  for (std::size_t i = 0; i < entries.size() - max_entries_; ++i) {
    fs::remove(entries[i].second, error);  // another process may have removed it first
  }
}

rig::Result<void> CacheFolder::Store(const std::string& key, const std::string& bytes) const {
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error) return rig::MakeError("cannot create " + directory_ + ": " + error.message());
  if (auto written = WriteTextFile(PathOf(key), bytes); !written) return written;
  RemoveLeastRecentlyUsed();
  return {};
}

void SayIfNotKept(const rig::Result<void>& stored, const std::string& what, std::ostream* notes) {
  if (!stored && notes != nullptr) {
    *notes << "hilrig: the " << what << " is not kept for later runs: " << stored.error().message
           << "\n";
  }
}

}  // namespace hilrig::host
