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
