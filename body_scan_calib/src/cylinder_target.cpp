#include <body_scan_calib/cylinder_target.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

namespace body_scan_calib {

constexpr double kMinAspect = 0.5;  // cos 60 deg
constexpr double kMinCornerEigenRatio = 0.15;
constexpr int kMinHalfWindow = 3;  // pixels

// A checker corner has strong gradients in two directions inside its window: the smaller
// eigenvalue of the structure tensor is a good part of the larger. Along a single edge or on a
// flat patch (refinement started too far from the corner) it is not.
bool looksLikeCorner(const cv::Mat& gray, const Eigen::Vector2d& pixel, int half_window) {
  const int u = static_cast<int>(std::lround(pixel.x())),
            v = static_cast<int>(std::lround(pixel.y()));
  const cv::Rect window(u - half_window - 1, v - half_window - 1, 2 * half_window + 3,
                        2 * half_window + 3);
  if ((window & cv::Rect(0, 0, gray.cols, gray.rows)) != window) return false;
  cv::Mat dx, dy;
  cv::Sobel(gray(window), dx, CV_32F, 1, 0);
  cv::Sobel(gray(window), dy, CV_32F, 0, 1);
  const cv::Rect inner(1, 1, 2 * half_window + 1, 2 * half_window + 1);
  const double xx = dx(inner).dot(dx(inner)), yy = dy(inner).dot(dy(inner)),
               xy = dx(inner).dot(dy(inner));
  const double mean = 0.5 * (xx + yy), spread = std::sqrt(0.25 * (xx - yy) * (xx - yy) + xy * xy);
  return mean > 0 && (mean - spread) > kMinCornerEigenRatio * (mean + spread);
}

std::vector<GridPointDetection> detectCylinderGridPoints(
    const cv::Mat& gray, const body_scan_driver::CalibrationCylinderLayout& layout,
    CylinderDetectionStats* stats) {
  CylinderDetectionStats local_stats;
  CylinderDetectionStats& counts = stats ? *stats : local_stats;
  counts = {};
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument(
        "cylinder detection needs a non-empty 8-bit grey image (convert the texture with "
        "cv::cvtColor first)");
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_1000);
  const cv::Ptr<cv::aruco::DetectorParameters> parameters = cv::aruco::DetectorParameters::create();
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> ids;
  cv::aruco::detectMarkers(gray, dictionary, marker_corners, ids, parameters);

  // Marker corners (TL, TR, BR, BL as ArUco orders them) in square coordinates: across from
  // the square's left edge, down from its top edge, in square sides.
  const float margin = static_cast<float>(0.5 * (1 - layout.marker_fraction));
  const std::vector<cv::Point2f> marker_in_square = {
      {margin, margin}, {1 - margin, margin}, {1 - margin, 1 - margin}, {margin, 1 - margin}};
  struct Prediction {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    double square_px = 1e9;  // smallest square side seen around it, pixels
    double aspect = 1;       // smallest short side / long side of those squares
  };
  std::map<int, Prediction> predictions;
  for (size_t m = 0; m < ids.size(); ++m) {
    if (ids[m] < 0 || ids[m] >= layout.markerCount()) continue;
    ++counts.markers;
    int col, row;
    layout.markerSquare(ids[m], col, row);
    const cv::Mat homography = cv::getPerspectiveTransform(marker_in_square, marker_corners[m]);
    // Square corners (across, down) -> grid corners (col, row): the top edge is row + 1.
    const std::vector<cv::Point2f> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const int corner_col[] = {col, col + 1, col + 1, col};
    const int corner_row[] = {row + 1, row + 1, row, row};
    std::vector<cv::Point2f> image_square;
    cv::perspectiveTransform(square, image_square, homography);
    double side = 1e9, longest = 0;
    for (int k = 0; k < 4; ++k) {
      const double length = cv::norm(image_square[k] - image_square[(k + 1) % 4]);
      side = std::min(side, length);
      longest = std::max(longest, length);
    }
    for (int k = 0; k < 4; ++k) {
      if (!layout.isGridPoint(corner_col[k], corner_row[k])) continue;
      Prediction& p = predictions[layout.gridPointId(corner_col[k], corner_row[k])];
      p.sum += Eigen::Vector2d(image_square[k].x, image_square[k].y);
      ++p.count;
      p.square_px = std::min(p.square_px, side);
      p.aspect = std::min(p.aspect, side / longest);
    }
  }

  std::vector<GridPointDetection> detections;
  for (const auto& [id, prediction] : predictions) {
    ++counts.predicted;
    // Squares seen at grazing angles (foreshortened below kMinAspect) bend away from the
    // marker's homography and blur into their neighbours: their corners are not reliable.
    if (prediction.aspect < kMinAspect) {
      ++counts.rejected_grazing;
      continue;
    }
    const Eigen::Vector2d guess = prediction.sum / prediction.count;
    // The refinement window must stay inside the white margin around the markers; a window
    // narrower than kMinHalfWindow cannot pull a poor prediction onto the corner.
    const int half_window =
        std::min(static_cast<int>(std::floor(margin * prediction.square_px)) - 1, 6);
    if (half_window < kMinHalfWindow) {
      ++counts.rejected_grazing;
      continue;
    }
    if (guess.x() < half_window + 1 || guess.y() < half_window + 1 ||
        guess.x() > gray.cols - half_window - 2 || guess.y() > gray.rows - half_window - 2)
      continue;
    std::vector<cv::Point2f> corner = {
        cv::Point2f(static_cast<float>(guess.x()), static_cast<float>(guess.y()))};
    cv::cornerSubPix(gray, corner, cv::Size(half_window, half_window), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40, 0.001));
    const Eigen::Vector2d refined(corner[0].x, corner[0].y);
    if ((refined - guess).norm() > 0.5 * half_window ||
        !looksLikeCorner(gray, refined, half_window)) {
      ++counts.rejected_refine;
      continue;
    }
    detections.push_back({id, refined});
  }
  return detections;
}

std::optional<Eigen::Vector3d> triangulateAtPixel(
    const cv::Mat1f& stripe_coordinate, const Eigen::Vector2d& pixel,
    const body_scan_driver::PairCalibration& calibration, int radius) {
  const int centre_u = static_cast<int>(std::lround(pixel.x())),
            centre_v = static_cast<int>(std::lround(pixel.y()));
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> values;
  for (int v = centre_v - radius; v <= centre_v + radius; ++v)
    for (int u = centre_u - radius; u <= centre_u + radius; ++u) {
      if (u < 0 || v < 0 || u >= stripe_coordinate.cols || v >= stripe_coordinate.rows) continue;
      const float s = stripe_coordinate(v, u);
      if (!std::isfinite(s)) continue;
      rows.emplace_back(1.0, u - pixel.x(), v - pixel.y());
      values.push_back(s);
    }
  const int window = (2 * radius + 1) * (2 * radius + 1);
  if (static_cast<int>(values.size()) < window / 2) return std::nullopt;
  Eigen::MatrixX3d design(rows.size(), 3);
  Eigen::VectorXd observed(values.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    design.row(i) = rows[i].transpose();
    observed[i] = values[i];
  }
  const Eigen::Vector3d fit = design.colPivHouseholderQr().solve(observed);
  const double rms = std::sqrt((design * fit - observed).squaredNorm() / values.size());
  if (!(rms < 0.5)) return std::nullopt;  // stripes: a decoding error or a depth edge nearby
  const Eigen::Vector4d plane = calibration.projector.planeAt(fit[0]);
  if (!plane.allFinite()) return std::nullopt;
  const Eigen::Vector3d point =
      body_scan_driver::intersectRayPlane(calibration.camera.normalizedPoint(pixel), plane);
  if (!point.allFinite()) return std::nullopt;
  return point;
}

CylinderObservation observeCylinder(const cv::Mat& gray, const cv::Mat1f& stripe_coordinate,
                                    const body_scan_driver::PairCalibration& calibration,
                                    const body_scan_driver::CalibrationCylinderLayout& layout) {
  if (gray.size() != stripe_coordinate.size())
    throw std::invalid_argument(
        "cylinder observation: the image and the decoded stripe image "
        "differ in size; they must come from one pattern set");
  CylinderObservation observation;
  observation.detections = detectCylinderGridPoints(gray, layout, &observation.stats);
  for (const GridPointDetection& detection : observation.detections)
    if (const auto point = triangulateAtPixel(stripe_coordinate, detection.pixel, calibration))
      observation.points.push_back({detection.id, detection.pixel, *point});
  return observation;
}

}  // namespace body_scan_calib
