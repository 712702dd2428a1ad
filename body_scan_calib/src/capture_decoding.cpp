#include <body_scan_calib/capture_decoding.h>
#include <body_scan_calib/projector_calibration.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/triangulation.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

namespace body_scan_calib {

size_t rejectInconsistentCodes(body_scan_driver::StripeImage& stripes,
                               const RobustDecoding& robust) {
  constexpr int kRadius = 2;
  const cv::Mat1f source = stripes.coordinate.clone();
  size_t rejected = 0;
  std::vector<float> window;
  window.reserve((2 * kRadius + 1) * (2 * kRadius + 1));
  for (int v = 0; v < source.rows; ++v)
    for (int u = 0; u < source.cols; ++u) {
      const float centre = source(v, u);
      if (!std::isfinite(centre)) continue;
      window.clear();
      for (int dv = -kRadius; dv <= kRadius; ++dv)
        for (int du = -kRadius; du <= kRadius; ++du) {
          const int y = v + dv, x = u + du;
          if ((dv || du) && y >= 0 && y < source.rows && x >= 0 && x < source.cols &&
              std::isfinite(source(y, x)))
            window.push_back(source(y, x));
        }
      bool consistent = static_cast<int>(window.size()) >= robust.min_neighbours;
      if (consistent) {
        std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
        consistent = std::abs(centre - window[window.size() / 2]) <= robust.max_neighbour_deviation;
      }
      if (consistent) continue;
      stripes.coordinate(v, u) = std::numeric_limits<float>::quiet_NaN();
      stripes.stripe(v, u) = body_scan_driver::kInvalidStripe;
      ++rejected;
    }
  return rejected;
}

void smoothAlongStripes(body_scan_driver::StripeImage& stripes, int radius) {
  if (radius <= 0) return;
  const bool along_rows = stripesChangeAlongRows(stripes.coordinate, 2);
  const cv::Mat1f source = stripes.coordinate.clone();
  std::vector<float> window;
  for (int v = 0; v < source.rows; ++v)
    for (int u = 0; u < source.cols; ++u) {
      if (!std::isfinite(source(v, u))) continue;
      window.clear();
      for (int d = -radius; d <= radius; ++d) {
        // Along the stripe: across the axis the coordinate changes along.
        const int y = along_rows ? v : v + d, x = along_rows ? u + d : u;
        if (y >= 0 && y < source.rows && x >= 0 && x < source.cols && std::isfinite(source(y, x)))
          window.push_back(source(y, x));
      }
      std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
      stripes.coordinate(v, u) = window[window.size() / 2];
    }
}

body_scan_driver::StripeImage decodePatternFrames(const std::vector<cv::Mat>& frames,
                                                  const std::vector<cv::Mat>& cross_frames,
                                                  const body_scan_driver::PatternLayout& layout,
                                                  const RobustDecoding& robust) {
  body_scan_driver::StripeImage stripes;
  body_scan_driver::DecoderParams params;
  if (robust.enabled) {
    params.min_contrast = robust.min_contrast;
    params.edge_contrast_ratio = robust.edge_contrast_ratio;
  }
  body_scan_driver::StripeDecoder(layout, params).decode(frames, stripes);
  if (!robust.enabled) return stripes;
  rejectInconsistentCodes(stripes, robust);
  if (cross_frames.size() >= 4) {
    // The other axis's code must be decodable and locally consistent at the pixel as well.
    body_scan_driver::StripeImage cross;
    body_scan_driver::StripeDecoder(
        body_scan_driver::PatternLayout((static_cast<int>(cross_frames.size()) - 2) / 2, true),
        params)
        .decode(cross_frames, cross);
    rejectInconsistentCodes(cross, robust);
    for (int v = 0; v < stripes.coordinate.rows; ++v)
      for (int u = 0; u < stripes.coordinate.cols; ++u)
        if (!std::isfinite(cross.coordinate(v, u))) {
          stripes.coordinate(v, u) = std::numeric_limits<float>::quiet_NaN();
          stripes.stripe(v, u) = body_scan_driver::kInvalidStripe;
        }
  }
  smoothAlongStripes(stripes, robust.along_stripe_radius);
  return stripes;
}

body_scan_driver::StripeImage decodeCapturedSet(const CapturedPatternSet& set, int bits,
                                                const RobustDecoding& robust) {
  return decodePatternFrames(set.frames, set.cross_frames,
                             body_scan_driver::PatternLayout(bits, true), robust);
}

std::vector<Eigen::Vector3f> triangulateStripes(
    const body_scan_driver::PairCalibration& calibration, const cv::Mat1f& coordinate) {
  if (coordinate.cols != calibration.camera.width || coordinate.rows != calibration.camera.height)
    throw std::invalid_argument(
        "the images are " + std::to_string(coordinate.cols) + "x" +
        std::to_string(coordinate.rows) + " but the calibration's camera is " +
        std::to_string(calibration.camera.width) + "x" + std::to_string(calibration.camera.height) +
        ": use the calibration of the pair that took them");
  const body_scan_driver::Triangulator triangulator(calibration, 0.05, 50.0);
  std::vector<float> xyz(coordinate.total() * 3);
  triangulator.triangulate(coordinate, xyz.data(), 3);
  std::vector<Eigen::Vector3f> points;
  for (size_t i = 0; i < coordinate.total(); ++i)
    if (std::isfinite(xyz[3 * i + 2]))
      points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  return points;
}

void writePointCloud(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  const std::string extension = std::filesystem::path(path).extension().string();
  const std::string count = std::to_string(points.size());
  std::string header;
  if (extension == ".ply")
    header = "ply\nformat binary_little_endian 1.0\nelement vertex " + count +
             "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  else if (extension == ".pcd")
    header =
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
        "TYPE F F F\nCOUNT 1 1 1\nWIDTH " +
        count +
        "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
        "POINTS " +
        count + "\nDATA binary\n";
  else
    throw std::invalid_argument("cannot write '" + path +
                                "': the cloud file must end in .ply or .pcd");
  std::string contents = header;
  contents.reserve(header.size() + points.size() * 12);
  for (const Eigen::Vector3f& p : points)
    contents.append(reinterpret_cast<const char*>(p.data()), 3 * sizeof(float));
  body_scan_driver::writeFileAtomically(path, contents);
}

}  // namespace body_scan_calib
