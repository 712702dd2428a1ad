#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/cylinder_target.h>
#include <body_scan_calib/world_alignment.h>
#include <body_scan_calib/world_alignment_run.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/stripe_decoder.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace body_scan_calib {

namespace fs = std::filesystem;

std::string calibrationFileStem(const std::string& pair_id) {
  std::string stem = pair_id;
  std::replace(stem.begin(), stem.end(), '/', '_');
  return stem;
}

std::optional<body_scan_driver::PairCalibration> calibrationToAlign(const std::string& folder,
                                                                    const std::string& pair_id) {
  if (folder.empty()) return std::nullopt;
  const std::string path = folder + "/" + calibrationFileStem(pair_id) + ".yaml";
  if (!fs::exists(path)) return std::nullopt;
  body_scan_driver::PairCalibration calibration = body_scan_driver::loadCalibration(path);
  calibration.alignment.reset();  // re-aligned from scratch
  return calibration;
}

void saveCylinderCapture(const CylinderCapture& capture, const std::string& folder) {
  const std::string pair_folder = folder + "/" + calibrationFileStem(capture.pair_id);
  savePatternFrames(pair_folder, capture.frames);
  writePngAtomically(pair_folder + "/texture.png", capture.gray);
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "pair_id" << YAML::Value << capture.pair_id << YAML::Key
      << "bits" << YAML::Value << capture.layout.bits() << YAML::Key << "inverse_frames"
      << YAML::Value << capture.layout.inverseFrames() << YAML::EndMap;
  body_scan_driver::writeFileAtomically(pair_folder + "/capture.yaml",
                                        std::string(out.c_str()) + "\n");
}

std::vector<CylinderCapture> loadCylinderCaptures(const std::string& images,
                                                  const std::string& calibration_in) {
  if (!fs::is_directory(images))
    throw std::runtime_error("image folder '" + images +
                             "' not found; record one with align_simulated_rig --save-images DIR");
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(images))
    if (entry.is_directory() && fs::exists(entry.path() / "capture.yaml"))
      folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  if (folders.empty())
    throw std::runtime_error("image folder '" + images +
                             "' has no pair folders with a capture.yaml; record one with "
                             "align_simulated_rig --save-images DIR");
  std::vector<CylinderCapture> captures;
  for (size_t i = 0; i < folders.size(); ++i) {
    const YAML::Node info = YAML::LoadFile((folders[i] / "capture.yaml").string());
    CylinderCapture capture;
    capture.pair_id = info["pair_id"].as<std::string>();
    capture.layout = body_scan_driver::PatternLayout(info["bits"].as<int>(8),
                                                     info["inverse_frames"].as<bool>(true));
    std::cout << "[" << i + 1 << "/" << folders.size() << "] " << capture.pair_id << ": reading "
              << folders[i].string() << "\n";
    capture.frames = loadPatternFrames(folders[i].string(), capture.layout);
    capture.gray = cv::imread((folders[i] / "texture.png").string(), cv::IMREAD_GRAYSCALE);
    if (capture.gray.empty())
      throw std::runtime_error("missing " + (folders[i] / "texture.png").string());
    auto calibration = calibrationToAlign(calibration_in, capture.pair_id);
    if (!calibration)
      throw std::runtime_error("no calibration for " + capture.pair_id + " in '" + calibration_in +
                               "': pass --calibration-in DIR with " +
                               calibrationFileStem(capture.pair_id) + ".yaml");
    capture.calibration = *calibration;
    captures.push_back(std::move(capture));
  }
  return captures;
}

namespace {

// yaml-cpp stores scalars as text when assigned: format numbers here, not in the emitter.
std::string number(double value, int significant = 7) {
  std::ostringstream text;
  text << std::setprecision(significant) << value;
  return text.str();
}
std::string mm(double metres) {  // millimetres, 3 decimals (micrometres)
  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << metres * 1000;
  return text.str();
}
YAML::Node numbers(std::initializer_list<double> values) {
  YAML::Node node;
  for (double value : values) node.push_back(number(value));
  node.SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

// Where the pairs saw the cylinder and how well they agree (cf. Figs 4.10-4.11): left, every
// pair's aligned grid points on the unrolled cylinder (angle about the axis, height), each pair
// offset by a few pixels so that shared points show all their colours; right, E_h of each
// shared point (eq 4.2) against its height.
void writePlot(const std::string& path, const std::vector<AlignedPair>& pairs,
               const body_scan_driver::CalibrationCylinderLayout& layout,
               const SharedPointAccuracy& accuracy) {
  const int size = 500;
  cv::Mat3b image(size, 2 * size, cv::Vec3b(255, 255, 255));
  const cv::Scalar colours[] = {{200, 80, 0},  {0, 140, 0},   {0, 0, 220},
                                {160, 0, 160}, {0, 160, 200}, {90, 90, 90}};
  double z_low = 1e9, z_high = -1e9, angle_low = 1e9, angle_high = -1e9;
  for (const AlignedPair& pair : pairs)
    for (const auto& [id, camera_point] : pair.camera_points) {
      const Eigen::Vector3d world = pair.alignment.toWorld(camera_point);
      const double angle = std::atan2(world.y(), world.x()) * 180 / M_PI;
      z_low = std::min(z_low, world.z()), z_high = std::max(z_high, world.z());
      angle_low = std::min(angle_low, angle), angle_high = std::max(angle_high, angle);
    }
  if (z_low > z_high) z_low = 0, z_high = layout.height, angle_low = -180, angle_high = 180;
  z_low -= 0.05, z_high += 0.05, angle_low -= 10, angle_high += 10;
  const cv::Rect unrolled(40, 40, size - 70, size - 110);
  cv::rectangle(image, unrolled, cv::Scalar(0, 0, 0));
  auto height_y = [&](const cv::Rect& box, double z) {
    return box.y + static_cast<int>(std::lround((z_high - z) / (z_high - z_low) * box.height));
  };
  for (size_t p = 0; p < pairs.size(); ++p) {
    const cv::Scalar colour = colours[p % 6];
    const cv::Point offset(p % 2 ? 3 : -3, (p / 2) % 2 ? 3 : -3);
    for (const auto& [id, camera_point] : pairs[p].camera_points) {
      const Eigen::Vector3d world = pairs[p].alignment.toWorld(camera_point);
      // Angle grows to the left: the cylinder as seen from its front (+x).
      const double angle = std::atan2(world.y(), world.x()) * 180 / M_PI;
      const int x =
          unrolled.x + static_cast<int>(std::lround((angle_high - angle) /
                                                    (angle_high - angle_low) * unrolled.width));
      cv::circle(image, cv::Point(x, height_y(unrolled, world.z())) + offset, 2, colour, -1,
                 cv::LINE_AA);
    }
    cv::putText(image, pairs[p].pair_id,
                {40 + 115 * static_cast<int>(p % 4), size - 14 + 18 * static_cast<int>(p / 4)},
                cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv::LINE_AA);
  }
  std::ostringstream unrolled_title, unrolled_axis;
  unrolled_title << "aligned grid points, unrolled cylinder (world frame)";
  unrolled_axis << "angle about z " << number(angle_high, 3) << " .. " << number(angle_low, 3)
                << " deg (front = 0)";
  cv::putText(image, unrolled_title.str(), {10, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(image, unrolled_axis.str(), {40, unrolled.y + unrolled.height + 20},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Right panel: E_h per comparison (mm) horizontally, height z vertically.
  const cv::Rect panel(size + 60, 40, size - 90, size - 110);
  cv::rectangle(image, panel, cv::Scalar(0, 0, 0));
  const double max_mm = std::max(1.0, std::ceil(accuracy.max_m * 1000));
  std::vector<std::pair<double, double>> samples;  // (E_h mm, z)
  for (size_t a = 0; a < pairs.size(); ++a)
    for (size_t b = a + 1; b < pairs.size(); ++b)
      for (const auto& [id, point_a] : pairs[a].camera_points) {
        const auto found = pairs[b].camera_points.find(id);
        if (found == pairs[b].camera_points.end()) continue;
        const Eigen::Vector3d world_a = pairs[a].alignment.toWorld(point_a);
        samples.emplace_back(1000 * (world_a - pairs[b].alignment.toWorld(found->second)).norm(),
                             world_a.z());
      }
  for (const auto& [error_mm, z] : samples)
    cv::circle(
        image,
        {panel.x + static_cast<int>(std::lround(error_mm / max_mm * panel.width)),
         panel.y + static_cast<int>(std::lround((z_high - z) / (z_high - z_low) * panel.height))},
        3, cv::Scalar(200, 80, 0), -1, cv::LINE_AA);
  const int mean_x =
      panel.x + static_cast<int>(std::lround(1000 * accuracy.mean_m / max_mm * panel.width));
  cv::line(image, {mean_x, panel.y}, {mean_x, panel.y + panel.height}, cv::Scalar(0, 0, 220), 1);
  std::ostringstream title, axis, heights;
  title << "E_h (eq 4.2): " << accuracy.shared_points << " points, mean " << mm(accuracy.mean_m)
        << " mm, std " << mm(accuracy.std_m) << " mm";
  axis << "0 .. " << max_mm << " mm (red: mean)";
  heights << "height z " << number(z_low, 3) << " .. " << number(z_high, 3) << " m (both panels)";
  cv::putText(image, title.str(), {size + 20, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(image, axis.str(), {panel.x, panel.y + panel.height + 20}, cv::FONT_HERSHEY_SIMPLEX,
              0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(image, heights.str(), {panel.x, panel.y + panel.height + 40},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  writePngAtomically(path, image);
}

// Aligns one capture: its report entry; on success also its aligned points (for E_h) in
// `aligned` and its aligned calibration file in `calibration_out`. Throws on failure.
void alignCapture(const CylinderCapture& capture,
                  const body_scan_driver::CalibrationCylinderLayout& layout,
                  const std::string& calibration_out, YAML::Node& entry,
                  std::vector<AlignedPair>& aligned) {
  body_scan_driver::StripeImage stripes;
  body_scan_driver::StripeDecoder(capture.layout).decode(capture.frames, stripes);
  const CylinderObservation observation =
      observeCylinder(capture.gray, stripes.coordinate, capture.calibration, layout);
  entry["markers"] = observation.stats.markers;
  entry["grid_points_detected"] = static_cast<int>(observation.detections.size());
  entry["grid_points_triangulated"] = static_cast<int>(observation.points.size());
  std::vector<Eigen::Vector3d> camera, world;
  for (const TriangulatedGridPoint& point : observation.points) {
    camera.push_back(point.camera_point);
    world.push_back(cylinderGridPoint(layout, point.id));
  }
  const AffineFit fit = fitWorldAffine(camera, world);
  // E_h compares the points the fit trusted; outliers are reported, not compared.
  AlignedPair pair{capture.pair_id, {}, fit.alignment};
  for (size_t i = 0, next_outlier = 0; i < observation.points.size(); ++i) {
    if (next_outlier < fit.outliers.size() && fit.outliers[next_outlier] == static_cast<int>(i)) {
      ++next_outlier;
      continue;
    }
    pair.camera_points[observation.points[i].id] = observation.points[i].camera_point;
  }
  entry["grid_points_outliers"] = static_cast<int>(fit.outliers.size());
  aligned.push_back(pair);
  entry["fit_rms_mm"] = mm(fit.rms_m);
  entry["fit_max_mm"] = mm(fit.max_m);
  const Eigen::Vector3d t = fit.alignment.world_from_camera.translation();
  const Eigen::Quaterniond q(fit.alignment.world_from_camera.linear());
  entry["world_from_camera"]["translation_m"] = numbers({t.x(), t.y(), t.z()});
  entry["world_from_camera"]["quaternion_xyzw"] = numbers({q.x(), q.y(), q.z(), q.w()});
  // Frobenius norm of L - I: how far the affine is from a rigid transform.
  entry["residual_linear_deviation"] =
      number((fit.alignment.residual_linear - Eigen::Matrix3d::Identity()).norm(), 3);
  if (capture.true_cylinder_from_camera) {
    const Eigen::Isometry3d& truth = *capture.true_cylinder_from_camera;
    entry["simulator_check"]["rotation_error_deg"] = number(
        Eigen::AngleAxisd(truth.linear().transpose() * fit.alignment.world_from_camera.linear())
                .angle() *
            180 / M_PI,
        3);
    entry["simulator_check"]["translation_error_mm"] = mm((truth.translation() - t).norm());
  }
  body_scan_driver::PairCalibration calibration = capture.calibration;
  calibration.alignment = fit.alignment;
  const std::string path = calibration_out + "/" + calibrationFileStem(capture.pair_id) + ".yaml";
  body_scan_driver::saveCalibration(path, calibration);
  entry["calibration_file"] = path;
  std::cout << "  " << capture.pair_id << ": " << observation.stats.markers << " markers, "
            << observation.detections.size() << " grid points, " << observation.points.size()
            << " triangulated; affine rms " << mm(fit.rms_m) << " mm -> " << path << "\n";
}

YAML::Node sharedPointsNode(const SharedPointAccuracy& accuracy) {
  YAML::Node e_h;
  e_h["shared_points"] = accuracy.shared_points;
  e_h["comparisons"] = accuracy.comparisons;
  e_h["mean_mm"] = mm(accuracy.mean_m);
  e_h["std_mm"] = mm(accuracy.std_m);
  e_h["max_mm"] = mm(accuracy.max_m);
  for (const auto& combination : accuracy.by_pairs) {
    YAML::Node node;
    node["pairs"] = std::vector<std::string>{combination.first, combination.second};
    node["points"] = combination.points;
    node["mean_mm"] = mm(combination.mean_m);
    e_h["by_pairs"].push_back(node);
  }
  return e_h;
}

}  // namespace

int alignWorld(const std::vector<CylinderCapture>& captures, const std::string& mode,
               const WorldAlignmentFiles& files) {
  const body_scan_driver::CalibrationCylinderLayout layout;
  std::vector<AlignedPair> aligned;
  YAML::Node report;
  report["thesis"] = "sec. 4.3.2, eqs 4.1-4.2, Table 4.2";
  report["mode"] = mode;
  report["target"]["radius_m"] = number(layout.radius);
  report["target"]["height_m"] = number(layout.height);
  report["target"]["grid_pitch_m"] = number(layout.grid_pitch);
  int failures = 0;
  for (const CylinderCapture& capture : captures) {
    YAML::Node entry;
    entry["pair_id"] = capture.pair_id;
    entry["calibration_source"] = capture.calibration.source;
    try {
      alignCapture(capture, layout, files.calibration_out, entry, aligned);
    } catch (const std::exception& e) {
      ++failures;
      entry["error"] = e.what();
      std::cerr << "  " << capture.pair_id << ": NOT aligned: " << e.what() << "\n";
    }
    report["pairs"].push_back(entry);
  }
  const SharedPointAccuracy accuracy = evaluateSharedPoints(aligned);
  report["E_h"] = sharedPointsNode(accuracy);
  YAML::Emitter out;
  out << report;
  body_scan_driver::writeFileAtomically(
      files.report,
      "# World alignment report (align_world); E_h = eq 4.2 over grid points seen by two "
      "pairs.\n" +
          std::string(out.c_str()) + "\n");
  const std::string plot =
      files.plot.empty() ? fs::path(files.report).replace_extension(".png").string() : files.plot;
  writePlot(plot, aligned, layout, accuracy);
  std::cout << "E_h (eq 4.2): " << accuracy.shared_points << " shared points, "
            << accuracy.comparisons << " comparisons, mean " << mm(accuracy.mean_m) << " mm, std "
            << mm(accuracy.std_m) << " mm, max " << mm(accuracy.max_m)
            << " mm\nreport: " << files.report << "\nplot: " << plot << "\n";
  return failures;
}

}  // namespace body_scan_calib
