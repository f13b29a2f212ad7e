// The page of a folder run (`hilrig run FOLDER --out DIR`): DIR/index.html, one row per scenario
// file with its verdict, the envelopes that met their expectation, its real-time factor and why it
// stopped, linked to the scenario's own run page (host/report/run_page.h). The runner writes it
// again after every scenario, so a run stopped or killed part-way leaves a page of what finished
// that says how many files did not run.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace hilrig::host {

// How one scenario file of the folder ended.
enum class SuiteVerdict {
  kPass,     // every envelope met its expectation and the run completed
  kFail,     // an envelope or check did not pass, or the run was stopped
  kInvalid,  // it never ran: its spec, or something its set-up needed, was at fault
};

struct SuiteRow {
  std::string name;  // the file's stem: also the name of its run folder under DIR
  SuiteVerdict verdict = SuiteVerdict::kInvalid;
  int envelopes_met = 0;
  int envelopes = 0;
  double real_time_factor = 0;
  std::string stop_reason;  // the report's ("completed", ...); empty when it never ran
  std::string error;        // why it never ran; empty otherwise
  bool has_page = false;    // DIR/name/index.html exists, so the row links to it
};

// "PASS", "FAIL" or "INVALID", as the folder run's table prints them.
const char* SuiteVerdictWord(SuiteVerdict verdict);

// The whole page for `rows`, the files run so far out of `files` in `folder`. Its verdict is
// INCOMPLETE while fewer rows than files are in, else FAIL when a row did not pass, else PASS. The
// page depends on its arguments alone (no time, no absolute output path).
std::string SuitePageHtml(const std::string& folder, const std::vector<SuiteRow>& rows,
                          std::size_t files);

}  // namespace hilrig::host
