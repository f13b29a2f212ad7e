// Two ends of an in-memory byte stream, for running a serial link against a scripted peer in one
// thread with no wall time passing. A read that finds nothing waiting first calls the reading
// end's idle hook (where a test's peer reads what it was sent and writes its answer), and if
// still nothing is there it reports a timeout at once, after telling the wait hook how long it
// would have waited (where a test advances its fake clock).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "host/link/byte_stream.h"

namespace hilrig::host {

class MemoryByteStream final : public ByteStream {
 public:
  struct Pipe;  // the bytes in flight both ways, shared by the two ends

  MemoryByteStream(std::shared_ptr<Pipe> pipe, int side, std::string name);
  ~MemoryByteStream() override;  // closes this end

  rig::Result<void> WriteAll(std::span<const std::uint8_t> bytes, int timeout_ms) override;
  StreamRead ReadSome(std::span<std::uint8_t> out, int timeout_ms) override;
  std::string name() const override { return name_; }

  // The other end reads what was written before and then sees the stream closed.
  void Close();
  void set_idle_hook(std::function<void()> hook) { idle_hook_ = std::move(hook); }
  void set_wait_hook(std::function<void(int timeout_ms)> hook) { wait_hook_ = std::move(hook); }
  // Bytes this end wrote in all.
  std::uint64_t bytes_written() const { return bytes_written_; }

 private:
  std::shared_ptr<Pipe> pipe_;
  int side_;
  std::string name_;
  std::function<void()> idle_hook_;
  std::function<void(int)> wait_hook_;
  std::uint64_t bytes_written_ = 0;
};

// {a, b}: what a writes, b reads, and the other way round.
std::pair<std::unique_ptr<MemoryByteStream>, std::unique_ptr<MemoryByteStream>>
MakeMemoryStreamPair(const std::string& name = "memory stream");

}  // namespace hilrig::host
