// The tag layout file of floor commissioning: AprilTags (tag36h11) laid flat
// on the floor at surveyed poses, and optionally the vehicle's surveyed poses
// for each image. Format, frames and corner order: docs/tag_layout.md.
//
//   format: groundline-tag-layout
//   version: "1.0"
//   family: tag36h11
//   frame: floor            # or base_link (one stationary view, no vehicle_poses)
//   survey_sigma_m: 0.001   # optional: 1-sigma survey error of each tag corner, per axis
//   tags:
//     - {id: 0, size_m: 0.16, pose: {x_m: 1.2, y_m: -0.3, yaw_rad: 0.0}}
//   vehicle_poses:          # frame: floor only; base_link pose in the floor frame
//     - {image: frame_000.png, pose: {x_m: -0.5, y_m: 0.02, yaw_rad: 0.01}}
//
// size_m is libapriltag's tag size: the edge of the outer black square. The
// pose is that of the tag's centre, its x axis pointing to the printed tag's
// right and y to its top (the tag lies face up, z up). Corner k of
// TagCornersInTagFrame (tag_detection.h) is libapriltag's det->p[k].
//
// Errors name the file, the line and the field. Unknown keys are errors.
#ifndef GROUNDLINE_CALIBRATION_TAG_LAYOUT_H_
#define GROUNDLINE_CALIBRATION_TAG_LAYOUT_H_

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::calibration {

inline constexpr char kTagLayoutFormat[] = "groundline-tag-layout";
inline constexpr char kTagLayoutVersion[] = "1.0";

enum class TagLayoutFrame {
  kFloor,     // tags surveyed in a floor frame, one vehicle pose per image
  kBaseLink,  // tags given in base_link: every image from one stationary pose
};

struct SurveyedTag {
  int id = 0;
  double size_m = 0.0;    // edge of the outer black square, > 0
  core::SE2 T_frame_tag;  // tag centre in the layout's frame
  // The four corners in the layout's frame (metres), det->p[0..3] order.
  std::array<Eigen::Vector2d, 4> CornersInFrame() const;
};

struct VehiclePose {
  std::string image;       // file name, relative to the image directory
  core::SE2 T_floor_base;  // base_link in the floor frame
};

struct TagLayout {
  TagLayoutFrame frame = TagLayoutFrame::kFloor;
  std::vector<SurveyedTag> tags;
  std::vector<VehiclePose> vehicle_poses;  // empty for kBaseLink
  double survey_sigma_m = 0.0;             // optional; inflates the mount covariance

  // Ok when tags is non-empty, ids are unique and in tag36h11's range, sizes
  // are > 0, poses are finite, survey_sigma_m >= 0, image names are unique and non-empty, and
  // vehicle_poses is empty for kBaseLink.
  core::Status Validate() const;
  // nullptr when the id is not in the layout.
  const SurveyedTag* FindTag(int id) const;
  // nullptr when the image has no pose in the layout.
  const VehiclePose* FindPose(const std::string& image) const;
};

core::Result<TagLayout> ParseTagLayoutYaml(const std::string& yaml_text,
                                           const std::string& source_name);
core::Result<TagLayout> ReadTagLayout(const std::filesystem::path& path);
// The file text of a valid layout (asserted); numbers in shortest round-trip form.
std::string TagLayoutToYaml(const TagLayout& layout);
// Writes atomically (PATH.tmp, then rename); fails for an invalid layout.
core::Status WriteTagLayout(const TagLayout& layout, const std::filesystem::path& path);

}  // namespace groundline::calibration

#endif  // GROUNDLINE_CALIBRATION_TAG_LAYOUT_H_
