// The page of a run folder, index.html beside report.json: what a person opens first after
// `hilrig run --out DIR`. It shows the report in tables (the verdict and why the run stopped, each
// envelope's worst value and limits, the objects' fate, the run's figures and counters) and the
// run's SVG plots inlined, so the one file is the whole picture (html_page.h: no script, no load);
// the neighbouring files are relative links. It is written with every report the folder gets, the
// "incomplete" one a claimed folder starts with included, so it never shows a previous run.
#pragma once

#include <string>
#include <vector>

#include "proto/report.pb.h"
#include "rig/result.h"

namespace hilrig::host {

inline constexpr const char* kRunPageFile = "index.html";

struct RunPagePlot {
  std::string file;  // "force.svg"
  std::string svg;   // the document; empty: it could not be read, and the page says so
};

// The page for `report` with `plots` (in the report's order) inlined. Cannot fail.
std::string RunPageHtml(const proto::Report& report, const std::vector<RunPagePlot>& plots);

// Reads the plots `report` lists from `out_dir` (one that cannot be read is named on the page,
// not an error) and writes index.html there, whole or not at all. Fails when it cannot be
// written.
rig::Result<void> WriteRunPage(const proto::Report& report, const std::string& out_dir);

}  // namespace hilrig::host
