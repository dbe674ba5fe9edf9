// The camera front end of the localizer: one grey frame -> undistort + IPM
// (perception/bev_remap.h, one remap table) -> lines and junctions with
// covariance (perception/line_extractor.h) -> floor observations in base_link
// (observations_from_extraction.h). The service runs it on its camera thread,
// the replay and the tests inside Localizer::AddFrame.
//
// Thread-safety: immutable after construction; Observe may run concurrently
// from several threads.
#ifndef GROUNDLINE_LOCALIZATION_FLOOR_FRONT_END_H_
#define GROUNDLINE_LOCALIZATION_FLOOR_FRONT_END_H_

#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <optional>

#include "groundline/calibration/camera_extrinsics.h"
#include "groundline/calibration/camera_model.h"
#include "groundline/core/status.h"
#include "groundline/localization/observations_from_extraction.h"
#include "groundline/perception/bev_remap.h"
#include "groundline/perception/line_extractor.h"

namespace groundline::localization {

struct FloorFrontEndOptions {
  // The BEV's sampling; its grid (remap.grid) is replaced by the one of `bev`.
  perception::BevRemap::Options remap = perception::BevRemap::Options::ForLineExtraction();
  // The BEV's extent (perception::ResolveBevGrid): by default the camera's
  // floor footprint at 1 cm cells.
  perception::BevExtent bev;
  perception::LineExtractorOptions extractor = perception::LineExtractorOptions::ForFusion();
  // The sampling of the floor texture's BEV (TextureBev): the BEV's extent
  // at texture.grid.cell_m (the rest of texture.grid is not used).
  perception::BevRemap::Options texture = perception::BevRemap::Options::ForTextureTracking();
  // A frame whose grey levels spread less than this (standard deviation over
  // a grid of samples) is blank: a covered lens, a blacked-out or saturated
  // camera. It is refused (an error), not read as a floor without markings.
  double min_frame_stddev = 2.0;
  // The mount's error is one error common to every frame until the mount
  // changes: each keyframe that sees a marking sees it displaced alike. The
  // smoother takes each keyframe's sighting as independent, so the mount's
  // share of a line's covariance (WithMount) is multiplied by the number of
  // keyframes that see one marking: N independent sightings of R + N C carry
  // the information of one marking seen with R / N + C, which is what N
  // sightings with a common error C carry. The reference camera sees 1.8 m of
  // floor along the drive and keyframes are 0.2-0.35 m apart: 5-9 sightings.
  double mount_error_sightings = 6.0;

  core::Status Validate() const;
};

class FloorFrontEnd {
 public:
  // Errors: invalid options; a camera that sees no floor cell of the grid.
  static core::Result<FloorFrontEnd> Create(const calibration::CameraModel& camera,
                                            const calibration::CameraMount& mount,
                                            const FloorFrontEndOptions& options = {});

  // The frame's lines and junctions, stamped stamp_s. Errors: an empty frame,
  // one whose size is not the camera model's, a blank one (min_frame_stddev).
  core::Result<ConvertedObservations> Observe(const cv::Mat& grey, double stamp_s) const;
  // The same, also returning the BEV image (for a status page or an overlay)
  // in *bev, whose buffer is reused when it has the BEV's size. scratch: the
  // extractor's working images (perception::ExtractionScratch; null: this
  // call's own). A caller observing frame after frame keeps both, so that no
  // frame allocates frame-sized buffers.
  core::Result<ConvertedObservations> Observe(
      const cv::Mat& grey, double stamp_s, cv::Mat* bev,
      perception::ExtractionScratch* scratch = nullptr) const;

  // The frame's BEV for tracking the floor's texture (FloorFlowTracker): the
  // BEV's extent and mount at the finer cells of options.texture, with its
  // seen cells. Its table is built at the first call on this mount (about
  // the cost of the BEV's own), and shared with the copies WithMount makes
  // for the same mount. Errors: a frame that is not an 8-bit grey image of
  // the camera's size.
  core::Status TextureBev(const cv::Mat& grey, BevFrame* out) const;

  // The same camera and options on another mount (a self-calibrated one),
  // with the mount's uncertainty: `mount_covariance` over (pitch_rad,
  // roll_rad, height_m, yaw_rad) (mount_self_calibration.h's order), carried
  // into every line's and junction's covariance (J C J^T through
  // calibration::FloorPointMountJacobian, times the options'
  // mount_error_sightings; zero: none, as Create). The
  // remap table is rebuilt on this one's grid (the BEV keeps its size and
  // extent; cells the new mount does not see become unseen); the extractor is
  // rebuilt for the new table. About the cost of Create: not per frame
  // (the same mount with another covariance shares this one's table: cheap).
  //
  // `observed`: the mount the observations are expressed under, when it is
  // not the BEV's (the best estimate of the mount, which the BEV follows
  // only in bounded steps, or a step the self-calibration suspects before
  // it confirms it): every line's endpoints and every junction are moved
  // from the BEV's mount to it (calibration::RemapFloorPoint, exact: the map
  // between two mounts is a floor-to-floor homography), the observations
  // carry it as their camera_mount, and `mount_covariance` is about it.
  // Unset: the BEV's mount.
  // Errors: an invalid mount, a covariance that is not symmetric positive
  // semi-definite, a mount that sees none of the grid.
  core::Result<FloorFrontEnd> WithMount(
      const calibration::CameraMount& mount, const Eigen::Matrix4d& mount_covariance,
      const std::optional<calibration::CameraMount>& observed = std::nullopt) const;

  // The BEV's mount.
  const calibration::CameraMount& mount() const { return remap_->mount(); }
  // The mount the observations are expressed under (WithMount's `observed`).
  const calibration::CameraMount& observed_mount() const {
    return observed_mount_ ? *observed_mount_ : remap_->mount();
  }
  const Eigen::Matrix4d& mount_covariance() const { return mount_covariance_; }
  const perception::BevRemap& remap() const { return *remap_; }
  const perception::LineExtractor& extractor() const { return *extractor_; }
  // The floor the camera sees on this grid (the convex hull of the seen
  // cells); every observation carries it.
  const std::shared_ptr<const FloorView>& view() const { return view_; }
  int image_width_px() const { return width_px_; }
  int image_height_px() const { return height_px_; }

 private:
  FloorFrontEnd() = default;
  static core::Result<FloorFrontEnd> Build(const calibration::CameraModel& camera,
                                           const calibration::CameraMount& mount,
                                           const perception::BevRemap::Options& remap_options,
                                           const FloorFrontEndOptions& options);
  // Moves the observations from the BEV's mount to the observed one.
  void ExpressUnderObservedMount(FloorObservations* observations) const;
  // Adds the mount's uncertainty to the observations' covariances.
  void AddMountUncertainty(FloorObservations* observations) const;

  FloorFrontEndOptions options_;
  perception::BevRemap::Options remap_options_;  // the grid as built
  Eigen::Matrix4d mount_covariance_ = Eigen::Matrix4d::Zero();
  std::optional<calibration::CameraMount> observed_mount_;  // unset: the BEV's
  std::shared_ptr<const perception::BevRemap> remap_;
  std::shared_ptr<const perception::LineExtractor> extractor_;
  std::shared_ptr<const FloorView> view_;
  // TextureBev's table, built at its first call (thread-safe).
  struct TextureTable {
    std::once_flag built;
    std::shared_ptr<const perception::BevRemap> remap;
  };
  std::shared_ptr<TextureTable> texture_;
  int width_px_ = 0;
  int height_px_ = 0;
  double min_frame_stddev_ = 0.0;
};

}  // namespace groundline::localization

#endif  // GROUNDLINE_LOCALIZATION_FLOOR_FRONT_END_H_
