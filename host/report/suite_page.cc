#include "host/report/suite_page.h"

#include "host/report/html_page.h"

namespace hilrig::host {
namespace {

PageVerdict PageVerdictOf(const std::vector<SuiteRow>& rows, std::size_t files) {
  if (rows.size() < files) return {"INCOMPLETE", Tone::kNeutral};
  for (const SuiteRow& row : rows) {
    if (row.verdict != SuiteVerdict::kPass) return {"FAIL", Tone::kFail};
  }
  return {"PASS", Tone::kPass};
}

Tone ToneOf(SuiteVerdict verdict) {
  return verdict == SuiteVerdict::kPass ? Tone::kPass : Tone::kFail;
}

std::string Heading(const std::string& folder, const std::vector<SuiteRow>& rows, std::size_t files,
                    const PageVerdict& verdict) {
  std::size_t passed = 0;
  for (const SuiteRow& row : rows) passed += row.verdict == SuiteVerdict::kPass ? 1 : 0;
  std::string sub = std::to_string(rows.size()) + " of " + std::to_string(files) +
                    " scenario files run, " + std::to_string(passed) + " passed";
  if (rows.size() < files) {
    sub += "; the rest did not run (the run was stopped, or is still going)";
  }
  return "<h1>Scenarios in " + HtmlText(folder) + " " + HtmlBadge(verdict.word, verdict.tone) +
         "</h1>\n<p class=\"sub\">" + HtmlText(sub) + "</p>\n";
}

std::vector<HtmlCell> RowCells(const SuiteRow& row) {
  const HtmlCell name =
      row.has_page ? HtmlCell{HtmlLink(row.name + "/index.html", row.name)} : TextCell(row.name);
  const HtmlCell verdict = TextCell(SuiteVerdictWord(row.verdict), ToneOf(row.verdict));
  if (row.verdict == SuiteVerdict::kInvalid && row.stop_reason.empty()) {
    return {name, verdict, {HtmlText("did not run: " + row.error), Tone::kPlain, false, 3}};
  }
  return {
      name, verdict,
      HtmlCell{HtmlText(std::to_string(row.envelopes_met) + " / " + std::to_string(row.envelopes)),
               Tone::kPlain, true, 1},
      HtmlCell{HtmlText(PageNumber(row.real_time_factor) + "x"), Tone::kPlain, true, 1},
      TextCell(row.stop_reason)};
}

}  // namespace

const char* SuiteVerdictWord(SuiteVerdict verdict) {
  switch (verdict) {
    case SuiteVerdict::kPass:
      return "PASS";
    case SuiteVerdict::kFail:
      return "FAIL";
    case SuiteVerdict::kInvalid:
      break;
  }
  return "INVALID";
}

std::string SuitePageHtml(const std::string& folder, const std::vector<SuiteRow>& rows,
                          std::size_t files) {
  const PageVerdict verdict = PageVerdictOf(rows, files);
  std::vector<std::vector<HtmlCell>> cells;
  for (const SuiteRow& row : rows) cells.push_back(RowCells(row));
  const std::string body =
      Heading(folder, rows, files, verdict) + "<h2>Scenarios</h2>\n" +
      HtmlTable({"scenario", "verdict", "envelopes met", "real-time factor", "stop"}, cells);
  return HtmlDocument("Scenarios in " + folder + ": " + verdict.word, body);
}

}  // namespace hilrig::host
