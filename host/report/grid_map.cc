#include "host/report/grid_map.h"

#include <algorithm>
#include <cmath>

#include "host/report/xml_text.h"

namespace hilrig::host {
namespace {

constexpr double kSwatchPx = 24;
constexpr double kCellTextMinHeightPx = 14;  // an 11 px text and a pixel above and below
constexpr const char* kEnDash = "\xE2\x80\x93";
constexpr const char* kMutedColor = "#777777";

struct Rgb {
  int red = 0, green = 0, blue = 0;
};

// kGridMapPassColor, kGridMapFailColor and kGridMapEmptyColor as channels.
constexpr Rgb kPass{0x00, 0x72, 0xB2};
constexpr Rgb kFail{0xD5, 0x5E, 0x00};
constexpr Rgb kEmpty{0xEA, 0xEE, 0xF2};

std::string Hex(const Rgb& color) {
  constexpr const char* kDigits = "0123456789ABCDEF";
  std::string text = "#";
  for (const int channel : {color.red, color.green, color.blue}) {
    text += kDigits[(channel >> 4) & 0xF];
    text += kDigits[channel & 0xF];
  }
  return text;
}

int Blend(int fail, int pass, double share) {
  return static_cast<int>(std::lround(fail + share * (pass - fail)));
}

Rgb FillOf(const GridMapCell& cell) {
  if (cell.cases == 0) return kEmpty;
  const double share =
      static_cast<double>(std::min(cell.passed, cell.cases)) / static_cast<double>(cell.cases);
  return {Blend(kFail.red, kPass.red, share), Blend(kFail.green, kPass.green, share),
          Blend(kFail.blue, kPass.blue, share)};
}

double LinearChannel(int channel) {
  const double c = channel / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// White or black, whichever contrasts more with `fill` (WCAG's relative luminance): white on the
// blue, black on the vermillion, so that a cell's count reads on every share.
const char* TextColorOn(const Rgb& fill) {
  const double luminance = 0.2126 * LinearChannel(fill.red) + 0.7152 * LinearChannel(fill.green) +
                           0.0722 * LinearChannel(fill.blue);
  return 1.05 / (luminance + 0.05) >= (luminance + 0.05) / 0.05 ? "#FFFFFF" : "#000000";
}

GridMapCell CellAt(const GridMap& map, std::size_t column, std::size_t row) {
  const std::size_t at = row * map.columns.size() + column;
  return at < map.cells.size() ? map.cells[at] : GridMapCell{};
}

std::size_t Utf8Chars(const std::string& text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) {
    return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  }));
}

struct LegendEntry {
  Rgb fill;
  std::string text;
};

// Pass and fail always; a share where some point has several cases; grey where one has none.
std::vector<LegendEntry> LegendEntries(const GridMap& map) {
  bool several = false, empty = false;
  for (std::size_t row = 0; row < map.rows.size(); ++row) {
    for (std::size_t column = 0; column < map.columns.size(); ++column) {
      const GridMapCell cell = CellAt(map, column, row);
      several = several || cell.cases > 1;
      empty = empty || cell.cases == 0;
    }
  }
  std::vector<LegendEntry> entries;
  if (several) {
    entries = {{kPass, "every case passed"},
               {kFail, "no case passed"},
               {FillOf({1, 2}), "k/n: k of the n cases passed"}};
  } else {
    entries = {{kPass, "passed"}, {kFail, "failed"}};
  }
  if (empty) entries.push_back({kEmpty, "no case finished"});
  return entries;
}

// Says what the document had no room for, or that there is no grid point at all.
std::string Remark(const GridMap& map, const GridMapLayout& layout) {
  if (map.columns.empty() || map.rows.empty()) return "no grid point to draw";
  std::string text;
  const auto add = [&](std::size_t more, const char* what) {
    if (more == 0) return;
    text += (text.empty() ? "" : " and ") + std::to_string(more) + " more " + what;
  };
  add(map.columns.size() - layout.drawn_columns, "columns");
  add(map.rows.size() - layout.drawn_rows, "rows");
  return text.empty() ? "" : text + " not drawn";
}

double Bottom(const GridMapLayout& layout) { return layout.area.top_px + layout.area.height_px; }

std::string Cells(const GridMap& map, const GridMapLayout& layout) {
  std::string rects = "<g class=\"cells\" stroke=\"#FFFFFF\">\n";
  std::string texts = "<g class=\"cell-text\">\n";
  for (std::size_t row = layout.drawn_rows; row-- > 0;) {  // top to bottom, as the map reads
    for (std::size_t column = 0; column < layout.drawn_columns; ++column) {
      const GridMapCell cell = CellAt(map, column, row);
      const PlotRect at = GridMapCellRect(layout, column, row);
      const Rgb fill = FillOf(cell);
      const std::string tip =
          map.x_label + " = " + map.columns[column] + ", " + map.y_label + " = " + map.rows[row] +
          ": " +
          (cell.cases == 0 ? std::string("no case finished")
                           : std::to_string(cell.passed) + " of " + std::to_string(cell.cases) +
                                 (cell.cases == 1 ? " case passed" : " cases passed"));
      rects += "<rect" + SvgAttr("x", SvgPx(at.left_px)) + SvgAttr("y", SvgPx(at.top_px)) +
               SvgAttr("width", SvgPx(at.width_px)) + SvgAttr("height", SvgPx(at.height_px)) +
               SvgAttr("fill", Hex(fill)) + "><title>" + EscapeXmlText(tip) + "</title></rect>\n";
      const std::string text = GridMapCellText(cell);
      const bool fits = static_cast<double>(Utf8Chars(text)) * kLegendCharPx + 4 <= at.width_px &&
                        at.height_px >= kCellTextMinHeightPx;
      if (!fits) continue;
      texts += SvgText(at.left_px + at.width_px / 2, at.top_px + at.height_px / 2 + 4, "middle",
                       text, SvgAttr("fill", TextColorOn(fill)));
    }
  }
  return rects + "</g>\n" + texts + "</g>\n";
}

std::string TickLabels(const GridMap& map, const GridMapLayout& layout) {
  std::string out = "<g class=\"tick-labels\" fill=\"#333333\">\n";
  for (std::size_t column = 0; column < layout.drawn_columns; column += layout.column_label_step) {
    const PlotRect at = GridMapCellRect(layout, column, 0);
    out += SvgText(at.left_px + at.width_px / 2, Bottom(layout) + 16, "middle",
                   SvgTruncated(map.columns[column], kGridMapMaxTickChars));
  }
  for (std::size_t row = 0; row < layout.drawn_rows; row += layout.row_label_step) {
    const PlotRect at = GridMapCellRect(layout, 0, row);
    out += SvgText(layout.area.left_px - 6, at.top_px + at.height_px / 2 + 4, "end",
                   SvgTruncated(map.rows[row], kGridMapMaxTickChars));
  }
  return out + "</g>\n";
}

std::string Labels(const GridMap& map, const GridMapLayout& layout) {
  const PlotRect& area = layout.area;
  return SvgTitle(layout.doc_width_px, map.title) +
         SvgText(area.left_px + area.width_px / 2, Bottom(layout) + 34, "middle", map.x_label,
                 " class=\"x-label\"") +
         SvgYLabel(16, area.top_px + area.height_px / 2, map.y_label);
}

// One entry a row under the x label, then the remark if there is one.
std::string Legend(const GridMap& map, const GridMapLayout& layout) {
  const double x = layout.area.left_px;
  const auto baseline = [&](std::size_t index) {
    return Bottom(layout) + kAxisBelowPx + kLegendGapPx +
           static_cast<double>(index) * kLegendRowPx + 12;
  };
  const double text_px = std::max(layout.doc_width_px - x - kSwatchPx - 10, kLegendCharPx * 4);
  const auto text_chars = static_cast<std::size_t>(text_px / kLegendCharPx);
  std::string out = "<g class=\"legend\" fill=\"#222222\">\n";
  const std::vector<LegendEntry> entries = LegendEntries(map);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    out += SvgSwatch(x, baseline(i), kSwatchPx, Hex(entries[i].fill), " stroke=\"#D0D7DE\"");
    out +=
        SvgText(x + kSwatchPx + 6, baseline(i), "start", SvgTruncated(entries[i].text, text_chars));
  }
  const std::string remark = Remark(map, layout);
  if (!remark.empty()) {
    out += SvgText(x, baseline(entries.size()), "start", remark,
                   " class=\"remark\"" + SvgAttr("fill", kMutedColor));
  }
  return out + "</g>\n";
}

}  // namespace

GridMapLayout GridMapLayoutOf(const GridMap& map) {
  GridMapLayout layout;
  const std::size_t columns = map.columns.size(), rows = map.rows.size();
  layout.cell_width_px =
      std::clamp(kGridMapAreaWidthPx / static_cast<double>(std::max<std::size_t>(columns, 1)),
                 kGridMapMinCellPx, kGridMapMaxCellWidthPx);
  layout.cell_height_px =
      std::clamp(kGridMapAreaHeightPx / static_cast<double>(std::max<std::size_t>(rows, 1)),
                 kGridMapMinCellPx, kGridMapMaxCellHeightPx);
  const std::size_t entries = LegendEntries(map).size();
  const double below_px = kAxisBelowPx + kLegendGapPx;
  // Room for the legend and a remark, whether or not there is one, so the cut is decided once.
  const double width_room_px = kMaxSizePx - kGridMapLeftPx - kPlotMarginRightPx;
  const double height_room_px =
      kMaxSizePx - kPlotMarginTopPx - below_px - static_cast<double>(entries + 1) * kLegendRowPx;
  layout.drawn_columns =
      std::min(columns, static_cast<std::size_t>(width_room_px / layout.cell_width_px));
  layout.drawn_rows =
      std::min(rows, static_cast<std::size_t>(height_room_px / layout.cell_height_px));
  layout.area = {kGridMapLeftPx, kPlotMarginTopPx,
                 static_cast<double>(layout.drawn_columns) * layout.cell_width_px,
                 static_cast<double>(layout.drawn_rows) * layout.cell_height_px};
  layout.legend_rows = static_cast<int>(entries) + (Remark(map, layout).empty() ? 0 : 1);
  layout.doc_width_px = std::max(
      kMinWidthPx,
      static_cast<int>(std::ceil(kGridMapLeftPx + layout.area.width_px + kPlotMarginRightPx)));
  layout.doc_height_px = static_cast<int>(std::ceil(kPlotMarginTopPx + layout.area.height_px +
                                                    below_px + layout.legend_rows * kLegendRowPx));
  std::size_t widest_chars = 1;
  for (std::size_t column = 0; column < layout.drawn_columns; ++column) {
    widest_chars =
        std::max(widest_chars, Utf8Chars(SvgTruncated(map.columns[column], kGridMapMaxTickChars)));
  }
  const double label_px = static_cast<double>(widest_chars) * kLegendCharPx + 8;
  layout.column_label_step = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(label_px / layout.cell_width_px)));
  layout.row_label_step = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(kLegendRowPx / layout.cell_height_px)));
  return layout;
}

PlotRect GridMapCellRect(const GridMapLayout& layout, std::size_t column, std::size_t row) {
  const double rows_above = static_cast<double>(layout.drawn_rows) - 1 - static_cast<double>(row);
  return {layout.area.left_px + static_cast<double>(column) * layout.cell_width_px,
          layout.area.top_px + rows_above * layout.cell_height_px, layout.cell_width_px,
          layout.cell_height_px};
}

std::string GridMapCellColor(const GridMapCell& cell) { return Hex(FillOf(cell)); }

std::string GridMapCellText(const GridMapCell& cell) {
  if (cell.cases == 0) return kEnDash;
  if (cell.cases == 1) return cell.passed >= 1 ? "pass" : "fail";
  return std::to_string(std::min(cell.passed, cell.cases)) + "/" + std::to_string(cell.cases);
}

std::string RenderGridMapSvg(const GridMap& map) {
  const GridMapLayout layout = GridMapLayoutOf(map);
  return SvgDocumentStart(layout.doc_width_px, layout.doc_height_px) + Cells(map, layout) +
         SvgFrame(layout.area) + TickLabels(map, layout) + Labels(map, layout) +
         Legend(map, layout) + "</svg>\n";
}

}  // namespace hilrig::host
