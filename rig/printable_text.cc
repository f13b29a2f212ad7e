#include "rig/printable_text.h"

#include <cstdio>

namespace hilrig::rig {
namespace {

bool IsControl(unsigned char c) { return c < 0x20 || c == 0x7f; }

// A C1 control in UTF-8: 0xC2 followed by 0x80..0x9F.
bool IsC1At(std::string_view text, std::size_t i) {
  return static_cast<unsigned char>(text[i]) == 0xc2 && i + 1 < text.size() &&
         static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
         static_cast<unsigned char>(text[i + 1]) <= 0x9f;
}

void AppendEscaped(unsigned char c, std::string& out) {
  switch (c) {
    case '\n':
      out += "\\n";
      return;
    case '\r':
      out += "\\r";
      return;
    case '\t':
      out += "\\t";
      return;
    default:
      char escape[5];
      std::snprintf(escape, sizeof(escape), "\\x%02x", c);
      out += escape;
  }
}

}  // namespace

std::string PrintableText(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (IsControl(c)) {
      AppendEscaped(c, out);
    } else if (IsC1At(text, i)) {
      AppendEscaped(c, out);
      AppendEscaped(static_cast<unsigned char>(text[++i]), out);
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

bool IsPrintableText(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (IsControl(static_cast<unsigned char>(text[i])) || IsC1At(text, i)) return false;
  }
  return true;
}

bool PrintableStreamBuf::PutRaw(const char* data, std::size_t size) {
  return target_->sputn(data, static_cast<std::streamsize>(size)) ==
         static_cast<std::streamsize>(size);
}

bool PrintableStreamBuf::Put(unsigned char c) {
  if (pending_c2_) {
    pending_c2_ = false;
    if (c >= 0x80 && c <= 0x9f) {
      std::string escaped;
      AppendEscaped(0xc2, escaped);
      AppendEscaped(c, escaped);
      return PutRaw(escaped.data(), escaped.size());
    }
    const char lead = static_cast<char>(0xc2);
    if (!PutRaw(&lead, 1)) return false;
  }
  if (c == 0xc2) {
    pending_c2_ = true;
    return true;
  }
  if (IsControl(c) && c != '\n' && c != '\t') {
    std::string escaped;
    AppendEscaped(c, escaped);
    return PutRaw(escaped.data(), escaped.size());
  }
  const char byte = static_cast<char>(c);
  return PutRaw(&byte, 1);
}

PrintableStreamBuf::int_type PrintableStreamBuf::overflow(int_type ch) {
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  return Put(static_cast<unsigned char>(traits_type::to_char_type(ch))) ? ch : traits_type::eof();
}

std::streamsize PrintableStreamBuf::xsputn(const char* data, std::streamsize size) {
  std::streamsize done = 0;
  while (done < size) {
    // A run of bytes that need no look pass in one call.
    std::streamsize run = 0;
    while (!pending_c2_ && done + run < size) {
      const auto c = static_cast<unsigned char>(data[done + run]);
      if ((IsControl(c) && c != '\n' && c != '\t') || c == 0xc2) break;
      ++run;
    }
    if (run > 0) {
      if (!PutRaw(data + done, static_cast<std::size_t>(run))) return done;
      done += run;
      continue;
    }
    if (!Put(static_cast<unsigned char>(data[done]))) return done;
    ++done;
  }
  return done;
}

int PrintableStreamBuf::sync() {
  if (pending_c2_) {
    // A lone 0xC2 at a flush: a C1 control cannot follow across a flush that the reader sees.
    pending_c2_ = false;
    const char lead = static_cast<char>(0xc2);
    if (!PutRaw(&lead, 1)) return -1;
  }
  return target_->pubsync();
}

}  // namespace hilrig::rig
