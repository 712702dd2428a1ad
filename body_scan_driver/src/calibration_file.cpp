#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/calibration_file.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

namespace body_scan_driver {
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
    throw CalibrationFileError("calibration file '" + path + "': '" + key + ".data' must hold " +
                               std::to_string(size) + " numbers; regenerate the file with the " +
                               "calibration tool or the simulator's factory calibration");
  return data.as<std::vector<double>>();
}

// The camera part (camera_calibration_parsers keys) of a camera or pair calibration file.
PinholeCamera readCameraPart(YAML::Node root, const std::string& path) {
  PinholeCamera camera;
  camera.width = root["image_width"].as<int>();
  camera.height = root["image_height"].as<int>();
  const std::vector<double> k = readMatrix(root, "camera_matrix", 9, path);
  camera.alpha = k[0], camera.gamma = k[1], camera.u0 = k[2], camera.beta = k[4], camera.v0 = k[5];
  const std::string model = root["distortion_model"].as<std::string>("plumb_bob");
  if (model != "plumb_bob")
    throw CalibrationFileError("calibration file '" + path + "': distortion_model '" + model +
                               "' is not supported; use plumb_bob with k1, k2 only");
  const std::vector<double> d = root["distortion_coefficients"]["data"].as<std::vector<double>>();
  if (d.size() < 2)
    throw CalibrationFileError("calibration file '" + path +
                               "': distortion_coefficients needs at least k1, k2");
  camera.k1 = d[0], camera.k2 = d[1];
  for (size_t i = 2; i < d.size(); ++i)
    if (d[i] != 0)
      throw CalibrationFileError("calibration file '" + path +
                                 "': only radial k1, k2 are modelled (eq 3.3); the tangential "
                                 "and k3 coefficients must be 0");
  if (camera.width <= 0 || camera.height <= 0 || !(camera.alpha > 0) || !(camera.beta > 0))
    throw CalibrationFileError("calibration file '" + path +
                               "': image size and focal lengths must be positive");
  return camera;
}

void writeCameraPart(YAML::Node& root, const PinholeCamera& c) {
  root["image_width"] = c.width;
  root["image_height"] = c.height;
  root["camera_matrix"] = matrixNode(3, 3, {c.alpha, c.gamma, c.u0, 0, c.beta, c.v0, 0, 0, 1});
  root["distortion_model"] = "plumb_bob";
  root["distortion_coefficients"] = matrixNode(1, 5, {c.k1, c.k2, 0, 0, 0});
  root["rectification_matrix"] = matrixNode(3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1});
  root["projection_matrix"] =
      matrixNode(3, 4, {c.alpha, c.gamma, c.u0, 0, 0, c.beta, c.v0, 0, 0, 0, 1, 0});
}

YAML::Node loadYamlFile(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw CalibrationFileError("calibration file '" + path +
                               "' not found: calibrate the pair, or start the simulated pair "
                               "with ~factory_calibration_file pointing there");
  } catch (const YAML::Exception& e) {
    throw CalibrationFileError("calibration file '" + path + "' is not valid YAML: " + e.what());
  }
}

}  // namespace

PairCalibration loadCalibration(const std::string& path) {
  YAML::Node root = loadYamlFile(path);  // non-const: a missing key must read as null, not throw
  try {
    PairCalibration calibration;
    calibration.pair_id = root["camera_name"].as<std::string>("");
    calibration.source = root["source"].as<std::string>("");
    calibration.camera = readCameraPart(root, path);
    const YAML::Node planes = root["projector"]["planes"];
    if (!planes || !planes.IsSequence() || planes.size() < 2)
      throw CalibrationFileError(
          "calibration file '" + path +
          "' has no 'projector: planes:' list (one [a, b, c, d] per stripe)");
    for (const YAML::Node& plane : planes) {
      const std::vector<double> p = plane.as<std::vector<double>>();
      // All four NaN = a stripe calibration never observed: it triangulates to nothing.
      const bool missing = p.size() == 4 && std::isnan(p[0]) && std::isnan(p[1]) &&
                           std::isnan(p[2]) && std::isnan(p[3]);
      if (p.size() != 4 || (!missing && !std::isfinite(p[0] + p[1] + p[2] + p[3])))
        throw CalibrationFileError(
            "calibration file '" + path +
            "': every projector plane must be 4 finite numbers [a, b, c, d], or "
            "[.nan, .nan, .nan, .nan] for a stripe that was never observed");
      calibration.projector.planes.emplace_back(p[0], p[1], p[2], p[3]);
    }
    if (const YAML::Node alignment = root["world_alignment"]) {
      const std::vector<double> h = readMatrix(alignment, "affine", 12, path);
      const Eigen::Matrix<double, 3, 4, Eigen::RowMajor> affine(h.data());
      try {
        calibration.alignment = WorldAlignment::fromAffine(affine);
      } catch (const std::invalid_argument& e) {
        throw CalibrationFileError("calibration file '" + path + "': " + e.what() +
                                   "; run align_world again");
      }
    }
    const int declared = root["projector"]["stripe_count"].as<int>(-1);
    if (declared != calibration.projector.stripeCount())
      throw CalibrationFileError("calibration file '" + path + "': stripe_count " +
                                 std::to_string(declared) + " does not match the " +
                                 std::to_string(calibration.projector.stripeCount()) + " planes");
    return calibration;
  } catch (const YAML::Exception& e) {
    throw CalibrationFileError("calibration file '" + path + "' is missing a field or has a " +
                               "wrong type (" + e.what() + ")");
  }
}

PinholeCamera loadCameraPart(const std::string& path) {
  YAML::Node root = loadYamlFile(path);  // non-const: a missing key must read as null, not throw
  try {
    return readCameraPart(root, path);
  } catch (const YAML::Exception& e) {
    throw CalibrationFileError("calibration file '" + path + "' is missing a field or has a " +
                               "wrong type (" + e.what() + ")");
  }
}

std::string cameraPartYaml(const std::string& camera_name, const PinholeCamera& camera) {
  YAML::Node root;
  root["camera_name"] = camera_name;
  writeCameraPart(root, camera);
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  return std::string(out.c_str()) + "\n";
}

void saveCalibration(const std::string& path, const PairCalibration& calibration) {
  YAML::Node root;
  root["camera_name"] = calibration.pair_id;
  root["source"] = calibration.source;
  writeCameraPart(root, calibration.camera);
  YAML::Node projector;
  projector["model"] = "stripe_planes";
  projector["stripe_count"] = calibration.projector.stripeCount();
  for (const Eigen::Vector4d& p : calibration.projector.planes) {
    YAML::Node plane;
    for (int i = 0; i < 4; ++i) plane.push_back(p[i]);
    plane.SetStyle(YAML::EmitterStyle::Flow);
    projector["planes"].push_back(plane);
  }
  root["projector"] = projector;
  if (calibration.alignment) {
    // Eq 4.1's H_a (rows of [A | t], metres); the rigid part and L follow from it on load.
    const Eigen::Matrix<double, 3, 4, Eigen::RowMajor> affine = calibration.alignment->affine();
    YAML::Node alignment;
    alignment["frame"] = "world";
    alignment["affine"] = matrixNode(3, 4, std::vector<double>(affine.data(), affine.data() + 12));
    root["world_alignment"] = alignment;
  }

  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  try {
    writeFileAtomically(
        path,
        "# Pair calibration (body_scan): camera part readable by camera_calibration_parsers;\n"
        "# projector planes a x + b y + c z + d = 0 per stripe, camera optical frame, metres;\n"
        "# a stripe never observed during calibration is [.nan, .nan, .nan, .nan].\n" +
            std::string(out.c_str()) + "\n");
  } catch (const FileWriteError& e) {
    throw CalibrationFileError(e.what());
  }
}

}  // namespace body_scan_driver
