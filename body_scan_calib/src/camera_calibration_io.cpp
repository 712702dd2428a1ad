#include <body_scan_calib/camera_calibration_io.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <yaml-cpp/yaml.h>

namespace body_scan_calib {

std::string cameraCalibrationYaml(const CameraCalibrationReport& report) {
  YAML::Node info;
  info["method"] =
      "Zhang closed form (thesis eqs 3.14-3.26) + Ceres Levenberg-Marquardt (body_scan_calib)";
  info["board"]["inner_cols"] = report.board.inner_cols;
  info["board"]["inner_rows"] = report.board.inner_rows;
  info["board"]["square_size"] = report.board.square_size;
  info["views"] = static_cast<int>(report.result.per_view_rms_px.size());
  info["rms_px"] = report.result.rms_px;
  info["iterations"] = report.result.iterations;
  const char* names[7] = {"alpha", "beta", "gamma", "u0", "v0", "k1", "k2"};
  for (int p = 0; p < 7; ++p) info["std_devs"][names[p]] = report.result.std_devs[p];
  for (size_t view = 0; view < report.result.per_view_rms_px.size(); ++view) {
    YAML::Node entry;
    entry["view"] =
        view < report.view_names.size() ? report.view_names[view] : "view " + std::to_string(view);
    entry["rms_px"] = report.result.per_view_rms_px[view];
    info["per_view"].push_back(entry);
  }
  YAML::Node root;
  root["calibration_report"] = info;

  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  return "# Camera calibration (body_scan): the camera part is readable by "
         "camera_calibration_parsers;\n# calibration_report says what the estimate is worth "
         "(std devs in pixels, k1/k2 unitless).\n" +
         cameraPartYaml(report.camera_name, report.result.camera) + std::string(out.c_str()) + "\n";
}

void saveCameraCalibration(const std::string& path, const CameraCalibrationReport& report) {
  try {
    body_scan_driver::writeFileAtomically(path, cameraCalibrationYaml(report));
  } catch (const body_scan_driver::FileWriteError& e) {
    throw CameraCalibrationError(e.what());
  }
}

body_scan_driver::PinholeCamera loadCameraCalibration(const std::string& path) {
  try {
    return body_scan_driver::loadCameraPart(path);
  } catch (const body_scan_driver::CalibrationFileError& e) {
    throw CameraCalibrationError(std::string(e.what()) +
                                 " (recalibrate with calibrate_camera --images DIR ... --output " +
                                 path + ")");
  }
}

}  // namespace body_scan_calib
