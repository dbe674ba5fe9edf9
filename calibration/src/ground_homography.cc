#include "groundline/calibration/ground_homography.h"
#include "groundline/core/yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <vector>

#include "text_util.h"
#include "yaml_text.h"
#include "yaml_util.h"

namespace groundline::calibration {
namespace {

using yaml_util::Where;

// 9 numbers, flat or as 3 rows of 3.
core::Result<Eigen::Matrix3d> ReadMatrix(const YAML::Node& root, const std::string& source) {
  const YAML::Node node = root["homography"];
  const std::string where = yaml_util::KeyWhere(root, source, "homography");
  std::vector<YAML::Node> items;
  if (node.IsSequence() && node.size() == 3 && node[0].IsSequence()) {
    for (size_t r = 0; r < 3; ++r) {
      if (!node[r].IsSequence() || node[r].size() != 3) {
        return core::Status::Error(where + ": expected 3 rows of 3 numbers");
      }
      for (size_t c = 0; c < 3; ++c) items.push_back(node[r][c]);
    }
  } else if (node.IsSequence() && node.size() == 9) {
    for (size_t i = 0; i < 9; ++i) items.push_back(node[i]);
  } else {
    return core::Status::Error(
        where + ": expected 9 numbers (row-major) or 3 rows of 3, got " +
        (node.IsSequence() ? std::to_string(node.size()) + " items" : std::string("no list")));
  }
  Eigen::Matrix3d H;
  for (size_t i = 0; i < 9; ++i) {
    double value = 0.0;
    bool ok = items[i].IsScalar();
    try {
      if (ok) value = items[i].as<double>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
    if (!ok || !std::isfinite(value)) {
      return core::Status::Error(Where(source, items[i]) + ": key 'homography' element " +
                                 std::to_string(i) + ": expected a finite number, got '" +
                                 (items[i].IsScalar() ? items[i].Scalar() : "a non-scalar") + "'");
    }
    H(static_cast<int>(i / 3), static_cast<int>(i % 3)) = value;
  }
  const double scale = H.norm();
  if (!(std::abs(H.determinant()) > 1e-12 * scale * scale * scale)) {
    return core::Status::Error(where + ": the matrix is singular; it maps no image to a plane");
  }
  return H;
}

}  // namespace

namespace {

core::Result<GroundHomography> ParseGroundHomographyYamlUnguarded(const std::string& yaml_text,
                                                                  const std::string& source_name) {
  const core::Result<YAML::Node> loaded = internal::LoadYamlText(yaml_text, source_name);
  if (!loaded.ok()) return loaded.status();
  const YAML::Node& root = *loaded;  // const: absent keys must not be inserted
  if (!root.IsMap() || !root["homography"]) {
    return core::Status::Error(source_name +
                               ": missing key 'homography' (the 3x3 image-to-floor "
                               "matrix)");
  }
  GroundHomography result;
  const YAML::Node version = root["version"];
  if (version) {
    if (!version.IsScalar() || version.Scalar() != "2") {
      return core::Status::Error(yaml_util::KeyWhere(root, source_name, "version") +
                                 ": expected '2' (Duckietown HomographyToolkit), "
                                 "got '" +
                                 (version.IsScalar() ? version.Scalar() : "") + "'");
    }
    if (const YAML::Node format = root["format"]; format) {
      return core::Status::Error(
          yaml_util::KeyWhere(root, source_name, "format") + ": '" +
          (format.IsScalar() ? format.Scalar() : "") +
          "' homographies depend on the image size and are not supported; only version-2 "
          "files without 'format' (input: normalized image coordinates) are read");
    }
    if (const YAML::Node date = root["date"]; date && date.IsScalar()) result.date = date.Scalar();
    result.input = HomographyInput::kNormalizedImage;
  }
  core::Result<Eigen::Matrix3d> H = ReadMatrix(root, source_name);
  if (!H.ok()) return H.status();
  result.H_floor_input = *H;
  if (result.input == HomographyInput::kRectifiedPixel) {
    // The Duckiebot frame is right-handed, z up: det(H) < 0 (see the header).
    if (result.H_floor_input.determinant() > 0.0) result.H_floor_input *= -1.0;
    result.floor_frame_right_handed = true;
  } else {
    // lambda > 0 for the ray 45 deg below the optical axis (see the header).
    if (result.H_floor_input.row(2).dot(Eigen::Vector3d(0.0, 1.0, 1.0)) < 0.0) {
      result.H_floor_input *= -1.0;
    }
    result.floor_frame_right_handed = result.H_floor_input.determinant() < 0.0;
  }
  return result;
}

}  // namespace

// A yaml-cpp exception escaping the walk becomes an error (no reader throws).
core::Result<GroundHomography> ParseGroundHomographyYaml(const std::string& yaml_text,
                                                         const std::string& source_name) {
  return core::internal::CatchYamlErrors(
      source_name, [&] { return ParseGroundHomographyYamlUnguarded(yaml_text, source_name); });
}

core::Result<GroundHomography> ReadGroundHomographyYaml(const std::filesystem::path& path) {
  core::Result<std::string> text = text_util::ReadTextFile(path, "ground homography file");
  if (!text.ok()) return text.status();
  return ParseGroundHomographyYaml(*text, path.string());
}

Eigen::Matrix3d FloorFromNormalizedImage(const GroundHomography& homography,
                                         const Eigen::Matrix3d& K_rectified) {
  if (homography.input == HomographyInput::kNormalizedImage) return homography.H_floor_input;
  return homography.H_floor_input * K_rectified;
}

core::Result<GroundHomographyMount> MountFromGroundHomography(const GroundHomography& homography,
                                                              const Eigen::Matrix3d& K_rectified) {
  GroundHomographyMount out;
  Eigen::Matrix3d H_floor_norm = FloorFromNormalizedImage(homography, K_rectified);
  out.mirrored_y = !homography.floor_frame_right_handed;
  if (out.mirrored_y) H_floor_norm.row(1) *= -1.0;
  Eigen::Matrix3d H_norm_floor;
  bool invertible = false;
  H_floor_norm.computeInverseWithCheck(H_norm_floor, invertible);
  if (!invertible || !H_norm_floor.allFinite()) {
    return core::Status::Error("ground homography: singular matrix");
  }
  // The sign convention (see the header) puts the floor point of the
  // normalized input (0, 1) in front of the camera.
  const Eigen::Vector3d in_view = H_floor_norm * Eigen::Vector3d(0.0, 1.0, 1.0);
  if (!(std::abs(in_view.z()) > 0.0)) {
    return core::Status::Error(
        "ground homography: the ray 45 deg below the optical axis does not meet the floor");
  }
  core::Result<CameraMount> mount = MountFromFloorHomography(H_norm_floor, in_view.hnormalized());
  if (!mount.ok()) return mount.status().WithContext("ground homography");
  out.mount = *mount;
  return out;
}

core::Result<Eigen::Vector2d> FloorPointOfPixel(const CameraModel& camera,
                                                const Eigen::Matrix3d& H_floor_norm,
                                                const Eigen::Vector2d& pixel,
                                                Eigen::Matrix2d* J_floor_pixel) {
  Eigen::Matrix<double, 3, 2> J_ray_pixel;
  core::Result<Eigen::Vector3d> ray = camera.Unproject(
      pixel, RayNormalization::kZEqualsOne, J_floor_pixel != nullptr ? &J_ray_pixel : nullptr);
  if (!ray.ok()) return ray.status();
  const Eigen::Vector3d g = H_floor_norm * *ray;
  if (!(g.z() > 0.0)) {
    std::ostringstream out;
    out << "pixel (" << pixel.x() << ", " << pixel.y()
        << ") is on or above the horizon of the ground homography";
    return core::Status::Error(out.str());
  }
  const Eigen::Vector2d floor = g.head<2>() / g.z();
  if (J_floor_pixel != nullptr) {
    // d(g_xy / g_z)/dn = (H_xy,n g_z - g_xy H_z,n) / g_z^2 over the first two
    // components n of the z = 1 ray.
    const Eigen::Matrix2d J_floor_norm = (H_floor_norm.topLeftCorner<2, 2>() * g.z() -
                                          g.head<2>() * H_floor_norm.block<1, 2>(2, 0)) /
                                         (g.z() * g.z());
    *J_floor_pixel = J_floor_norm * J_ray_pixel.topRows<2>();
  }
  return floor;
}

}  // namespace groundline::calibration
