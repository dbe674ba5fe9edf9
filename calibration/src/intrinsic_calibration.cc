#include "groundline/calibration/intrinsic_calibration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "mrcal_problem.h"
#include "text_util.h"

// libmrcal 2.2's mrcal_optimize leaks its libdogleg solver context (and the
// cholmod factorization it holds) each time its outlier-rejection loop throws
// out corners and solves again ("Threw out some outliers ...; going again").
// The leak is in the library, bounded by the number of re-solves; tell
// LeakSanitizer, when it runs, not to report it.
#if defined(GROUNDLINE_SANITIZED)
extern "C" const char* __lsan_default_suppressions() { return "leak:libdogleg.so\n"; }
#endif

namespace groundline::calibration {
namespace {

struct LensInfo {
  int distortions = 0;  // OpenCV-style terms
};

std::optional<LensInfo> SupportedLens(const std::string& name) {
  if (name == "LENSMODEL_PINHOLE") return LensInfo{0};
  if (name == "LENSMODEL_OPENCV4") return LensInfo{4};
  if (name == "LENSMODEL_OPENCV5") return LensInfo{5};
  if (name == "LENSMODEL_OPENCV8") return LensInfo{8};
  if (name == "LENSMODEL_OPENCV12") return LensInfo{12};
  return std::nullopt;
}

Eigen::Vector3d WarpedPoint_board(const BoardGrid& grid, int index,
                                  const std::optional<std::array<double, 2>>& warp) {
  Eigen::Vector3d p = grid.Point_board(index);
  if (warp) {
    const double xr = static_cast<double>(index % grid.width_n) / (grid.width_n - 1);
    const double yr = static_cast<double>(index / grid.width_n) / (grid.height_n - 1);
    p.z() += (*warp)[0] * 4.0 * xr * (1.0 - xr) + (*warp)[1] * 4.0 * yr * (1.0 - yr);
  }
  return p;
}

core::Result<OpenCvSeedResult> OpenCvSeed(const std::vector<CalibrationView>& views,
                                          const BoardGrid& grid, int width_px, int height_px,
                                          int distortions, bool fix_aspect_ratio,
                                          std::vector<cv::Mat>* rvecs,
                                          std::vector<cv::Mat>* tvecs) {
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const CalibrationView& view : views) {
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (std::size_t i = 0; i < view.observation.grid_index.size(); ++i) {
      const Eigen::Vector3d p = grid.Point_board(view.observation.grid_index[i]);
      obj.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
      img.emplace_back(static_cast<float>(view.observation.corners_px[i].x()),
                       static_cast<float>(view.observation.corners_px[i].y()));
    }
    object_points.push_back(std::move(obj));
    image_points.push_back(std::move(img));
  }
  int flags = 0;
  if (distortions < 5) flags |= cv::CALIB_FIX_K3;
  if (distortions == 0) flags |= cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_ZERO_TANGENT_DIST;
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  if (fix_aspect_ratio) flags |= cv::CALIB_FIX_ASPECT_RATIO;  // ratio of K: 1
  cv::Mat dist = cv::Mat::zeros(5, 1, CV_64F);
  cv::Mat std_intrinsics, std_extrinsics, per_view;
  OpenCvSeedResult seed;
  try {
    seed.rms_px =
        cv::calibrateCamera(object_points, image_points, cv::Size(width_px, height_px), K, dist,
                            *rvecs, *tvecs, std_intrinsics, std_extrinsics, per_view, flags);
  } catch (const cv::Exception& e) {
    return core::Status::Error(std::string("OpenCV calibrateCamera (the seed) failed: ") +
                               e.what());
  }
  seed.intrinsics = {K.at<double>(0, 0), K.at<double>(1, 1), K.at<double>(0, 2),
                     K.at<double>(1, 2)};
  for (int i = 0; i < 5; ++i) seed.intrinsics.push_back(dist.at<double>(i));
  for (int i = 0; i < per_view.rows; ++i) {
    seed.per_view_rms_px.push_back(per_view.at<double>(i));
    seed.mean_per_view_rms_px += per_view.at<double>(i) / per_view.rows;
  }
  return seed;
}

}  // namespace

namespace internal {

mrcal_stats_t SolveMrcalProblem(MrcalProblem* p, const BoardGrid& grid, std::vector<double>* x,
                                bool verbose) {
  const int n_views = static_cast<int>(p->frames.size());
  std::vector<mrcal_observation_board_t> observations(n_views);
  for (int i = 0; i < n_views; ++i) observations[i] = {{0, -1}, i};
  const mrcal_problem_constants_t constants = {-1.0, -1.0};
  const int n_x = mrcal_num_measurements(n_views, 0, grid.width_n, grid.height_n, 1, 0, n_views, 0,
                                         0, p->selections, &p->lensmodel);
  x->assign(n_x, 0.0);
  return mrcal_optimize(nullptr, 0, x->data(), n_x * static_cast<int>(sizeof(double)),
                        p->intrinsics.data(), nullptr, p->frames.data(), nullptr, &p->warp, 1, 0,
                        n_views, 0, 0, observations.data(), nullptr, n_views, 0, p->pool.data(),
                        &p->lensmodel, p->imagersize, p->selections, &constants, grid.pitch_m,
                        grid.width_n, grid.height_n, verbose, false);
}

}  // namespace internal

core::Status IntrinsicCalibrationOptions::Validate() const {
  if (!SupportedLens(lens_model)) {
    return core::Status::Error("lens model '" + lens_model +
                               "' is not supported for calibration; use LENSMODEL_PINHOLE, "
                               "LENSMODEL_OPENCV4, OPENCV5, OPENCV8 or OPENCV12");
  }
  if (min_views < 1) return core::Status::Error("min_views must be >= 1");
  return core::Status::Ok();
}

core::Result<IntrinsicCalibration> CalibrateIntrinsics(const std::vector<CalibrationView>& views,
                                                       const BoardGrid& grid, int width_px,
                                                       int height_px,
                                                       const IntrinsicCalibrationOptions& options) {
  assert(options.Validate().ok());
  const auto start = std::chrono::steady_clock::now();
  if (static_cast<int>(views.size()) < options.min_views) {
    return core::Status::Error("only " + std::to_string(views.size()) +
                               " view(s) with the board detected; at least " +
                               std::to_string(options.min_views) +
                               " are needed (take more views covering the whole image)");
  }
  for (const CalibrationView& v : views) {
    if (v.observation.corners_px.size() < 4) {
      return core::Status::Error(v.name + ": fewer than 4 corners; drop this view");
    }
  }
  const LensInfo lens = *SupportedLens(options.lens_model);
  std::vector<cv::Mat> rvecs, tvecs;
  core::Result<OpenCvSeedResult> seed =
      OpenCvSeed(views, grid, width_px, height_px, std::min(lens.distortions, 5),
                 options.seed_fix_aspect_ratio, &rvecs, &tvecs);
  if (!seed.ok()) return seed.status();

  internal::MrcalProblem p;
  if (!mrcal_lensmodel_from_name(&p.lensmodel, options.lens_model.c_str())) {
    return core::Status::Error("mrcal does not know lens model " + options.lens_model);
  }
  const int n_params = mrcal_lensmodel_num_params(&p.lensmodel);
  p.intrinsics.assign(n_params, 0.0);
  for (int i = 0; i < std::min<int>(n_params, 9); ++i) p.intrinsics[i] = seed->intrinsics[i];
  p.imagersize[0] = width_px;
  p.imagersize[1] = height_px;
  const int n_views = static_cast<int>(views.size());
  const int n_grid = grid.width_n * grid.height_n;
  p.frames.resize(n_views);
  p.pool.assign(static_cast<std::size_t>(n_views) * n_grid, mrcal_point3_t{{0.0, 0.0, -1.0}});
  for (int i = 0; i < n_views; ++i) {
    for (int k = 0; k < 3; ++k) {
      p.frames[i].r.xyz[k] = rvecs[i].at<double>(k);
      p.frames[i].t.xyz[k] = tvecs[i].at<double>(k);
    }
    const BoardObservation& obs = views[i].observation;
    for (std::size_t j = 0; j < obs.grid_index.size(); ++j) {
      p.pool[static_cast<std::size_t>(i) * n_grid + obs.grid_index[j]] =
          mrcal_point3_t{{obs.corners_px[j].x(), obs.corners_px[j].y(), 1.0}};
    }
  }

  // Stage 1: everything but the board flex, no outlier rejection; stage 2:
  // the full problem from there.
  mrcal_problem_selections_t& selections = p.selections;
  selections.do_optimize_intrinsics_core = true;
  selections.do_optimize_intrinsics_distortions = lens.distortions > 0;
  selections.do_optimize_frames = true;
  selections.do_apply_regularization = options.regularization;
  std::vector<double> x;
  internal::SolveMrcalProblem(&p, grid, &x, options.verbose);
  selections.do_optimize_calobject_warp = options.optimize_board_warp;
  selections.do_apply_outlier_rejection = options.outlier_rejection;
  const mrcal_stats_t stats = internal::SolveMrcalProblem(&p, grid, &x, options.verbose);

  core::Result<CameraModel> camera =
      CameraModel::Create(options.lens_model, p.intrinsics, width_px, height_px);
  if (!camera.ok()) {
    return core::Status::Error("the mrcal solve gave an invalid camera (" + camera.message() +
                               "); check the views and the target definition");
  }
  IntrinsicCalibration result{*camera, {}, {}, std::move(seed).value(), grid, options, {}, {}};
  if (core::Result<CalibrationCovariance> cov = internal::ComputeCalibrationCovariance(p, grid);
      cov.ok()) {
    result.covariance = std::move(cov).value();
  } else {
    result.covariance_error = cov.message();
  }
  IntrinsicCalibrationSummary& s = result.summary;
  if (options.optimize_board_warp) s.board_warp_m = std::array<double, 2>{p.warp.x2, p.warp.y2};
  s.mrcal_rms_px = stats.rms_reproj_error__pixels;
  double sum_sq = 0.0;
  int inliers = 0;
  for (int i = 0; i < n_views; ++i) {
    ViewResult v;
    v.name = views[i].name;
    for (int k = 0; k < 3; ++k) {
      v.rt_cam_board[k] = p.frames[i].r.xyz[k];
      v.rt_cam_board[3 + k] = p.frames[i].t.xyz[k];
    }
    const Eigen::Vector3d r(v.rt_cam_board[0], v.rt_cam_board[1], v.rt_cam_board[2]);
    const Eigen::Matrix3d R = r.norm() > 0 ? Eigen::AngleAxisd(r.norm(), r.normalized()).matrix()
                                           : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d t(v.rt_cam_board[3], v.rt_cam_board[4], v.rt_cam_board[5]);
    const BoardObservation& obs = views[i].observation;
    const int x0 = mrcal_measurement_index_boards(i, n_views, 0, grid.width_n, grid.height_n);
    double view_sq = 0.0;
    for (std::size_t j = 0; j < obs.grid_index.size(); ++j) {
      const int g = obs.grid_index[j];
      const bool outlier = p.pool[static_cast<std::size_t>(i) * n_grid + g].z < 0.0;
      core::Result<Eigen::Vector2d> q =
          result.camera.Project(R * WarpedPoint_board(grid, g, s.board_warp_m) + t);
      const Eigen::Vector2d res =
          q.ok() ? Eigen::Vector2d(*q - obs.corners_px[j])
                 : Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0.0);
      v.grid_index.push_back(g);
      v.observed_px.push_back(obs.corners_px[j]);
      v.residual_px.push_back(res);
      v.outlier.push_back(outlier ? 1 : 0);
      if (outlier) {
        ++s.outliers;
        continue;
      }
      const Eigen::Vector2d mrcal_res(x[x0 + 2 * g], x[x0 + 2 * g + 1]);
      s.residual_check_px = std::max(s.residual_check_px, (mrcal_res - res).norm());
      view_sq += res.squaredNorm();
      v.worst_px = std::max(v.worst_px, res.norm());
      ++v.inliers;
    }
    s.points += static_cast<int>(obs.grid_index.size());
    v.rms_px = v.inliers > 0 ? std::sqrt(view_sq / v.inliers) : 0.0;
    s.worst_px = std::max(s.worst_px, v.worst_px);
    sum_sq += view_sq;
    inliers += v.inliers;
    result.views.push_back(std::move(v));
  }
  s.rms_px = inliers > 0 ? std::sqrt(sum_sq / inliers) : 0.0;
  s.solve_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::string MrcalCornersVnl(const std::vector<CalibrationView>& views, const BoardGrid& grid) {
  std::ostringstream out;
  out << "# filename x y level\n";
  const int n_grid = grid.width_n * grid.height_n;
  for (const CalibrationView& view : views) {
    std::vector<const Eigen::Vector2d*> at(n_grid, nullptr);
    for (std::size_t j = 0; j < view.observation.grid_index.size(); ++j) {
      at[view.observation.grid_index[j]] = &view.observation.corners_px[j];
    }
    for (int g = 0; g < n_grid; ++g) {
      out << view.name << ' ';
      if (at[g] == nullptr) {
        out << "- - -\n";
      } else {
        out << text_util::ShortestDecimal(at[g]->x()) << ' '
            << text_util::ShortestDecimal(at[g]->y()) << " 0\n";
      }
    }
  }
  return out.str();
}

}  // namespace groundline::calibration
