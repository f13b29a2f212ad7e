// Fuzz target for the MCAP reader (host/mcap): the input is a file's bytes, read whole and read as
// a file cut short. Properties checked beyond "does not crash" and "allocates within the limits":
// an error's offset lies inside the file; every message read is on a channel read; a file that
// reads whole recovers to the same messages, not flagged truncated; a recovered file's complete
// part is no longer than the file and reads back to the same messages when cut there.
// Corpus: fuzz/corpus/mcap_reader (small files McapWriter wrote, zstd and stored).
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_target.h"
#include "host/mcap/mcap_reader.h"

namespace {

using namespace hilrig::mcap;

void Require(bool condition) {
  if (!condition) __builtin_trap();
}

// Small limits: a fuzzed chunk that claims gigabytes is refused, not allocated.
McapReadLimits FuzzLimits() {
  McapReadLimits limits;
  limits.max_chunk_uncompressed_bytes = 1 << 20;
  limits.max_total_uncompressed_bytes = 4 << 20;
  return limits;
}

void CheckConsistent(const McapReadResult& read, std::size_t size) {
  if (!read.ok()) {
    Require(read.error->offset <= size);
    return;
  }
  for (const McapMessage& message : read.contents.messages) {
    Require(read.contents.channels.contains(message.channel_id));
  }
}

bool SameMessages(const McapContents& a, const McapContents& b) {
  if (a.messages.size() != b.messages.size()) return false;
  for (std::size_t i = 0; i < a.messages.size(); ++i) {
    const McapMessage& x = a.messages[i];
    const McapMessage& y = b.messages[i];
    if (x.channel_id != y.channel_id || x.sequence != y.sequence ||
        x.log_time_ns != y.log_time_ns || x.publish_time_ns != y.publish_time_ns ||
        x.payload != y.payload) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const McapReadLimits limits = FuzzLimits();
  const McapReadResult whole = ReadMcap(bytes, limits);
  CheckConsistent(whole, size);
  const McapReadResult recovered = RecoverMcap(bytes, limits);
  CheckConsistent(recovered, size);
  if (whole.ok()) {
    Require(recovered.ok() && !recovered.contents.truncated);
    Require(SameMessages(whole.contents, recovered.contents));
  }
  if (recovered.ok() && recovered.contents.truncated) {
    Require(recovered.contents.complete_bytes <= size);
    const McapReadResult again =
        RecoverMcap(bytes.substr(0, recovered.contents.complete_bytes), limits);
    // (Unless the cut happens to end in what looks like a Footer and the magic.)
    if (again.contents.truncated) {
      Require(again.ok() && SameMessages(again.contents, recovered.contents));
    }
  }
  return 0;
}
