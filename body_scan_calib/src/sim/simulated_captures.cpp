#include <body_scan_calib/capture_folder.h>
#include <body_scan_calib/sim/calibration_scenes.h>
#include <body_scan_calib/sim/simulated_captures.h>
#include <body_scan_driver/sim/calibration_cylinder.h>

#include <filesystem>
#include <iostream>
#include <opencv2/imgproc.hpp>

namespace body_scan_calib::sim {

namespace fs = std::filesystem;
using body_scan_driver::sim::VirtualPair;
using body_scan_driver::sim::VirtualPairConfig;

PairViews captureSimulatedPairViews(const VirtualPairConfig& config, const Checkerboard& board,
                                    int exposures, const std::string& save_images) {
  PairViews views;
  views.layout = body_scan_driver::PatternLayout(config.bits, config.inverse_frames);
  views.exposures = exposures;
  const auto poses = rig::defaultBoardPoses();
  for (size_t pose = 0; pose < poses.size(); ++pose) {
    std::cout << "placing the board in pose " << pose + 1 << "/" << poses.size() << ", capturing "
              << exposures << " exposures" << std::endl;
    const VirtualPair pair(config, rig::boardScene(board, poses[pose], config.world_from_camera));
    views.pose_frames.push_back(
        rig::captureAveraged(pair, exposures, static_cast<uint32_t>(1000 * pose)));
    if (!save_images.empty())
      savePatternFrames((fs::path(save_images) / poseFolderName(static_cast<int>(pose))).string(),
                        views.pose_frames.back());
  }
  std::cout << "placing the five evaluation spheres, capturing " << exposures << " exposures"
            << std::endl;
  const VirtualPair sphere_pair(
      config,
      rig::sphereScene(views.nominal_centers, views.sphere_radius_m, config.world_from_camera));
  views.sphere_frames = rig::captureAveraged(sphere_pair, exposures, 90000);
  views.sphere_single_frames = rig::captureAveraged(sphere_pair, 1, 99000);
  if (!save_images.empty())
    savePatternFrames((fs::path(save_images) / "spheres").string(), views.sphere_frames);
  views.true_centers = views.nominal_centers;  // the simulator places them exactly
  views.truth = sphere_pair.factoryCalibration();
  return views;
}

std::vector<CylinderCapture> captureSimulatedCylinder(const std::string& scene_file,
                                                      const std::vector<std::string>& pair_files,
                                                      const std::string& calibration_in,
                                                      const std::string& save_images,
                                                      bool ideal_optics) {
  auto scene =
      std::make_shared<body_scan_driver::sim::Scene>(body_scan_driver::sim::loadScene(scene_file));
  const body_scan_driver::sim::CalibrationCylinder* cylinder = nullptr;
  for (const auto& surface : scene->surfaces())
    if (auto found = dynamic_cast<const body_scan_driver::sim::CalibrationCylinder*>(surface.get()))
      cylinder = found;
  if (!cylinder)
    throw std::runtime_error("scene '" + scene_file +
                             "' has no calibration_cylinder object; use "
                             "body_scan_driver/config/scenes/calibration_cylinder.yaml");
  std::vector<CylinderCapture> captures;
  for (size_t i = 0; i < pair_files.size(); ++i) {
    VirtualPairConfig config = body_scan_driver::sim::loadVirtualPairConfig(pair_files[i]);
    if (!ideal_optics) config = body_scan_driver::sim::withRealCaptureOptics(config);
    std::cout << "[" << i + 1 << "/" << pair_files.size() << "] " << config.pair_id
              << ": capturing the cylinder (simulator)... " << std::flush;
    const VirtualPair pair(config, scene);
    body_scan_driver::sim::RenderedPatternSet rendered = pair.render(1);
    CylinderCapture capture;
    capture.pair_id = config.pair_id;
    capture.frames = std::move(rendered.frames);
    cv::cvtColor(rendered.texture, capture.gray, cv::COLOR_RGB2GRAY);
    capture.layout = pair.layout();
    if (auto calibration = calibrationToAlign(calibration_in, config.pair_id)) {
      capture.calibration = *calibration;
    } else {
      capture.calibration = pair.factoryCalibration();
      std::cout << "(no calibration in '" << calibration_in
                << "': using the simulator's factory calibration) ";
    }
    capture.true_cylinder_from_camera =
        cylinder->worldFromCylinder().inverse() * config.world_from_camera;
    std::cout << "done\n";
    if (!save_images.empty()) saveCylinderCapture(capture, save_images);
    captures.push_back(std::move(capture));
  }
  return captures;
}

}  // namespace body_scan_calib::sim
