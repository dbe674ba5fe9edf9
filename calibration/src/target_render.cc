#include "groundline/calibration/target_render.h"

#include <cassert>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "groundline/calibration/tag_detection.h"
#include "xml_text.h"

namespace groundline::calibration {
namespace {

constexpr double kMarginMm = 10.0;
constexpr double kCaptionMm = 30.0;  // strip under the pattern: scale bar + caption
constexpr std::uint32_t kBlack = 0x000000;
constexpr std::uint32_t kWhite = 0xffffff;
constexpr std::uint32_t kRed = 0xe00000;

struct Paper {
  const char* name;
  double w_mm, h_mm;
};
constexpr Paper kPapers[] = {
    {"A4", 210, 297},  {"A4_landscape", 297, 210}, {"A3", 297, 420}, {"A3_landscape", 420, 297},
    {"A2", 420, 594},  {"A2_landscape", 594, 420}, {"A1", 594, 841}, {"A1_landscape", 841, 594},
    {"A0", 841, 1189}, {"A0_landscape", 1189, 841}};

SheetPrimitive Rect(double x, double y, double w, double h, std::uint32_t rgb) {
  SheetPrimitive p;
  p.kind = SheetPrimitive::Kind::kRect;
  p.x_mm = x, p.y_mm = y, p.w_mm = w, p.h_mm = h, p.rgb = rgb;
  return p;
}
SheetPrimitive Line(double x0, double y0, double x1, double y1, double stroke, std::uint32_t rgb) {
  SheetPrimitive p;
  p.kind = SheetPrimitive::Kind::kLine;
  p.x_mm = x0, p.y_mm = y0, p.w_mm = x1 - x0, p.h_mm = y1 - y0, p.stroke_mm = stroke, p.rgb = rgb;
  return p;
}
SheetPrimitive Text(double x, double y, double h, std::string text) {
  SheetPrimitive p;
  p.kind = SheetPrimitive::Kind::kText;
  p.x_mm = x, p.y_mm = y, p.h_mm = h, p.text = std::move(text);
  return p;
}

std::string Mm(double v_m) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g mm", v_m * 1000.0);
  return text;
}

// The scale bar with its labels, starting at (x, y) (top-left), length_mm long.
void AddScaleBar(double x, double y, double length_mm, std::vector<SheetPrimitive>* out) {
  for (int i = 0; i * 10.0 < length_mm; ++i) {
    out->push_back(Rect(x + i * 10.0, y, 10.0, 3.0, i % 2 == 0 ? kBlack : kWhite));
  }
  out->push_back(Line(x, y, x + length_mm, y, 0.2, kBlack));
  out->push_back(Line(x, y + 3.0, x + length_mm, y + 3.0, 0.2, kBlack));
  out->push_back(Line(x + length_mm, y, x + length_mm, y + 3.0, 0.2, kBlack));
  out->push_back(Text(x, y + 8.0, 3.5, "0"));
  out->push_back(Text(x + length_mm - 12.0, y + 8.0, 3.5,
                      std::to_string(static_cast<int>(length_mm)) + " mm"));
}

void AddTag(int id, double x0, double y0, double tag_size_mm, std::vector<SheetPrimitive>* out) {
  const std::vector<std::uint8_t> cells = Tag36h11Cells(id);
  const double cell = tag_size_mm / 8.0;
  for (int r = 0; r < 10; ++r) {
    for (int c = 0; c < 10; ++c) {
      if (cells[r * 10 + c] != 0) continue;
      out->push_back(Rect(x0 + (c - 1) * cell, y0 + (r - 1) * cell, cell, cell, kBlack));
    }
  }
}

const Paper* ChoosePaper(const std::string& requested, double need_w, double need_h) {
  for (const Paper& p : kPapers) {
    if (!requested.empty() && requested != p.name) continue;
    if (p.w_mm >= need_w && p.h_mm >= need_h) return &p;
  }
  return nullptr;
}

// The scale bar, the caption (lines split at "; ") and the printing note.
void AddCaption(TargetSheet* sheet, double y, const std::string& caption) {
  const double bar = sheet->width_mm - 2 * kMarginMm >= 110.0 ? 100.0 : 50.0;
  AddScaleBar(kMarginMm, y, bar, &sheet->primitives);
  y += 15.0;
  for (std::size_t start = 0;;) {
    const std::size_t end = caption.find("; ", start);
    sheet->primitives.push_back(Text(kMarginMm, y, 4.0, caption.substr(start, end - start)));
    y += 6.0;
    if (end == std::string::npos) break;
    start = end + 2;
  }
  sheet->primitives.push_back(Text(kMarginMm, y, 3.0,
                                   "Print at 100 % (actual size, no fit-to-page). The bar must "
                                   "measure " +
                                       std::to_string(static_cast<int>(bar)) + " mm."));
}

core::Result<TargetSheet> LayoutBoard(const CalibTarget& t) {
  const Eigen::Vector2d size_mm = t.PatternSize_m() * 1000.0;
  const Paper* paper =
      ChoosePaper(t.paper, size_mm.x() + 2 * kMarginMm, size_mm.y() + 2 * kMarginMm + kCaptionMm);
  if (paper == nullptr) {
    return core::Status::Error("target '" + t.name + "': a " + Mm(size_mm.x() / 1000) + " x " +
                               Mm(size_mm.y() / 1000) + " pattern does not fit paper '" +
                               (t.paper.empty() ? "A0" : t.paper) + "' with 10 mm margins");
  }
  TargetSheet sheet;
  sheet.file_stem = t.name;
  sheet.width_mm = paper->w_mm;
  sheet.height_mm = paper->h_mm;
  sheet.paper = paper->name;
  sheet.origin_x_mm = std::round((paper->w_mm - size_mm.x()) / 2.0);
  sheet.origin_y_mm = kMarginMm;
  std::string caption;
  if (t.type == TargetType::kChessboard) {
    const double sq = t.square_m * 1000.0;
    for (int r = 0; r <= t.inner_corners_y; ++r) {
      for (int c = 0; c <= t.inner_corners_x; ++c) {
        if ((r + c) % 2 != 0) continue;
        sheet.primitives.push_back(
            Rect(sheet.origin_x_mm + c * sq, sheet.origin_y_mm + r * sq, sq, sq, kBlack));
      }
    }
    caption = t.name + ": chessboard, " + std::to_string(t.inner_corners_x) + " x " +
              std::to_string(t.inner_corners_y) + " inner corners, squares " + Mm(t.square_m);
  } else {
    const double pitch = t.tag_size_m * (1.0 + t.spacing_ratio) * 1000.0;
    for (int r = 0; r < t.tags_y; ++r) {
      for (int c = 0; c < t.tags_x; ++c) {
        AddTag(t.first_id + r * t.tags_x + c, sheet.origin_x_mm + c * pitch,
               sheet.origin_y_mm + r * pitch, t.tag_size_m * 1000.0, &sheet.primitives);
      }
    }
    caption = t.name + ": aprilgrid tag36h11 " + std::to_string(t.tags_x) + " x " +
              std::to_string(t.tags_y) + ", ids " + std::to_string(t.first_id) + "-" +
              std::to_string(t.first_id + t.count - 1) + ", tags " + Mm(t.tag_size_m) + ", gaps " +
              Mm(t.tag_size_m * t.spacing_ratio);
  }
  AddCaption(&sheet, sheet.origin_y_mm + size_mm.y() + 8.0, caption);
  return sheet;
}

core::Result<TargetSheet> LayoutFloorSheet(const CalibTarget& t, int id) {
  const Paper* paper = ChoosePaper(t.paper, 0, 0);
  const double tag = t.tag_size_m * 1000.0;
  const double quiet = tag / 8.0;  // the white border cell
  if (tag + 2 * quiet + 2 * kMarginMm > paper->w_mm ||
      tag + 2 * quiet + 2 * kMarginMm + kCaptionMm + 40.0 > paper->h_mm) {
    return core::Status::Error("target '" + t.name + "': a " + Mm(t.tag_size_m) +
                               " tag does not fit paper " + t.paper);
  }
  TargetSheet sheet;
  char stem[64];
  std::snprintf(stem, sizeof(stem), "_id%03d", id);
  sheet.file_stem = t.name + stem;
  sheet.width_mm = paper->w_mm;
  sheet.height_mm = paper->h_mm;
  sheet.paper = paper->name;
  sheet.origin_x_mm = (paper->w_mm - tag) / 2.0;
  sheet.origin_y_mm = kMarginMm + quiet + 18.0;
  AddTag(id, sheet.origin_x_mm, sheet.origin_y_mm, tag, &sheet.primitives);
  const double cx = sheet.origin_x_mm + tag / 2.0, cy = sheet.origin_y_mm + tag / 2.0;
  // Centre marks: the tag's centre lines drawn from the page edges up to the
  // quiet zone (a line crossing the quiet zone or the tag would break its
  // outline for the detector); they cross at the tag centre.
  const double gap = quiet + 1.0;
  const double top = sheet.origin_y_mm - gap, bottom = sheet.origin_y_mm + tag + gap;
  const double left = sheet.origin_x_mm - gap, right = sheet.origin_x_mm + tag + gap;
  sheet.primitives.push_back(Line(cx, 0.0, cx, top, 0.3, kRed));
  sheet.primitives.push_back(Line(cx, bottom, cx, bottom + 4.0, 0.3, kRed));
  sheet.primitives.push_back(Line(0.0, cy, left, cy, 0.3, kRed));
  sheet.primitives.push_back(Line(right, cy, paper->w_mm, cy, 0.3, kRed));
  // Corner marks just outside the quiet zone.
  const double x0 = sheet.origin_x_mm - quiet - 2.0, x1 = sheet.origin_x_mm + tag + quiet + 2.0;
  const double y0 = sheet.origin_y_mm - quiet - 2.0, y1 = sheet.origin_y_mm + tag + quiet + 2.0;
  for (double x : {x0, x1}) {
    for (double y : {y0, y1}) {
      const double dx = x == x0 ? 8.0 : -8.0, dy = y == y0 ? 8.0 : -8.0;
      sheet.primitives.push_back(Line(x, y, x + dx, y, 0.4, kBlack));
      sheet.primitives.push_back(Line(x, y, x, y + dy, 0.4, kBlack));
    }
  }
  sheet.primitives.push_back(Text(kMarginMm, kMarginMm + 6.0, 8.0, "ID " + std::to_string(id)));
  AddCaption(&sheet, y1 + 6.0,
             t.name + ": tag36h11 id " + std::to_string(id) + "; tag " + Mm(t.tag_size_m) +
                 " (black border, outer edge); the red lines meet at the tag centre");
  return sheet;
}

std::string Hex(std::uint32_t rgb) {
  char text[8];
  std::snprintf(text, sizeof(text), "#%06x", rgb & 0xffffffu);
  return text;
}

std::string Num(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4f", v);
  std::string s = text;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

std::vector<std::uint8_t> Tag36h11Cells(int id) {
  const core::Result<TagPattern> pattern = Tag36h11Pattern(id);
  assert(pattern.ok() && pattern->total_width == 10);
  std::vector<std::uint8_t> cells(pattern->black.size());
  for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = pattern->black[i] != 0 ? 0 : 1;
  return cells;
}

core::Result<std::vector<TargetSheet>> LayoutTarget(const CalibTarget& target) {
  std::vector<TargetSheet> sheets;
  if (target.IsBoard()) {
    core::Result<TargetSheet> sheet = LayoutBoard(target);
    if (!sheet.ok()) return sheet.status();
    sheets.push_back(std::move(sheet).value());
    return sheets;
  }
  for (int id = target.first_id; id < target.first_id + target.count; ++id) {
    core::Result<TargetSheet> sheet = LayoutFloorSheet(target, id);
    if (!sheet.ok()) return sheet.status();
    sheets.push_back(std::move(sheet).value());
  }
  return sheets;
}

std::string SheetToSvg(const TargetSheet& sheet) {
  std::ostringstream s;
  s << "<?xml version='1.0' encoding='UTF-8'?>\n<svg xmlns='http://www.w3.org/2000/svg' width='"
    << Num(sheet.width_mm) << "mm' height='" << Num(sheet.height_mm) << "mm' viewBox='0 0 "
    << Num(sheet.width_mm) << ' ' << Num(sheet.height_mm) << "'>\n<rect width='"
    << Num(sheet.width_mm) << "' height='" << Num(sheet.height_mm) << "' fill='#ffffff'/>\n";
  for (const SheetPrimitive& p : sheet.primitives) {
    switch (p.kind) {
      case SheetPrimitive::Kind::kRect:
        s << "<rect x='" << Num(p.x_mm) << "' y='" << Num(p.y_mm) << "' width='" << Num(p.w_mm)
          << "' height='" << Num(p.h_mm) << "' fill='" << Hex(p.rgb)
          << "' shape-rendering='crispEdges'/>\n";
        break;
      case SheetPrimitive::Kind::kLine:
        s << "<line x1='" << Num(p.x_mm) << "' y1='" << Num(p.y_mm) << "' x2='"
          << Num(p.x_mm + p.w_mm) << "' y2='" << Num(p.y_mm + p.h_mm) << "' stroke='" << Hex(p.rgb)
          << "' stroke-width='" << Num(p.stroke_mm) << "'/>\n";
        break;
      case SheetPrimitive::Kind::kText:
        s << "<text x='" << Num(p.x_mm) << "' y='" << Num(p.y_mm) << "' font-family='sans-serif' "
          << "font-size='" << Num(p.h_mm * 1.4) << "' fill='" << Hex(p.rgb) << "'>"
          << internal::XmlEscape(p.text) << "</text>\n";
        break;
    }
  }
  s << "</svg>\n";
  return s.str();
}

cv::Mat RasterizeSheet(const TargetSheet& sheet, double dpi) {
  assert(dpi > 0.0);
  const double s = dpi / 25.4;  // px per mm
  auto px = [s](double mm) { return static_cast<int>(std::lround(mm * s)); };
  cv::Mat image(px(sheet.height_mm), px(sheet.width_mm), CV_8UC3, cv::Scalar(255, 255, 255));
  for (const SheetPrimitive& p : sheet.primitives) {
    const cv::Scalar colour(p.rgb & 0xff, (p.rgb >> 8) & 0xff, (p.rgb >> 16) & 0xff);
    switch (p.kind) {
      case SheetPrimitive::Kind::kRect: {
        // Edges rounded independently, so that abutting cells share an edge.
        const cv::Rect r(cv::Point(px(p.x_mm), px(p.y_mm)),
                         cv::Point(px(p.x_mm + p.w_mm), px(p.y_mm + p.h_mm)));
        image(r & cv::Rect(0, 0, image.cols, image.rows)).setTo(colour);
        break;
      }
      case SheetPrimitive::Kind::kLine:
        cv::line(image, cv::Point(px(p.x_mm), px(p.y_mm)),
                 cv::Point(px(p.x_mm + p.w_mm), px(p.y_mm + p.h_mm)), colour,
                 std::max(1, px(p.stroke_mm)), cv::LINE_8);
        break;
      case SheetPrimitive::Kind::kText: {
        int baseline = 0;
        const double unit =
            cv::getTextSize("H", cv::FONT_HERSHEY_SIMPLEX, 1.0, 1, &baseline).height;
        const double scale = p.h_mm * s / unit;
        cv::putText(image, p.text, cv::Point(px(p.x_mm), px(p.y_mm)), cv::FONT_HERSHEY_SIMPLEX,
                    scale, colour, std::max(1, static_cast<int>(scale * 1.5)), cv::LINE_AA);
        break;
      }
    }
  }
  return image;
}

}  // namespace groundline::calibration
