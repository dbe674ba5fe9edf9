// A synthetic straight rack aisle for the mount self-calibration's tests:
// the markings' segments as a BEV made with a given mount shows them, for a
// given true mount, along a gently wobbling drive (calibration and
// localization tests share it). Its code is in synthetic_aisle.cc, compiled
// at the build's optimization level: the tests themselves compile at -O0,
// and a drive of frames is most of their work.
#ifndef GROUNDLINE_TESTS_SUPPORT_SYNTHETIC_AISLE_H_
#define GROUNDLINE_TESTS_SUPPORT_SYNTHETIC_AISLE_H_

#include <Eigen/Core>
#include <optional>
#include <random>
#include <vector>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/mount_self_calibration.h"
#include "groundline/core/se2.h"

namespace groundline::testing_aisle {

using calibration::CameraMount;
using calibration::FloorSegment;
using calibration::MountFrame;
using calibration::MountVector;

// The mount moved by the given amounts (degrees, millimetres).
CameraMount Moved(CameraMount m, double pitch_deg, double roll_deg, double height_mm,
                  double yaw_deg);

// A straight rack aisle along world x: two lane tapes 1.2 m apart, a joint
// near the centre line, transverse joints every 3 m and stop bars (two edges
// 5 cm apart) every 9 m.
struct WorldLine {
  Eigen::Vector2d a, b;
};
std::vector<WorldLine> Aisle(double length_m);

// What the camera's floor footprint holds (base_link): 0.7-2.2 m ahead,
// widening from +-0.35 m to +-1.0 m.
bool InView(const Eigen::Vector2d& p);

struct Drive {
  std::vector<WorldLine> world;
  double speed_mps = 1.5;
  double rate_hz = 10.0;
  double wobble_m = 0.04;     // lateral path deviation amplitude
  double sigma_m = 0.001;     // endpoint noise across the line
  int clutter_per_frame = 0;  // random segments that are no marking
  // The floor's texture: this many patches tracked from the previous frame
  // into each frame (MountFrame::flow), each point with this noise per axis;
  // a share of them move as no floor point does (the edge of something
  // standing on the floor, glare): outliers.
  int texture_points = 0;
  double texture_sigma_m = 0.001;
  double texture_outlier_share = 0.0;
  std::mt19937 rng{7};
  // The frame made last (the texture is tracked from it).
  struct Previous {
    double stamp_s;
    core::SE2 T_odom_base;
    CameraMount truth, used;
  };
  std::optional<Previous> previous;
};

// The truth's pose at t: along x at speed, a gentle lateral wobble.
core::SE2 PoseAt(const Drive& d, double t);

// One frame: each marking's part in view, under the true mount, as the BEV
// made with `used` shows it, with noise across the line and its covariance.
MountFrame MakeFrame(Drive& d, double t, const CameraMount& truth, const CameraMount& used);

// The frames from t0 to t1 at the drive's rate.
std::vector<MountFrame> Frames(Drive& d, double t0, double t1, const CameraMount& truth,
                               const CameraMount& used);

MountVector Difference(const CameraMount& a, const CameraMount& b);

}  // namespace groundline::testing_aisle

#endif  // GROUNDLINE_TESTS_SUPPORT_SYNTHETIC_AISLE_H_
