#include "host/report/html_page.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

#include "host/report/xml_text.h"
#include "rig/number_text.h"

namespace hilrig::host {
namespace {

// Green and red strong enough for white text on them (WCAG AA), grey for what was not graded.
constexpr const char* kStyle = R"(
body { font: 14px/1.4 sans-serif; color: #1f2328; background: #fff; margin: 0 auto;
       max-width: 1200px; padding: 16px 24px 48px; }
h1 { font-size: 22px; margin: 8px 0 4px; }
h2 { font-size: 17px; margin: 28px 0 8px; border-bottom: 1px solid #d0d7de; padding-bottom: 4px; }
h3 { font-size: 14px; margin: 16px 0 4px; }
p { margin: 6px 0; }
.sub { color: #59636e; }
.wide { overflow-x: auto; max-width: 100%; margin: 6px 0 14px; }
table { border-collapse: collapse; }
th, td { border: 1px solid #d0d7de; padding: 3px 8px; text-align: left; vertical-align: top; }
th { background: #f6f8fa; font-weight: 600; white-space: nowrap; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.pass, td.fail, td.neutral { font-weight: 600; white-space: nowrap; }
td.pass { color: #fff; background: #1a7f37; }
td.fail { color: #fff; background: #cf222e; }
td.neutral { color: #1f2328; background: #eaeef2; }
.badge { display: inline-block; padding: 1px 10px; border-radius: 4px; font-weight: 700;
         vertical-align: middle; }
.badge.pass { color: #fff; background: #1a7f37; }
.badge.fail { color: #fff; background: #cf222e; }
.badge.neutral { color: #1f2328; background: #eaeef2; }
code { font: 12px/1.4 monospace; white-space: pre-wrap; word-break: break-all; }
svg { display: block; max-width: 100%; height: auto; margin: 8px 0 16px; }
.plots { display: flex; flex-wrap: wrap; gap: 0 24px; }
figure { margin: 0 0 12px; }
.plots figure { flex: 0 1 520px; min-width: 0; }
figcaption { font-weight: 600; margin-top: 8px; }
)";

const char* ToneClass(Tone tone) {
  switch (tone) {
    case Tone::kPass:
      return "pass";
    case Tone::kFail:
      return "fail";
    case Tone::kNeutral:
      return "neutral";
    case Tone::kPlain:
      break;
  }
  return "";
}

// `text` with every "id=\"" and "url(#" followed by `prefix`.
std::string PrefixIds(const std::string& text, const std::string& prefix) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    bool matched = false;
    for (const std::string_view marker : {std::string_view(" id=\""), std::string_view("url(#")}) {
      if (text.compare(i, marker.size(), marker) == 0) {
        out.append(marker);
        out += prefix;
        i += marker.size();
        matched = true;
        break;
      }
    }
    if (!matched) out += text[i++];
  }
  return out;
}

}  // namespace

std::string HtmlText(const std::string& text) { return EscapeXmlText(text); }

HtmlCell TextCell(const std::string& text, Tone tone) { return {HtmlText(text), tone, false, 1}; }

std::string PageNumber(double value) {
  if (!std::isfinite(value)) return rig::NumberText(value);
  std::array<char, 32> buffer{};
  const bool whole = value == std::trunc(value) && std::abs(value) < 1e15;
  const auto [end, error] = whole ? std::to_chars(buffer.data(), buffer.data() + buffer.size(),
                                                  value + 0.0, std::chars_format::fixed, 0)
                                  : std::to_chars(buffer.data(), buffer.data() + buffer.size(),
                                                  value, std::chars_format::general, 4);
  if (error != std::errc()) return rig::NumberText(value);  // unreachable: 32 characters hold it
  return std::string(buffer.data(), end);
}

HtmlCell NumberCell(double value, const std::string& unit) {
  std::string text = PageNumber(value);
  if (!unit.empty()) text += " " + unit;
  return {HtmlText(text), Tone::kPlain, true, 1};
}

std::string HtmlTable(const std::vector<std::string>& headers,
                      const std::vector<std::vector<HtmlCell>>& rows) {
  std::string html = "<div class=\"wide\"><table>\n<tr>";
  for (const std::string& header : headers) html += "<th>" + HtmlText(header) + "</th>";
  html += "</tr>\n";
  for (const std::vector<HtmlCell>& row : rows) {
    html += "<tr>";
    std::size_t spanned = 0;
    for (const HtmlCell& cell : row) {
      std::string classes = ToneClass(cell.tone);
      if (cell.numeric) classes += classes.empty() ? "num" : " num";
      html += "<td";
      if (!classes.empty()) html += " class=\"" + classes + "\"";
      if (cell.columns > 1) html += " colspan=\"" + std::to_string(cell.columns) + "\"";
      html += ">" + cell.html + "</td>";
      spanned += static_cast<std::size_t>(std::max(cell.columns, 1));
    }
    for (; spanned < headers.size(); ++spanned) html += "<td></td>";
    html += "</tr>\n";
  }
  return html + "</table></div>\n";
}

std::string HtmlBadge(const std::string& text, Tone tone) {
  return "<span class=\"badge " + std::string(ToneClass(tone)) + "\">" + HtmlText(text) + "</span>";
}

std::string HtmlLink(const std::string& relative_path, const std::string& text) {
  // RFC 3986's unreserved characters and the path separator stay; every other byte is %XX.
  constexpr const char* kHex = "0123456789ABCDEF";
  std::string href;
  for (const char c : relative_path) {
    const auto byte = static_cast<unsigned char>(c);
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    if (alnum || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      href += c;
    } else {
      href += {'%', kHex[byte >> 4], kHex[byte & 0xF]};
    }
  }
  return "<a href=\"" + HtmlText(href) + "\">" + HtmlText(text) + "</a>";
}

std::string HtmlFileLinks(const std::vector<std::string>& files) {
  std::string html = "<h2>Files</h2>\n<p>";
  for (const std::string& file : files) html += HtmlLink(file, file) + " ";
  return html + "</p>\n";
}

std::string InlineSvg(const std::string& svg, const std::string& id_prefix) {
  std::size_t start = 0;
  if (svg.compare(0, 5, "<?xml") == 0) {
    const std::size_t end = svg.find("?>");
    start = end == std::string::npos ? svg.size() : end + 2;
    while (start < svg.size() && (svg[start] == '\n' || svg[start] == '\r')) ++start;
  }
  return PrefixIds(svg.substr(start), id_prefix);
}

std::string HtmlDocument(const std::string& title, const std::string& body_html) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
         "style-src 'unsafe-inline'\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         HtmlText(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n" +
         body_html + "</body>\n</html>\n";
}

}  // namespace hilrig::host
