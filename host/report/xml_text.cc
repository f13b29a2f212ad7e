#include "host/report/xml_text.h"

namespace hilrig::host {

std::string EscapeXmlText(const std::string& text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      default:
        const auto byte = static_cast<unsigned char>(c);
        escaped += (byte < 0x20 && c != '\t' && c != '\n' && c != '\r') || byte == 0x7F ? '?' : c;
    }
  }
  return escaped;
}

}  // namespace hilrig::host
