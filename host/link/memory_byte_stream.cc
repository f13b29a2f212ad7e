#include "host/link/memory_byte_stream.h"

#include <algorithm>

namespace hilrig::host {

struct MemoryByteStream::Pipe {
  std::deque<std::uint8_t> to[2];  // to[side]: what that side reads
  bool closed[2] = {false, false};
};

MemoryByteStream::MemoryByteStream(std::shared_ptr<Pipe> pipe, int side, std::string name)
    : pipe_(std::move(pipe)), side_(side), name_(std::move(name)) {}

MemoryByteStream::~MemoryByteStream() { Close(); }

void MemoryByteStream::Close() { pipe_->closed[side_] = true; }

rig::Result<void> MemoryByteStream::WriteAll(std::span<const std::uint8_t> bytes, int) {
  if (pipe_->closed[0] || pipe_->closed[1]) {
    return rig::MakeError(rig::ErrorCode::kLinkClosed, name_ + ": closed");
  }
  pipe_->to[1 - side_].insert(pipe_->to[1 - side_].end(), bytes.begin(), bytes.end());
  bytes_written_ += bytes.size();
  return {};
}

StreamRead MemoryByteStream::ReadSome(std::span<std::uint8_t> out, int timeout_ms) {
  std::deque<std::uint8_t>& in = pipe_->to[side_];
  if (in.empty() && !pipe_->closed[1 - side_] && idle_hook_) idle_hook_();
  if (in.empty()) {
    if (pipe_->closed[0] || pipe_->closed[1]) {
      return {StreamStatus::kClosed, 0, name_ + ": closed by the peer"};
    }
    if (wait_hook_) wait_hook_(timeout_ms);
    return {};
  }
  const std::size_t count = std::min(out.size(), in.size());
  std::copy_n(in.begin(), count, out.begin());
  in.erase(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(count));
  return {StreamStatus::kData, count, {}};
}

std::pair<std::unique_ptr<MemoryByteStream>, std::unique_ptr<MemoryByteStream>>
MakeMemoryStreamPair(const std::string& name) {
  auto pipe = std::make_shared<MemoryByteStream::Pipe>();
  return {std::make_unique<MemoryByteStream>(pipe, 0, name + " (a)"),
          std::make_unique<MemoryByteStream>(pipe, 1, name + " (b)")};
}

}  // namespace hilrig::host
