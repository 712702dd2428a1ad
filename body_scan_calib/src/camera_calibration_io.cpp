#include <body_scan_calib/camera_calibration_io.h>
#include <body_scan_driver/atomic_file.h>
#include <yaml-cpp/yaml.h>

namespace body_scan::calib {
namespace {

YAML::Node matrixNode(int rows, int cols, const std::vector<double>& data) {
  YAML::Node node;
  node["rows"] = rows;
  node["cols"] = cols;
  node["data"] = data;
  node["data"].SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

std::vector<double> readMatrix(const YAML::Node& root, const std::string& key, size_t size,
                               const std::string& path) {
  const YAML::Node data = root[key]["data"];
  if (!data || !data.IsSequence() || data.size() != size)
    throw CameraCalibrationError("camera calibration file '" + path + "': '" + key +
                                 ".data' must hold " + std::to_string(size) +
                                 " numbers; recalibrate with calibrate_camera");
  return data.as<std::vector<double>>();
}

}  // namespace

std::string cameraCalibrationYaml(const CameraCalibrationReport& report) {
  const PinholeCamera& c = report.result.camera;
  YAML::Node root;
  root["camera_name"] = report.camera_name;
  root["image_width"] = c.width;
  root["image_height"] = c.height;
  root["camera_matrix"] = matrixNode(3, 3, {c.alpha, c.gamma, c.u0, 0, c.beta, c.v0, 0, 0, 1});
  root["distortion_model"] = "plumb_bob";
  root["distortion_coefficients"] = matrixNode(1, 5, {c.k1, c.k2, 0, 0, 0});
  root["rectification_matrix"] = matrixNode(3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1});
  root["projection_matrix"] =
      matrixNode(3, 4, {c.alpha, c.gamma, c.u0, 0, 0, c.beta, c.v0, 0, 0, 0, 1, 0});

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
  root["calibration_report"] = info;

  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  return "# Camera calibration (body_scan): the camera part is readable by "
         "camera_calibration_parsers;\n# calibration_report says what the estimate is worth "
         "(std devs in pixels, k1/k2 unitless).\n" +
         std::string(out.c_str()) + "\n";
}

void saveCameraCalibration(const std::string& path, const CameraCalibrationReport& report) {
  try {
    writeFileAtomically(path, cameraCalibrationYaml(report));
  } catch (const FileWriteError& e) {
    throw CameraCalibrationError(e.what());
  }
}

PinholeCamera loadCameraCalibration(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw CameraCalibrationError("camera calibration file '" + path +
                                 "' not found: run calibrate_camera --images DIR ... --output " +
                                 path);
  } catch (const YAML::Exception& e) {
    throw CameraCalibrationError("camera calibration file '" + path +
                                 "' is not valid YAML: " + e.what());
  }
  try {
    PinholeCamera camera;
    camera.width = root["image_width"].as<int>();
    camera.height = root["image_height"].as<int>();
    const std::vector<double> k = readMatrix(root, "camera_matrix", 9, path);
    camera.alpha = k[0], camera.gamma = k[1], camera.u0 = k[2], camera.beta = k[4],
    camera.v0 = k[5];
    const std::string model = root["distortion_model"].as<std::string>("plumb_bob");
    if (model != "plumb_bob")
      throw CameraCalibrationError("camera calibration file '" + path + "': distortion_model '" +
                                   model + "' is not supported; use plumb_bob with k1, k2 only");
    const std::vector<double> d = root["distortion_coefficients"]["data"].as<std::vector<double>>();
    if (d.size() < 2)
      throw CameraCalibrationError("camera calibration file '" + path +
                                   "': distortion_coefficients needs at least k1, k2");
    camera.k1 = d[0], camera.k2 = d[1];
    for (size_t i = 2; i < d.size(); ++i)
      if (d[i] != 0)
        throw CameraCalibrationError("camera calibration file '" + path +
                                     "': only radial k1, k2 are modelled (eq 3.3); tangential "
                                     "and k3 coefficients must be 0 - recalibrate with "
                                     "calibrate_camera");
    if (camera.width <= 0 || camera.height <= 0 || !(camera.alpha > 0) || !(camera.beta > 0))
      throw CameraCalibrationError("camera calibration file '" + path +
                                   "': image size and focal lengths must be positive");
    return camera;
  } catch (const YAML::Exception& e) {
    throw CameraCalibrationError("camera calibration file '" + path +
                                 "' is missing a field or has a wrong type (" + e.what() + ")");
  }
}

}  // namespace body_scan::calib
