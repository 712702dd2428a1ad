// FeatureNoise in YAML (feature_noise_file.h).
#include <body_gait_id/feature_noise_file.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

namespace body_gait_id {
namespace {

Eigen::VectorXd readVector(const YAML::Node& root, const char* key, int size,
                           const std::string& path) {
  const std::string where = "feature noise file '" + path + "': ";
  const YAML::Node node = root[key];
  if (!node || !node.IsSequence() || static_cast<int>(node.size()) != size)
    throw std::runtime_error(where + "'" + key + "' must be a list of " + std::to_string(size) +
                             " SDs; write the file with evaluate_gait_id --write-noise");
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) {
    try {
      v[i] = node[i].as<double>();
    } catch (const YAML::Exception&) {
      v[i] = std::nan("");
    }
    if (!(v[i] >= 0) || !std::isfinite(v[i]))
      throw std::runtime_error(where + "'" + key + "'[" + std::to_string(i) +
                               "] is not a non-negative number");
  }
  return v;
}

}  // namespace

FeatureNoise readFeatureNoise(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("feature noise file '" + path + "': " + e.what() +
                             " (check the path, or write the file with evaluate_gait_id "
                             "--write-noise)");
  }
  return {readVector(root, "dynamic", dynamicSize(View::k3D), path),
          readVector(root, "statics", kStaticSize, path),
          readVector(root, "shape", kShapeSize, path)};
}

std::string featureNoiseYaml(const FeatureNoise& noise, const std::string& source) {
  YAML::Emitter out;
  out.SetDoublePrecision(6);
  out << YAML::Comment(
             "within-subject SD of each 3D feature component between two walks of a person "
             "(rad, m); body_gait_id feature_noise_file.h")
      << YAML::BeginMap << YAML::Key << "source" << YAML::Value << source;
  const auto list = [&out](const char* key, const Eigen::VectorXd& v) {
    out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (Eigen::Index i = 0; i < v.size(); ++i) out << v[i];
    out << YAML::EndSeq;
  };
  list("dynamic", noise.dynamic);
  list("statics", noise.statics);
  list("shape", noise.shape);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace body_gait_id
