// The secret with which a DUT process proves, in its hello, that it is the one the runner started:
// 128 random bits from the kernel, fresh for every start, handed to the child in its environment
// (kLinkTokenEnvironment; never on the command line, which `ps` shows to every user) or, for a DUT
// started by hand, in a file. Sending the token itself over the loopback link is enough: another
// user can neither read the child's environment nor watch loopback traffic without privileges
// that would defeat any scheme, and a token is never used for a second run, so a proof seen once
// cannot be replayed. Text form: 32 lowercase hex digits.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "rig/result.h"

namespace hilrig::host {

inline constexpr const char* kLinkTokenEnvironment = "HILRIG_LINK_TOKEN";

struct LinkToken {
  std::array<std::uint8_t, 16> bytes{};

  std::string Hex() const;
  // The bytes as the hello carries them.
  std::string Proof() const { return std::string(bytes.begin(), bytes.end()); }
};

rig::Result<LinkToken> NewLinkToken();
// 32 hex digits; trailing whitespace (a file's newline) is ignored. The error never repeats the
// text, which may be somebody's secret.
rig::Result<LinkToken> ParseLinkToken(std::string_view text);
// A regular file of at most a few hundred bytes holding the text form; errors name the path.
rig::Result<LinkToken> ReadLinkTokenFile(const std::string& path);
// The token a DUT started by hand proves: read from `path` when the file exists, else a new one
// written there (created, owner-only, never over another file; `*created` says which). Errors
// name the path.
rig::Result<LinkToken> ReadOrCreateLinkTokenFile(const std::string& path, bool* created);
// Whether a hello's proof is the token; takes the same time wherever the first difference is.
bool ProvesLinkToken(const LinkToken& token, std::string_view proof);

}  // namespace hilrig::host
