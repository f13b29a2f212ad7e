// Text from outside the rig (a spec's path, a board's name, a peer's reason, a file name) made safe
// to print on one line of a terminal or a comment of a script: control characters are shown as
// escapes, so an escape sequence cannot move the cursor, recolour or retitle a terminal, and a
// newline cannot start a line of its own in a file that is run.
#pragma once

#include <streambuf>
#include <string>
#include <string_view>

namespace hilrig::rig {

// `text` with each C0 control character, DEL and each C1 control character (U+0080 to U+009F in
// UTF-8, which some terminals obey) replaced by an escape: \n, \r, \t, and \xNN for the others
// (each byte). Every other byte is kept, UTF-8 included. O(size); cannot fail.
std::string PrintableText(std::string_view text);

// True when PrintableText would change nothing.
bool IsPrintableText(std::string_view text);

// A stream buffer in front of a terminal's: what is written through it reaches `target` with
// every control character but the line break and the tab shown as PrintableText shows it, so that
// nothing a command prints (a board's name, a peer's reason, a file name) can drive the terminal.
// Bytes are passed on as they come (a C1 control split across two writes is still caught); the
// target is not owned.
class PrintableStreamBuf final : public std::streambuf {
 public:
  explicit PrintableStreamBuf(std::streambuf* target) : target_(target) {}
  std::streambuf* target() const { return target_; }

 protected:
  int_type overflow(int_type ch) override;
  std::streamsize xsputn(const char* data, std::streamsize size) override;
  int sync() override;

 private:
  bool Put(unsigned char c);
  bool PutRaw(const char* data, std::size_t size);

  std::streambuf* target_;
  bool pending_c2_ = false;  // the last byte was 0xC2, the first of a possible C1 control
};

}  // namespace hilrig::rig
