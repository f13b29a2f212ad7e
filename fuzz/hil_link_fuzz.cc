// Fuzz target for the HIL link's incremental decoder (host/link/hil_link_codec.h): the input is
// the byte stream a peer sends, fed in two chunkings. Properties checked beyond "does not crash or
// hang": the decoder yields the same events whatever the chunking; once it reports an oversized or
// malformed frame it yields nothing more; every message it delivers re-encodes into a frame that
// decodes to the same message; and its counters agree with the events it yielded.
//
// Corpus: fuzz/corpus/hil_link, seeded with valid frames of each message type written by the codec
// itself, so that mutations reach past the length prefix and the parse.
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "fuzz/fuzz_target.h"
#include "host/link/hil_link_codec.h"

namespace {

using hilrig::host::LinkDecoder;
using hilrig::host::LinkError;
using hilrig::host::LinkEvent;
using hilrig::proto::LinkMessage;

void Require(bool condition) {
  if (!condition) __builtin_trap();
}

// Events as comparable text: serialized messages, or the error's name and detail.
std::vector<std::string> Decode(const std::uint8_t* data, std::size_t size, std::size_t split,
                                LinkDecoder& decoder) {
  std::vector<std::string> events;
  const auto drain = [&] {
    while (auto event = decoder.Next()) {
      if (const auto* message = std::get_if<LinkMessage>(&*event)) {
        events.push_back(std::string(1, 'm').append(message->SerializeAsString()));
        // Round trip: what was delivered encodes into a frame that decodes to itself.
        auto frame = hilrig::host::EncodeLinkFrame(*message);
        Require(frame.ok());
        const std::size_t body = message->ByteSizeLong();
        Require(frame.value().size() > body);
        LinkMessage back;
        Require(back.ParseFromString(frame.value().substr(frame.value().size() - body)));
        Require(back.SerializeAsString() == message->SerializeAsString());
      } else {
        events.push_back(std::string(1, 'e').append(std::get<LinkError>(*event).Message()));
      }
      Require(events.size() <= size + 1);  // every event consumes at least one byte
    }
  };
  decoder.Feed(std::span<const std::uint8_t>(data, split));
  drain();
  decoder.Feed(std::span<const std::uint8_t>(data + split, size - split));
  drain();
  return events;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  LinkDecoder whole;
  const std::vector<std::string> at_once = Decode(data, size, size, whole);
  LinkDecoder chunked;
  const std::size_t split = size == 0 ? 0 : data[0] % (size + 1);
  const std::vector<std::string> in_two = Decode(data, size, split, chunked);
  Require(at_once == in_two);
  // After a framing error nothing else comes out.
  for (std::size_t i = 0; i < at_once.size(); ++i) {
    const bool framing =
        at_once[i].rfind("eoversized", 0) == 0 || at_once[i].rfind("emalformed", 0) == 0;
    if (framing) Require(i + 1 == at_once.size() && whole.broken());
  }
  const auto& counters = whole.counters();
  Require(counters.bytes == size);
  Require(counters.messages + counters.errors() == at_once.size());
  return 0;
}
