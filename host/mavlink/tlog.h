// QGroundControl's telemetry log (.tlog): a plain sequence of records with no file header, each an
// 8-byte big-endian unsigned timestamp in microseconds followed by one complete MAVLink frame as
// it crossed the link. QGroundControl stamps records with Unix-epoch time; the writer here stores
// whatever clock its caller has (simulated time, for a rig), which the format cannot tell apart.
// A run's traffic logged this way can be replayed and plotted with the usual MAVLink ground tools.
// The reader splits a log image back into records, for tests and offline tools.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <span>
#include <vector>

#include "host/mavlink/mavlink_frame.h"
#include "host/mavlink/mavlink_messages.h"

namespace hilrig::mavlink {

inline constexpr std::size_t kTlogTimestampBytes = 8;

// Appends records to a stream it does not own.
class TlogWriter {
 public:
  // Cannot fail; does not allocate.
  explicit TlogWriter(std::ostream& out);

  // Appends one record. Fails (returns false) when `frame` is empty or longer than
  // kMaxSignedFrameBytes (nothing is written then) or when the stream is not good after writing.
  // O(frame); does not allocate.
  bool Write(std::uint64_t time_us, std::span<const std::uint8_t> frame);

 private:
  std::ostream& out_;
};

struct TlogRecord {
  std::uint64_t time_us = 0;
  Frame frame;

  bool operator==(const TlogRecord&) const = default;
};

struct TlogContents {
  std::vector<TlogRecord> records;       // in file order
  std::uint64_t v1_records_skipped = 0;  // records holding a MAVLink v1 frame (not decoded)
  // Bytes that belonged to no accepted record (corrupt or unknown frames, a cut-off tail); the
  // reader slides over them one byte at a time until a timestamp and a checked frame line up.
  std::uint64_t bytes_skipped = 0;
};

// Splits a whole log image into its records; each frame is checked by a FrameParser with
// `lookup`. Cannot fail (what it cannot read it counts as skipped); O(bytes) for a clean log,
// O(bytes x frame) at worst; allocates the record vector.
TlogContents ReadTlog(std::span<const std::uint8_t> bytes, WireInfoLookup lookup = &FindWireInfo);

}  // namespace hilrig::mavlink
