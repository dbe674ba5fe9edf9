// Printable calibration targets at exact scale: SVG (vector, millimetre user
// units: width="297mm" viewBox="0 0 297 210", so 1 user unit = 1 mm) and PNG
// (raster at a chosen DPI, for printers or viewers without SVG).
//
// Every sheet carries a 100 mm scale bar (10 mm black/white segments; 50 mm
// on sheets too narrow) and a caption with the target name and dimensions:
// print at 100 % ("actual size", no fit-to-page) and check the bar with a
// ruler before using the sheet.
//
// Layouts (board frame of calib_target.h: origin at the pattern's top-left):
//   chessboard   (inner_corners_x + 1) x (inner_corners_y + 1) squares, the
//                top-left square black.
//   aprilgrid    tag (c, r) (id first_id + r * tags_x + c) has its black
//                border's top-left corner at (c, r) * tag_size * (1 +
//                spacing_ratio); the one-cell white border of each tag lies
//                in the gaps.
//   floor tag    one tag per sheet, centred, with its id and size in text;
//                centre marks: the tag's two centre lines in thin red from
//                the page edges up to the quiet zone (they stop there: a line
//                touching the tag's outline breaks its detection), meeting at
//                the tag centre when extended, to align the sheet on floor
//                marks; and corner marks outside the quiet zone.
// Paper: a board's `paper` (A4, A3, ... A0, "_landscape" suffix) or else the
// smallest ISO A sheet that holds the pattern with 10 mm margins and the
// caption strip.
//
// Tag bit patterns come from libapriltag (apriltag_to_image of tag36h11).
#ifndef GROUNDLINE_CALIBRATION_TARGET_RENDER_H_
#define GROUNDLINE_CALIBRATION_TARGET_RENDER_H_

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "groundline/calibration/calib_target.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

// tag36h11 tag `id` as its 10 x 10 cells (row-major from the top-left, 1 =
// white, 0 = black), the white outer border included, as libapriltag draws it.
// id must be in 0..586 (asserted).
std::vector<std::uint8_t> Tag36h11Cells(int id);

struct SheetPrimitive {
  enum class Kind { kRect, kLine, kText } kind = Kind::kRect;
  double x_mm = 0, y_mm = 0, w_mm = 0, h_mm = 0;  // rect; line: (x, y) to (x + w, y + h)
  double stroke_mm = 0.0;                         // line width
  std::uint32_t rgb = 0x000000;
  std::string text;  // text: baseline-left at (x, y), height h_mm
};

struct TargetSheet {
  std::string file_stem;  // e.g. "aprilgrid_6x6_88mm" or "floor_tags_a4_160mm_id007"
  double width_mm = 0.0;
  double height_mm = 0.0;
  std::string paper;  // e.g. "A3_landscape"
  // Top-left of the pattern (board frame origin) on the page, mm.
  double origin_x_mm = 0.0;
  double origin_y_mm = 0.0;
  std::vector<SheetPrimitive> primitives;  // white page, drawn in order
};

// The sheets of a target (one for a board, `count` for floor tags). Fails when
// the pattern does not fit the requested paper.
core::Result<std::vector<TargetSheet>> LayoutTarget(const CalibTarget& target);

std::string SheetToSvg(const TargetSheet& sheet);
// A BGR image of round(size_mm / 25.4 * dpi) pixels; dpi > 0 (asserted).
cv::Mat RasterizeSheet(const TargetSheet& sheet, double dpi);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_TARGET_RENDER_H_
