#include "groundline/sim/layout_png.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "groundline/core/atomic_file.h"
#include "options_check.h"

namespace groundline::sim {
namespace {

// Colours are BGR.
const cv::Scalar kOutside(255, 255, 255);
const cv::Scalar kConcrete(172, 176, 178);
const cv::Scalar kTrajectory(0, 0, 230);

cv::Scalar ObstacleColour(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::kWall:
      return {70, 70, 70};
    case ObstacleKind::kColumn:
      return {45, 45, 45};
    case ObstacleKind::kRackUpright:
      return {30, 30, 30};
    case ObstacleKind::kRackBeam:
      return {125, 125, 125};
    case ObstacleKind::kPallet:
      return {105, 110, 115};
    case ObstacleKind::kDockDoor:
      return {95, 95, 95};
    case ObstacleKind::kTrailer:
      return {85, 85, 85};
  }
  return {90, 90, 90};
}

cv::Scalar MarkingBgr(MarkingColour colour) {
  const std::array<int, 3> rgb = MarkingColourRgb(colour);
  return {static_cast<double>(rgb[2]), static_cast<double>(rgb[1]), static_cast<double>(rgb[0])};
}

class Canvas {
 public:
  Canvas(const Vector2& lo_m, const Vector2& hi_m, double ppm)
      : lo_m_(lo_m),
        hi_m_(hi_m),
        ppm_(ppm),
        image_(static_cast<int>(std::ceil((hi_m.y() - lo_m.y()) * ppm)),
               static_cast<int>(std::ceil((hi_m.x() - lo_m.x()) * ppm)), CV_8UC3, kOutside) {}

  // Sub-pixel points (OpenCV's `shift`) for anti-aliased drawing.
  cv::Point Px(const Vector2& p_m) const {
    return {static_cast<int>(std::lround((p_m.x() - lo_m_.x()) * ppm_ * kScale)),
            static_cast<int>(std::lround((hi_m_.y() - p_m.y()) * ppm_ * kScale))};
  }
  void FillBox(const OrientedBox& box, const cv::Scalar& colour) {
    std::vector<cv::Point> poly;
    for (const Vector2& c : box.Corners()) poly.push_back(Px(c));
    cv::fillConvexPoly(image_, poly, colour, cv::LINE_AA, kShift);
  }
  void Line(const Vector2& a, const Vector2& b, double width_m, const cv::Scalar& colour) {
    const int px = std::max(1, static_cast<int>(std::lround(width_m * ppm_)));
    cv::line(image_, Px(a), Px(b), colour, px, cv::LINE_AA, kShift);
  }
  cv::Mat& image() { return image_; }
  double ppm() const { return ppm_; }

  static constexpr int kShift = 3;
  static constexpr int kScale = 1 << kShift;

 private:
  Vector2 lo_m_;
  Vector2 hi_m_;
  double ppm_;
  cv::Mat image_;
};

void DrawMarking(const FloorMarking& m, Canvas* canvas) {
  const cv::Scalar colour = MarkingBgr(m.colour);
  const double width_m = m.kind == MarkingKind::kJoint ? 0.0 : m.width_m;
  const double period = m.dash_length_m + m.gap_length_m;
  const bool dashed = m.kind == MarkingKind::kTapeDashed && period > 0.0;
  double s0 = 0.0;  // arc length at the start of the segment
  for (std::size_t i = 1; i < m.polyline_m.size(); ++i) {
    const Vector2 a = m.polyline_m[i - 1];
    const Vector2 b = m.polyline_m[i];
    const double len = (b - a).norm();
    if (!dashed) {
      canvas->Line(a, b, width_m, colour);
    } else if (len > 0.0) {
      for (double s = std::floor(s0 / period) * period; s < s0 + len; s += period) {
        const double u0 = std::clamp((s - s0) / len, 0.0, 1.0);
        const double u1 = std::clamp((s + m.dash_length_m - s0) / len, 0.0, 1.0);
        if (u1 > u0) canvas->Line(a + u0 * (b - a), a + u1 * (b - a), width_m, colour);
      }
    }
    s0 += len;
  }
}

void DrawScaleBar(const World& world, Canvas* canvas) {
  cv::Mat& image = canvas->image();
  const double width_m = image.cols / canvas->ppm();
  double bar_m = 1.0;
  for (double candidate : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) {
    if (candidate <= 0.2 * width_m) bar_m = candidate;
  }
  const int bar_px = static_cast<int>(std::lround(bar_m * canvas->ppm()));
  const cv::Point origin(20, image.rows - 20);
  cv::rectangle(image, origin + cv::Point(-6, -38), origin + cv::Point(bar_px + 70, 8),
                cv::Scalar(255, 255, 255), cv::FILLED);
  cv::rectangle(image, origin + cv::Point(0, -8), origin + cv::Point(bar_px, 0),
                cv::Scalar(0, 0, 0), cv::FILLED);
  for (int k = 0; k <= 2; ++k) {
    const int x = origin.x + k * bar_px / 2;
    cv::line(image, {x, origin.y - 14}, {x, origin.y}, cv::Scalar(0, 0, 0), 2);
  }
  cv::putText(image, std::to_string(static_cast<int>(bar_m)) + " m",
              origin + cv::Point(bar_px + 8, 0), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0),
              2, cv::LINE_AA);
  cv::putText(image, world.name, {20, 30}, cv::FONT_HERSHEY_SIMPLEX, 0.8, cv::Scalar(0, 0, 0), 2,
              cv::LINE_AA);
}

}  // namespace

core::Status LayoutPngOptions::Validate() const {
  return internal::FirstError({
      internal::CheckRange("LayoutPngOptions", "pixels_per_m", pixels_per_m, 0.5, 1000.0),
      internal::CheckRange("LayoutPngOptions", "margin_m", margin_m, 0.0, 1000.0),
      internal::CheckRange("LayoutPngOptions", "max_side_px", max_side_px, 64, 65000),
  });
}

core::Status WriteLayoutPng(const World& world, const core::Trajectory* trajectory,
                            const std::filesystem::path& path, const LayoutPngOptions& options) {
  if (core::Status status = options.Validate(); !status.ok()) return status;
  Vector2 lo = world.floor_min_m;
  Vector2 hi = world.floor_max_m;
  for (const Obstacle& o : world.obstacles) {
    for (const Vector2& c : o.box.Corners()) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
  }
  lo -= Vector2::Constant(options.margin_m);
  hi += Vector2::Constant(options.margin_m);
  const Vector2 size_px = (hi - lo) * options.pixels_per_m;
  if (size_px.maxCoeff() > options.max_side_px) {
    return core::Status::Error("layout PNG of " + world.name + " would be " +
                               std::to_string(static_cast<int>(size_px.x())) + " x " +
                               std::to_string(static_cast<int>(size_px.y())) +
                               " px, above max_side_px; lower pixels_per_m");
  }
  Canvas canvas(lo, hi, options.pixels_per_m);
  OrientedBox floor = OrientedBox::FromMinMax(world.floor_min_m, world.floor_max_m);
  canvas.FillBox(floor, kConcrete);
  for (const FloorMarking& m : world.markings) {
    if (m.kind == MarkingKind::kJoint) DrawMarking(m, &canvas);
  }
  for (const FloorMarking& m : world.markings) {
    if (m.kind != MarkingKind::kJoint) DrawMarking(m, &canvas);
  }
  // Beams first so that the uprights below them stay visible.
  for (bool beams : {true, false}) {
    for (const Obstacle& o : world.obstacles) {
      if ((o.kind == ObstacleKind::kRackBeam) == beams)
        canvas.FillBox(o.box, ObstacleColour(o.kind));
    }
  }
  for (const MovingObstacle& m : world.moving) {
    if (!m.PresentAt(options.moving_obstacle_stamp_s)) continue;
    const OrientedBox box = m.FootprintAt(options.moving_obstacle_stamp_s);
    if (m.IsCircle()) {
      cv::circle(canvas.image(), canvas.Px(box.center_m),
                 static_cast<int>(m.radius_m * options.pixels_per_m * Canvas::kScale) + 4,
                 cv::Scalar(200, 0, 200), cv::FILLED, cv::LINE_AA, Canvas::kShift);
    } else {
      canvas.FillBox(box, cv::Scalar(0, 140, 255));
    }
  }
  if (trajectory != nullptr && !trajectory->empty()) {
    std::vector<cv::Point> points;
    for (const core::StampedPose& p : *trajectory)
      points.push_back(canvas.Px(p.pose.translation()));
    cv::polylines(canvas.image(), points, false, kTrajectory, 2, cv::LINE_AA, Canvas::kShift);
    const core::SE2& start = trajectory->front().pose;
    cv::circle(canvas.image(), canvas.Px(start.translation()), 6 * Canvas::kScale, kTrajectory,
               cv::FILLED, cv::LINE_AA, Canvas::kShift);
    const Vector2 tip =
        start.translation() + 3.0 * Vector2(std::cos(start.yaw()), std::sin(start.yaw()));
    cv::arrowedLine(canvas.image(), canvas.Px(start.translation()), canvas.Px(tip), kTrajectory, 3,
                    cv::LINE_AA, Canvas::kShift, 0.4);
  }
  DrawScaleBar(world, &canvas);

  std::vector<unsigned char> png;
  if (!cv::imencode(".png", canvas.image(), png)) {
    return core::Status::Error("layout PNG of " + world.name + ": PNG encoding failed");
  }
  return core::WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace groundline::sim
