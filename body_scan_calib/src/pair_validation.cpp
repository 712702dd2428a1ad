#include <body_scan_calib/capture_decoding.h>
#include <body_scan_calib/pair_validation.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/triangulation.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace body_scan_calib {
namespace {

// The board plane (unit normal, offset) in the camera frame from a board pose.
Eigen::Vector4d boardPlane(const Eigen::Isometry3d& board_to_camera) {
  const Eigen::Vector3d normal = board_to_camera.linear().col(2);
  return {normal.x(), normal.y(), normal.z(), -normal.dot(board_to_camera.translation())};
}

// Distances of the triangulated board pixels to the plane; fills `board_pixels`.
std::vector<double> boardDistances(const std::vector<float>& xyz, const cv::Mat1b& region,
                                   const Eigen::Vector4d& plane, size_t& board_pixels) {
  std::vector<double> distances;
  board_pixels = 0;
  for (size_t i = 0; i < region.total(); ++i) {
    if (!region(static_cast<int>(i / region.cols), static_cast<int>(i % region.cols))) continue;
    ++board_pixels;
    const Eigen::Vector3d p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (p.allFinite()) distances.push_back(std::abs(plane.head<3>().dot(p) + plane[3]));
  }
  return distances;
}

// ---- the OpenCV pinhole-projector peer ----

struct PinholePeer {
  cv::Mat camera_matrix, camera_distortion, projector_matrix, projector_distortion;
  cv::Mat rotation, translation;  // camera -> projector
};

// Projector pixel (column, row) at each board corner: a homography from the camera pixels
// around the corner to their decoded projector coordinates (as the OpenCV procam tools do).
std::vector<cv::Point2f> projectorCorners(const std::vector<Eigen::Vector2d>& corners,
                                          const cv::Mat1f& columns, const cv::Mat1f& rows,
                                          std::vector<char>& found) {
  constexpr int kRadius = 20;
  std::vector<cv::Point2f> projector(corners.size());
  found.assign(corners.size(), 0);
  for (size_t c = 0; c < corners.size(); ++c) {
    std::vector<cv::Point2f> camera_points, projector_points;
    const int u0 = static_cast<int>(std::lround(corners[c].x()));
    const int v0 = static_cast<int>(std::lround(corners[c].y()));
    for (int v = std::max(0, v0 - kRadius); v <= std::min(columns.rows - 1, v0 + kRadius); ++v)
      for (int u = std::max(0, u0 - kRadius); u <= std::min(columns.cols - 1, u0 + kRadius); ++u)
        if (std::isfinite(columns(v, u)) && std::isfinite(rows(v, u))) {
          camera_points.emplace_back(u, v);
          projector_points.emplace_back(columns(v, u) - 0.5f, rows(v, u) - 0.5f);
        }
    if (camera_points.size() < 50) continue;
    const cv::Mat homography = cv::findHomography(camera_points, projector_points, cv::RANSAC, 2.0);
    if (homography.empty()) continue;
    std::vector<cv::Point2f> mapped;
    cv::perspectiveTransform(std::vector<cv::Point2f>{cv::Point2f(corners[c].x(), corners[c].y())},
                             mapped, homography);
    projector[c] = mapped[0];
    found[c] = 1;
  }
  return projector;
}

PinholePeer calibratePeer(const std::vector<std::vector<Eigen::Vector2d>>& corners,
                          const std::vector<cv::Mat1f>& columns, const std::vector<cv::Mat1f>& rows,
                          const Checkerboard& board, cv::Size camera_size,
                          cv::Size projector_size) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> camera_points, projector_points;
  const std::vector<Eigen::Vector3d> board_points = board.objectPoints();
  for (size_t view = 0; view < corners.size(); ++view) {
    std::vector<char> found;
    const std::vector<cv::Point2f> projector =
        projectorCorners(corners[view], columns[view], rows[view], found);
    std::vector<cv::Point3f> o;
    std::vector<cv::Point2f> c, p;
    for (size_t i = 0; i < corners[view].size(); ++i)
      if (found[i]) {
        o.emplace_back(board_points[i].x(), board_points[i].y(), 0);
        c.emplace_back(corners[view][i].x(), corners[view][i].y());
        p.push_back(projector[i]);
      }
    if (o.size() < 6) continue;
    object.push_back(o);
    camera_points.push_back(c);
    projector_points.push_back(p);
  }
  if (object.size() < 3)
    throw PairCalibrationError("OpenCV peer: projector corners found on fewer than 3 poses");
  PinholePeer peer;
  std::vector<cv::Mat> r, t;
  // OpenCV's defaults (5 distortion coefficients), as the procam tools call it.
  cv::calibrateCamera(object, camera_points, camera_size, peer.camera_matrix,
                      peer.camera_distortion, r, t);
  cv::calibrateCamera(object, projector_points, projector_size, peer.projector_matrix,
                      peer.projector_distortion, r, t);
  cv::Mat essential, fundamental;
  cv::stereoCalibrate(object, camera_points, projector_points, peer.camera_matrix,
                      peer.camera_distortion, peer.projector_matrix, peer.projector_distortion,
                      camera_size, peer.rotation, peer.translation, essential, fundamental,
                      cv::CALIB_FIX_INTRINSIC);
  return peer;
}

// Each pixel's ray meets the surface of its decoded projector column (Newton along the ray on
// the distorted projector column). NaN where it does not converge.
std::vector<float> triangulatePeer(const PinholePeer& peer, const cv::Mat1f& columns,
                                   double start_depth) {
  std::vector<cv::Point2f> pixels;
  std::vector<size_t> indices;
  for (int v = 0; v < columns.rows; ++v)
    for (int u = 0; u < columns.cols; ++u)
      if (std::isfinite(columns(v, u))) {
        pixels.emplace_back(u, v);
        indices.push_back(static_cast<size_t>(v) * columns.cols + u);
      }
  std::vector<float> xyz(columns.total() * 3, std::numeric_limits<float>::quiet_NaN());
  if (pixels.empty()) return xyz;
  std::vector<cv::Point2f> normalized;
  cv::undistortPoints(pixels, normalized, peer.camera_matrix, peer.camera_distortion);
  cv::Matx33d R;
  peer.rotation.convertTo(R, CV_64F);
  const cv::Vec3d T(peer.translation.at<double>(0), peer.translation.at<double>(1),
                    peer.translation.at<double>(2));
  const cv::Matx33d K = peer.projector_matrix;
  std::vector<double> d(8, 0.0);
  for (int i = 0; i < std::min<int>(8, peer.projector_distortion.total()); ++i)
    d[i] = peer.projector_distortion.at<double>(i);
  auto column_at = [&](const cv::Vec3d& ray, double depth) {
    const cv::Vec3d p = R * (ray * depth) + T;
    const double x = p[0] / p[2], y = p[1] / p[2], r2 = x * x + y * y;
    const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
    const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
    const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
    return K(0, 0) * xd + K(0, 1) * yd + K(0, 2);
  };
  for (size_t n = 0; n < pixels.size(); ++n) {
    const cv::Vec3d ray(normalized[n].x, normalized[n].y, 1.0);
    const double target = columns(pixels[n].y, pixels[n].x) - 0.5;
    double depth = start_depth;
    bool converged = false;
    for (int iteration = 0; iteration < 20 && depth > 0; ++iteration) {
      const double f = column_at(ray, depth) - target;
      if (std::abs(f) < 1e-4) {
        converged = true;
        break;
      }
      const double h = 1e-4 * depth;
      const double slope = (column_at(ray, depth + h) - column_at(ray, depth - h)) / (2 * h);
      if (!std::isfinite(slope) || slope == 0) break;
      depth -= std::clamp(f / slope, -0.5 * depth, 0.5 * depth);
    }
    if (!converged) continue;
    const size_t i = indices[n];
    for (int k = 0; k < 3; ++k) xyz[3 * i + k] = static_cast<float>(ray[k] * depth);
  }
  return xyz;
}

PlaneErrorStatistics pooled(const std::vector<std::vector<double>>& distances,
                            const std::vector<size_t>& board_pixels, double gross_mm) {
  std::vector<double> all;
  size_t pixels = 0;
  for (size_t k = 0; k < distances.size(); ++k) {
    all.insert(all.end(), distances[k].begin(), distances[k].end());
    pixels += board_pixels[k];
  }
  return planeErrorStatistics(all, pixels, gross_mm);
}

}  // namespace

PlaneErrorStatistics planeErrorStatistics(const std::vector<double>& distances_m,
                                          size_t board_pixels, double gross_mm) {
  PlaneErrorStatistics stats;
  stats.board_pixels = board_pixels;
  stats.points = distances_m.size();
  stats.coverage = board_pixels ? static_cast<double>(stats.points) / board_pixels : 0;
  if (distances_m.empty()) return stats;
  std::vector<double> sorted = distances_m;
  std::sort(sorted.begin(), sorted.end());
  auto quantile = [&](double q) {
    return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * (sorted.size() - 1)))];
  };
  stats.median_mm = quantile(0.5) * 1e3;
  stats.p95_mm = quantile(0.95) * 1e3;
  double squared = 0;
  size_t gross = 0;
  for (double d : sorted) {
    squared += d * d;
    if (d * 1e3 > gross_mm) ++gross;
  }
  stats.rms_mm = std::sqrt(squared / sorted.size()) * 1e3;
  stats.gross_share = static_cast<double>(gross) / sorted.size();
  return stats;
}

PairValidation validateLeaveOnePoseOut(const PairViews& views,
                                       const PairCalibrationOptions& options,
                                       const ValidationOptions& validation,
                                       const Progress& progress) {
  auto report = [&](const std::string& message) {
    if (progress) progress(message);
  };
  const size_t poses = views.pose_frames.size();
  if (poses < 4)
    throw PairCalibrationError(
        "leave-one-pose-out needs >= 4 board poses (3 remain to "
        "calibrate), got " +
        std::to_string(poses));
  const bool with_peer = validation.with_peer && views.pose_cross_frames.size() == poses &&
                         !views.pose_cross_frames.front().empty();
  PairValidation result;
  result.gross_mm = validation.gross_mm;
  result.ours.model = "plane per stripe, smooth across stripes (ours)";
  result.peer.model = "OpenCV pinhole projector (calibrateCamera + stereoCalibrate)";

  // Decode every pose once (the stripe code and, for the peer, the row code).
  std::vector<cv::Mat1f> columns(poses), rows(poses);
  for (size_t k = 0; k < poses; ++k) {
    columns[k] =
        decodePatternFrames(views.pose_frames[k],
                            views.pose_cross_frames.size() == poses ? views.pose_cross_frames[k]
                                                                    : std::vector<cv::Mat>(),
                            views.layout, options.decoding)
            .coordinate;
    if (with_peer) {
      // The same decoding for the row code as for the stripes.
      const int row_bits = (static_cast<int>(views.pose_cross_frames[k].size()) - 2) / 2;
      rows[k] =
          decodePatternFrames(views.pose_cross_frames[k], {},
                              body_scan_driver::PatternLayout(row_bits, true), options.decoding)
              .coordinate;
    }
  }

  std::vector<std::vector<double>> ours_distances(poses), peer_distances(poses);
  std::vector<size_t> board_pixels(poses, 0);
  for (size_t held_out = 0; held_out < poses; ++held_out) {
    report("leave out pose " + std::to_string(held_out + 1) + "/" + std::to_string(poses));
    std::vector<std::vector<cv::Mat>> frames, cross;
    std::vector<cv::Mat1f> train_columns, train_rows;
    for (size_t k = 0; k < poses; ++k)
      if (k != held_out) {
        frames.push_back(views.pose_frames[k]);
        if (views.pose_cross_frames.size() == poses) cross.push_back(views.pose_cross_frames[k]);
        train_columns.push_back(columns[k]);
        if (with_peer) train_rows.push_back(rows[k]);
      }
    const PairCalibrationOutcome outcome = calibratePair(frames, views.layout, options, {}, cross);
    const cv::Mat& lit = views.pose_frames[held_out][body_scan_driver::PatternLayout::litFrame()];
    std::vector<Eigen::Vector2d> corners;
    if (!detectCheckerboardCorners(lit, options.board, corners))
      throw PairCalibrationError("pose " + std::to_string(held_out) + ": board not found");
    const Eigen::Isometry3d pose =
        estimateBoardPose(outcome.calibration.camera, corners, options.board);
    const cv::Mat1b region = boardRegion(outcome.calibration.camera, pose, options.board);

    const body_scan_driver::Triangulator triangulator(outcome.calibration, 0.05, 50.0);
    std::vector<float> xyz(columns[held_out].total() * 3);
    triangulator.triangulate(columns[held_out], xyz.data(), 3);
    ours_distances[held_out] =
        boardDistances(xyz, region, boardPlane(pose), board_pixels[held_out]);
    result.ours.per_pose.push_back(
        planeErrorStatistics(ours_distances[held_out], board_pixels[held_out], result.gross_mm));

    if (!with_peer) continue;
    const cv::Size camera_size(lit.cols, lit.rows);
    const int projector_columns = views.layout.stripeCount();
    const int projector_rows =
        1 << ((static_cast<int>(views.pose_cross_frames[held_out].size()) - 2) / 2);
    const PinholePeer peer =
        calibratePeer(outcome.camera.corners, train_columns, train_rows, options.board, camera_size,
                      cv::Size(projector_columns, projector_rows));
    {
      char line[256];
      std::snprintf(line, sizeof(line),
                    "  peer: projector fx %.1f fy %.1f cx %.1f cy %.1f, baseline (%.1f, %.1f, %.1f) mm",
                    peer.projector_matrix.at<double>(0, 0), peer.projector_matrix.at<double>(1, 1),
                    peer.projector_matrix.at<double>(0, 2), peer.projector_matrix.at<double>(1, 2),
                    1e3 * peer.translation.at<double>(0), 1e3 * peer.translation.at<double>(1),
                    1e3 * peer.translation.at<double>(2));
      report(line);
    }
    // The board plane from the peer's own camera (PnP), as for ours.
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    for (const Eigen::Vector3d& p : options.board.objectPoints())
      object.emplace_back(p.x(), p.y(), 0);
    for (const Eigen::Vector2d& p : corners) image.emplace_back(p.x(), p.y());
    cv::Mat rvec, tvec, rotation;
    cv::solvePnP(object, image, peer.camera_matrix, peer.camera_distortion, rvec, tvec);
    cv::Rodrigues(rvec, rotation);
    Eigen::Isometry3d peer_pose = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) peer_pose.linear()(r, c) = rotation.at<double>(r, c);
      peer_pose.translation()[r] = tvec.at<double>(r);
    }
    const std::vector<float> peer_xyz =
        triangulatePeer(peer, columns[held_out], peer_pose.translation().z());
    size_t pixels = 0;
    peer_distances[held_out] = boardDistances(peer_xyz, region, boardPlane(peer_pose), pixels);
    result.peer.per_pose.push_back(
        planeErrorStatistics(peer_distances[held_out], pixels, result.gross_mm));
  }
  result.ours.pooled = pooled(ours_distances, board_pixels, result.gross_mm);
  if (with_peer) result.peer.pooled = pooled(peer_distances, board_pixels, result.gross_mm);

  const PairCalibrationOutcome all =
      calibratePair(views.pose_frames, views.layout, options, {}, views.pose_cross_frames);
  for (int stripe = 0; stripe < all.planes.projector.stripeCount(); ++stripe) {
    if (all.planes.poses_per_stripe[stripe] == 0) continue;
    ++result.stripes_on_board;
    if (all.planes.projector.planes[stripe].allFinite()) ++result.stripes_calibrated;
  }
  return result;
}

namespace {

double rounded(double value, double unit) { return std::round(value / unit) * unit; }

void emitStatistics(YAML::Emitter& out, const PlaneErrorStatistics& s) {
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "board_pixels" << YAML::Value << s.board_pixels;
  out << YAML::Key << "points" << YAML::Value << s.points;
  out << YAML::Key << "coverage_percent" << YAML::Value << rounded(100 * s.coverage, 0.01);
  out << YAML::Key << "median_mm" << YAML::Value << rounded(s.median_mm, 1e-3);
  out << YAML::Key << "rms_mm" << YAML::Value << rounded(s.rms_mm, 1e-3);
  out << YAML::Key << "p95_mm" << YAML::Value << rounded(s.p95_mm, 1e-3);
  out << YAML::Key << "gross_percent" << YAML::Value << rounded(100 * s.gross_share, 1e-3);
  out << YAML::EndMap;
}

void emitModel(YAML::Emitter& out, const ModelValidation& model) {
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << model.model;
  out << YAML::Key << "pooled" << YAML::Value;
  emitStatistics(out, model.pooled);
  out << YAML::Key << "per_held_out_pose" << YAML::Value << YAML::BeginSeq;
  for (const PlaneErrorStatistics& s : model.per_pose) emitStatistics(out, s);
  out << YAML::EndSeq;
  out << YAML::EndMap;
}

}  // namespace

std::string validationYaml(const PairValidation& validation) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "method" << YAML::Value
      << "leave one board pose out: calibrate from the others, triangulate the held-out pose's "
         "board pixels, distance to the board plane from its corners (PnP with each model's "
         "camera)";
  out << YAML::Key << "gross_threshold_mm" << YAML::Value << validation.gross_mm;
  out << YAML::Key << "stripes_on_a_board" << YAML::Value << validation.stripes_on_board;
  out << YAML::Key << "stripes_calibrated" << YAML::Value << validation.stripes_calibrated;
  out << YAML::Key << "ours" << YAML::Value;
  emitModel(out, validation.ours);
  if (!validation.peer.per_pose.empty()) {
    out << YAML::Key << "peer" << YAML::Value;
    emitModel(out, validation.peer);
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace body_scan_calib
