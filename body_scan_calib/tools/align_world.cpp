// align_world: aligns every pair to the world frame with the calibration cylinder (thesis
// sec. 4.3.2) and reports E_h (eq 4.2, Table 4.2). Live against the simulator (the cylinder
// scene is loaded, each pair renders its pattern set) or offline from an image folder.
#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/cylinder_target.h>
#include <body_scan_calib/world_alignment.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <body_scan_driver/sim/calibration_cylinder.h>
#include <body_scan_driver/sim/virtual_pair.h>
#include <body_scan_driver/stripe_decoder.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_driver/tools/package_file.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;
using namespace body_scan_driver;
using namespace body_scan_calib;

namespace {

struct Options {
  std::string scene, images, save_images, calibration_in, calibration_out, report, plot;
  std::vector<std::string> pairs;
};

std::string fileStem(const std::string& pair_id) {
  std::string stem = pair_id;
  std::replace(stem.begin(), stem.end(), '/', '_');
  return stem;
}

// One pair's capture of the cylinder: what a live or recorded run provides.
struct Capture {
  std::string pair_id;
  std::vector<cv::Mat> frames;
  cv::Mat gray;
  body_scan_driver::PatternLayout layout{8, true};
  body_scan_driver::PairCalibration calibration;
  std::optional<Eigen::Isometry3d> true_cylinder_from_camera;  // simulator only: evaluation
};

std::optional<body_scan_driver::PairCalibration> calibrationFromDir(const std::string& dir,
                                                                    const std::string& pair_id) {
  if (dir.empty()) return std::nullopt;
  const std::string path = dir + "/" + fileStem(pair_id) + ".yaml";
  if (!fs::exists(path)) return std::nullopt;
  body_scan_driver::PairCalibration calibration = loadCalibration(path);
  calibration.alignment.reset();  // re-aligned from scratch
  return calibration;
}

void saveCapture(const Capture& capture, const std::string& dir) {
  const std::string folder = dir + "/" + fileStem(capture.pair_id);
  body_scan_calib::savePatternFrames(folder, capture.frames);
  body_scan_calib::writePngAtomically(folder + "/texture.png", capture.gray);
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "pair_id" << YAML::Value << capture.pair_id << YAML::Key
      << "bits" << YAML::Value << capture.layout.bits() << YAML::Key << "inverse_frames"
      << YAML::Value << capture.layout.inverseFrames() << YAML::EndMap;
  writeFileAtomically(folder + "/capture.yaml", std::string(out.c_str()) + "\n");
}

std::vector<Capture> captureLive(const Options& options) {
  auto scene = std::make_shared<body_scan_driver::sim::Scene>(
      body_scan_driver::sim::loadScene(options.scene));
  const body_scan_driver::sim::CalibrationCylinder* cylinder = nullptr;
  for (const auto& surface : scene->surfaces())
    if (auto found = dynamic_cast<const body_scan_driver::sim::CalibrationCylinder*>(surface.get()))
      cylinder = found;
  if (!cylinder)
    throw std::runtime_error("scene '" + options.scene +
                             "' has no calibration_cylinder object; use "
                             "body_scan_driver/config/scenes/calibration_cylinder.yaml");
  std::vector<Capture> captures;
  for (size_t i = 0; i < options.pairs.size(); ++i) {
    const body_scan_driver::sim::VirtualPairConfig config =
        body_scan_driver::sim::loadVirtualPairConfig(options.pairs[i]);
    std::cout << "[" << i + 1 << "/" << options.pairs.size() << "] " << config.pair_id
              << ": capturing the cylinder (simulator)... " << std::flush;
    const body_scan_driver::sim::VirtualPair pair(config, scene);
    body_scan_driver::sim::RenderedPatternSet rendered = pair.render(1);
    Capture capture;
    capture.pair_id = config.pair_id;
    capture.frames = std::move(rendered.frames);
    cv::cvtColor(rendered.texture, capture.gray, cv::COLOR_RGB2GRAY);
    capture.layout = pair.layout();
    if (auto calibration = calibrationFromDir(options.calibration_in, config.pair_id)) {
      capture.calibration = *calibration;
    } else {
      capture.calibration = pair.factoryCalibration();
      std::cout << "(no calibration in '" << options.calibration_in
                << "': using the simulator's factory calibration) ";
    }
    capture.true_cylinder_from_camera =
        cylinder->worldFromCylinder().inverse() * config.world_from_camera;
    std::cout << "done\n";
    if (!options.save_images.empty()) saveCapture(capture, options.save_images);
    captures.push_back(std::move(capture));
  }
  return captures;
}

std::vector<Capture> captureOffline(const Options& options) {
  if (!fs::is_directory(options.images))
    throw std::runtime_error("image folder '" + options.images +
                             "' not found; record one with align_world --save-images DIR");
  std::vector<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(options.images))
    if (entry.is_directory() && fs::exists(entry.path() / "capture.yaml"))
      folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  if (folders.empty())
    throw std::runtime_error("image folder '" + options.images +
                             "' has no pair folders with a capture.yaml; record one with "
                             "align_world --save-images DIR");
  std::vector<Capture> captures;
  for (size_t i = 0; i < folders.size(); ++i) {
    const YAML::Node info = YAML::LoadFile((folders[i] / "capture.yaml").string());
    Capture capture;
    capture.pair_id = info["pair_id"].as<std::string>();
    capture.layout = body_scan_driver::PatternLayout(info["bits"].as<int>(8),
                                                     info["inverse_frames"].as<bool>(true));
    std::cout << "[" << i + 1 << "/" << folders.size() << "] " << capture.pair_id << ": reading "
              << folders[i].string() << "\n";
    capture.frames = body_scan_calib::loadPatternFrames(folders[i].string(), capture.layout);
    capture.gray = cv::imread((folders[i] / "texture.png").string(), cv::IMREAD_GRAYSCALE);
    if (capture.gray.empty())
      throw std::runtime_error("missing " + (folders[i] / "texture.png").string());
    auto calibration = calibrationFromDir(options.calibration_in, capture.pair_id);
    if (!calibration)
      throw std::runtime_error("no calibration for " + capture.pair_id + " in '" +
                               options.calibration_in + "': pass --calibration-in DIR with " +
                               fileStem(capture.pair_id) + ".yaml");
    capture.calibration = *calibration;
    captures.push_back(std::move(capture));
  }
  return captures;
}

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
  body_scan_calib::writePngAtomically(path, image);
}

int run(const Options& options) {
  const std::vector<Capture> captures =
      options.images.empty() ? captureLive(options) : captureOffline(options);
  const body_scan_driver::CalibrationCylinderLayout layout;
  std::vector<AlignedPair> aligned;
  YAML::Node report;
  report["thesis"] = "sec. 4.3.2, eqs 4.1-4.2, Table 4.2";
  report["mode"] = options.images.empty() ? "live (simulator)" : "offline (" + options.images + ")";
  report["target"]["radius_m"] = number(layout.radius);
  report["target"]["height_m"] = number(layout.height);
  report["target"]["grid_pitch_m"] = number(layout.grid_pitch);
  int failures = 0;
  for (const Capture& capture : captures) {
    YAML::Node entry;
    entry["pair_id"] = capture.pair_id;
    entry["calibration_source"] = capture.calibration.source;
    try {
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
        if (next_outlier < fit.outliers.size() &&
            fit.outliers[next_outlier] == static_cast<int>(i)) {
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
      const std::string path = options.calibration_out + "/" + fileStem(capture.pair_id) + ".yaml";
      saveCalibration(path, calibration);
      entry["calibration_file"] = path;
      std::cout << "  " << capture.pair_id << ": " << observation.stats.markers << " markers, "
                << observation.detections.size() << " grid points, " << observation.points.size()
                << " triangulated; affine rms " << mm(fit.rms_m) << " mm -> " << path << "\n";
    } catch (const std::exception& e) {
      ++failures;
      entry["error"] = e.what();
      std::cerr << "  " << capture.pair_id << ": NOT aligned: " << e.what() << "\n";
    }
    report["pairs"].push_back(entry);
  }
  const SharedPointAccuracy accuracy = evaluateSharedPoints(aligned);
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
  report["E_h"] = e_h;
  YAML::Emitter out;
  out << report;
  writeFileAtomically(options.report,
                      "# World alignment report (align_world); E_h = eq 4.2 over grid points "
                      "seen by two pairs.\n" +
                          std::string(out.c_str()) + "\n");
  const std::string plot = options.plot.empty()
                               ? fs::path(options.report).replace_extension(".png").string()
                               : options.plot;
  writePlot(plot, aligned, layout, accuracy);
  std::cout << "E_h (eq 4.2): " << accuracy.shared_points << " shared points, "
            << accuracy.comparisons << " comparisons, mean " << mm(accuracy.mean_m) << " mm, std "
            << mm(accuracy.std_m) << " mm, max " << mm(accuracy.max_m)
            << " mm\nreport: " << options.report << "\nplot: " << plot << "\n";
  return failures == 0 ? 0 : 1;
}

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parseOptions(int argc, char** argv, Options& options) {
  CLI::App app(
      "Aligns each projector-camera pair to the world frame defined by the calibration cylinder "
      "(thesis sec. 4.3.2): detects and triangulates the cylinder's grid points, fits the affine "
      "of eq 4.1 per pair, writes each pair's calibration file with its world_alignment section "
      "and a YAML report with E_h (eq 4.2) over the points seen by two pairs. Live against the "
      "simulator (default) or offline from an image folder (--images).",
      "align_world");
  const char* home = std::getenv("HOME");
  options.calibration_out = std::string(home ? home : ".") + "/.ros/body_scan/calibration";
  options.report = "world_alignment_report.yaml";
  auto* live = app.add_option_group("Live (simulator, default)");
  auto* scene = live->add_option(
      "--scene", options.scene,
      "cylinder scene (default: body_scan_driver's config/scenes/calibration_cylinder.yaml)");
  scene->check(CLI::ExistingFile);
  auto* pair =
      live->add_option("--pair", options.pairs,
                       "a pair file (repeat; default: body_scan_calib's config/alignment/*.yaml)");
  pair->check(CLI::ExistingFile);
  auto* save_images = live->add_option("--save-images", options.save_images,
                                       "also write what each pair captured, for an offline run");
  auto* offline = app.add_option_group("Offline");
  offline
      ->add_option("--images", options.images,
                   "one folder per pair as written by --save-images: frame_NN.png in pattern "
                   "order, texture.png, capture.yaml (pair_id, bits, inverse_frames)")
      ->excludes(scene)
      ->excludes(pair)
      ->excludes(save_images);
  app.add_option("--calibration-in", options.calibration_in,
                 "pair calibrations to align, <pole>_<pair>.yaml (live: the simulator's factory "
                 "calibration for a pair without a file; offline: required)");
  app.add_option("--calibration-out", options.calibration_out, "aligned calibrations")
      ->capture_default_str();
  app.add_option("--report", options.report, "YAML report")->capture_default_str();
  app.add_option("--plot", options.plot,
                 "PNG: top view of the aligned points, E_h per shared point against height "
                 "(default: the report's path with .png)");
  return body_scan_driver::tools::parseCommandLine(app, argc, argv);
}

// The live run's defaults from the packages that ship them: the cylinder scene, every pair file
// of the alignment rig.
void liveDefaults(Options& options) {
  if (options.scene.empty())
    options.scene = body_scan_driver::tools::packageFile(
        "body_scan_driver", "config/scenes/calibration_cylinder.yaml", "--scene");
  if (options.pairs.empty()) {
    for (const auto& entry : fs::directory_iterator(
             body_scan_driver::tools::packageFile("body_scan_calib", "config/alignment", "--pair")))
      if (entry.path().extension() == ".yaml") options.pairs.push_back(entry.path().string());
    std::sort(options.pairs.begin(), options.pairs.end());
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const auto status = parseOptions(argc, argv, options)) return *status;
  try {
    if (options.images.empty()) liveDefaults(options);
    return run(options);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
