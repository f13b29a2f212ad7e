// The building blocks of the HTML pages the rig writes into its result folders (index.html of a
// run, host/report/run_page.h, and of a sweep, host/sweep/sweep_page.h): one self-contained
// document each, readable from a file system with no network. The style sheet is inline, there is
// no script, and a Content-Security-Policy forbids the page any load at all (a browser reports an
// attempt on its console), so the page shows the same anywhere and never calls out. Every text is
// escaped; numbers are locale-free (rig/number_text.h).
#pragma once

#include <string>
#include <vector>

namespace hilrig::host {

// How a cell or a badge reads: a verdict in green or red, something not graded in grey.
enum class Tone { kPlain, kPass, kFail, kNeutral };

// A page's verdict: the word in its badge and title, and its colour.
struct PageVerdict {
  const char* word;
  Tone tone;
};

struct HtmlCell {
  std::string html;  // already escaped (HtmlText) or markup the page built
  Tone tone = Tone::kPlain;
  bool numeric = false;  // right-aligned with tabular digits
  int columns = 1;       // the columns the cell spans
};

// `text` escaped for an HTML element or a quoted attribute.
std::string HtmlText(const std::string& text);

// A cell of plain text, escaped here.
HtmlCell TextCell(const std::string& text, Tone tone = Tone::kPlain);
// A number as a table shows it: four significant digits ("0.6015", "1e-09"), whole numbers below
// 1e15 whole ("34000"), "nan", "inf" and "-inf" as words; locale-free.
std::string PageNumber(double value);

// PageNumber with an optional unit, right-aligned.
HtmlCell NumberCell(double value, const std::string& unit = "");

// A table with a header row, in a box that scrolls sideways when the page is narrower than the
// table (a long name never pushes the page wider). Rows that span fewer columns than the header
// are padded.
std::string HtmlTable(const std::vector<std::string>& headers,
                      const std::vector<std::vector<HtmlCell>>& rows);

// "<span class=\"badge pass\">PASS</span>": a verdict word in its colour; `text` is escaped.
std::string HtmlBadge(const std::string& text, Tone tone);

// `<a href="relative_path">text</a>`: the path percent-encoded (a name with a space or '#' still
// links to its file) and escaped, the text escaped.
std::string HtmlLink(const std::string& relative_path, const std::string& text);

// A section "Files" with a relative link to each of `files` (the page's neighbours).
std::string HtmlFileLinks(const std::vector<std::string>& files);

// An SVG document (svg_plot.h, histogram_plot.h) as an element of the page: the XML declaration
// dropped, and each id and its url(#id) references prefixed with `id_prefix` so that several
// plots with the same clip path ids can share one page.
std::string InlineSvg(const std::string& svg, const std::string& id_prefix);

// The whole document: doctype, character set, the policy that forbids loads, the style sheet,
// the escaped `title`, then `body_html` as given.
std::string HtmlDocument(const std::string& title, const std::string& body_html);

}  // namespace hilrig::host
