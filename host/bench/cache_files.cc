#include "host/bench/cache_files.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/message.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

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

CacheFolder::CacheFolder(std::string directory, std::string extension)
    : directory_(std::move(directory)), extension_(std::move(extension)) {}

std::string CacheFolder::PathOf(const std::string& key) const {
  return (fs::path(directory_) / (key + extension_)).string();
}

std::optional<std::string> CacheFolder::Load(const std::string& key) const {
  std::ifstream file(PathOf(key), std::ios::binary);
  if (!file) return std::nullopt;
  return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

rig::Result<void> CacheFolder::Store(const std::string& key, const std::string& bytes) const {
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error) return rig::MakeError("cannot create " + directory_ + ": " + error.message());
  return WriteTextFile(PathOf(key), bytes);
}

void SayIfNotKept(const rig::Result<void>& stored, const std::string& what, std::ostream* notes) {
  if (!stored && notes != nullptr) {
    *notes << "hilrig: the " << what << " is not kept for later runs: " << stored.error().message
           << "\n";
  }
}

}  // namespace hilrig::host
