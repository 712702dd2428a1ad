#include <body_gait_model/gait_poses_file.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace body_gait_model {
namespace {

std::set<std::string> modelKeys() {
  std::set<std::string> keys = {"p", "q", "r", "proximal_radius", "distal_radius"};
  for (const auto& placement : kJointPlacements) keys.insert(placement.name);
  return keys;
}
const std::set<std::string> kModelKeys = modelKeys();
// Written beside a model by evaluate_body_fit and the gallery export; not part of the model.
const std::set<std::string> kAnnotationKeys = {"frame", "sequence", "low_quality"};

// Where an error is: `file` (the file, named) and `pose` (e.g. "pose s2" or "pose 3").
struct Place {
  std::string file, pose;
};

std::vector<double> numbers(const YAML::Node& node, const char* key, std::size_t size,
                            const Place& at) {
  std::vector<double> values;
  try {
    values = node[key].as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(at.file + ", " + at.pose + ": '" + key + "' must be a list of " +
                             std::to_string(size) + " numbers");
  }
  if (values.size() != size)
    throw std::runtime_error(at.file + ", " + at.pose + ": '" + key + "' must be a list of " +
                             std::to_string(size) + " numbers (" + at.pose + "." + key + " has " +
                             std::to_string(values.size()) + " numbers, not " +
                             std::to_string(size) + ")");
  return values;
}

// strict: a key that is neither a model key nor an annotation is an error (a `poses:` list);
// messages carry other fields (header, segment names, quality), which are read past.
BodyModel modelFromYaml(const YAML::Node& node, const Place& at, bool strict) {
  if (!node.IsMap())
    throw std::runtime_error(at.file + ", " + at.pose + " must be a map with p, q, r");
  if (strict)
    for (const auto& entry : node) {
      const std::string key = entry.first.as<std::string>();
      if (kModelKeys.count(key) || kAnnotationKeys.count(key)) continue;
      std::string known;
      for (const auto& name : kModelKeys) known += (known.empty() ? "" : ", ") + name;
      throw std::runtime_error(at.file + ", " + at.pose + ": unknown key '" + key +
                               "'; known keys: " + known);
    }
  for (const char* key : {"p", "q", "r"})
    if (!node[key])
      throw std::runtime_error(at.file + ", " + at.pose + " has no '" + key + "' (eqs 5.1-5.3)");
  BodyModel model;
  model.p = Eigen::Map<const PoseVector>(numbers(node, "p", 6, at).data());
  model.q = Eigen::Map<const JointAngles>(numbers(node, "q", 22, at).data());
  model.r = Eigen::Map<const SegmentLengths>(numbers(node, "r", 12, at).data());
  // Default shape: a standard adult whose legs are this long (standingModel: legs 0.53 of H).
  const double legs = model.r[kRightUpperLeg] + model.r[kRightLowerLeg];
  if (!(legs > 0))
    throw std::runtime_error(at.file + ", " + at.pose + ": the leg lengths in 'r' must be > 0 m");
  model.shape = standingModel(legs / 0.53).shape;
  if (node["proximal_radius"]) {
    const auto radii = numbers(node, "proximal_radius", kSegmentCount, at);
    std::copy(radii.begin(), radii.end(), model.shape.proximal_radius.begin());
  }
  if (node["distal_radius"]) {
    const auto radii = numbers(node, "distal_radius", kSegmentCount, at);
    std::copy(radii.begin(), radii.end(), model.shape.distal_radius.begin());
  }
  for (const auto& [key, field] : kJointPlacements) {
    if (!node[key]) continue;
    try {
      model.shape.*field = node[key].as<double>();
    } catch (const YAML::Exception&) {
      throw std::runtime_error(at.file + ", " + at.pose + ": '" + key + "' must be a number");
    }
  }
  // Models written before hip_back existed put the hips on the lower torso's axis.
  if (node["hip_rise"] && !node["hip_back"]) model.shape.hip_back = 0;
  return model;
}

template <typename Vector>
YAML::Node flow(const Vector& values) {
  YAML::Node node(YAML::NodeType::Sequence);
  for (const double v : values) node.push_back(v);
  node.SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

// The YAML documents of a file. Not YAML::LoadAllFromFile: on some malformed text (e.g.
// "   , 0]") yaml-cpp 0.7's LoadAll returns empty documents forever without consuming input.
// The documents are split at their "---" / "..." marker lines (as rostopic echo writes them)
// and each is loaded alone. Throws YAML::BadFile or YAML::Exception.
std::vector<YAML::Node> loadDocuments(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw YAML::BadFile(path);
  std::vector<YAML::Node> documents;
  std::string document, line;
  bool any = false;  // text other than markers, blank lines and comments since the last marker
  auto flush = [&] {
    if (any) documents.push_back(YAML::Load(document));
    document.clear();
    any = false;
  };
  while (std::getline(in, line)) {
    const bool start = line.rfind("---", 0) == 0 && (line.size() == 3 || line[3] == ' ');
    const bool end = line == "...";
    if (start || end) {
      flush();
      if (start) document = line.substr(3) + "\n";  // "--- {a: 1}": content after the marker
      any = document.find_first_not_of(" \t\n") != std::string::npos;
      continue;
    }
    document += line + "\n";
    const size_t first = line.find_first_not_of(" \t");
    any = any || (first != std::string::npos && line[first] != '#');
  }
  flush();
  return documents;
}

// The models of a file, each labelled pose_prefix + its 1-based number. An empty `poses:` list
// gives none (the callers say what they needed).
std::vector<BodyModel> readModels(const std::string& path, const std::string& pose_prefix) {
  const std::string file = "body models file '" + path + "'";
  std::vector<YAML::Node> documents;
  try {
    documents = loadDocuments(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(file +
                             " cannot be read: check the path (a YAML file with 'poses:', "
                             "gait_poses_file.h)");
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(file + " is not valid YAML: " + e.what());
  }
  std::vector<YAML::Node> poses;
  bool strict = true;
  if (documents.size() == 1 && documents[0].IsMap() && documents[0]["poses"]) {
    if (!documents[0]["poses"].IsSequence())
      throw std::runtime_error(file + ": 'poses' must be a list of poses, each with p, q, r");
    for (const YAML::Node& pose : documents[0]["poses"]) poses.push_back(pose);
  } else {
    strict = false;  // BodyModel messages, as rostopic echo prints them
    for (const YAML::Node& document : documents)
      if (document.IsMap() && document["p"]) poses.push_back(document);
    if (poses.empty())
      throw std::runtime_error(file +
                               " has no 'poses:' list and no BodyModel messages (each pose: p, "
                               "q, r; see gait_poses_file.h)");
  }
  std::vector<BodyModel> models;
  for (std::size_t i = 0; i < poses.size(); ++i)
    models.push_back(modelFromYaml(poses[i], {file, pose_prefix + std::to_string(i + 1)}, strict));
  return models;
}

}  // namespace

YAML::Node bodyModelToYaml(const BodyModel& model) {
  YAML::Node node;
  node["p"] = flow(model.p);
  node["q"] = flow(model.q);
  node["r"] = flow(model.r);
  node["proximal_radius"] = flow(model.shape.proximal_radius);
  node["distal_radius"] = flow(model.shape.distal_radius);
  for (const auto& [key, field] : kJointPlacements) node[key] = model.shape.*field;
  return node;
}

std::string bodyModelsYaml(const std::vector<BodyModel>& models, const std::string& comment) {
  YAML::Node root;
  for (const BodyModel& model : models) root["poses"].push_back(bodyModelToYaml(model));
  YAML::Emitter out;
  out.SetDoublePrecision(17);  // exact round trip
  out << root;
  std::string text;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) text += "# " + line + "\n";
  return text + out.c_str() + "\n";
}

std::vector<BodyModel> loadBodyModels(const std::string& path) {
  std::vector<BodyModel> models = readModels(path, "pose ");
  if (models.empty())
    throw std::runtime_error("body models file '" + path +
                             "': 'poses' is empty (each pose: p, q, r; see gait_poses_file.h)");
  return models;
}

RepresentativePoses loadRepresentativePoses(const std::string& path) {
  const std::vector<BodyModel> models = readModels(path, "pose s");
  if (models.size() != 4)
    throw std::runtime_error("body models file '" + path + "' holds " +
                             std::to_string(models.size()) +
                             " poses: give exactly 4 poses (s1..s4 of thesis 5.3), each with p, "
                             "q, r");
  return {models[0], models[1], models[2], models[3]};
}

void saveRepresentativePoses(const std::string& path, const RepresentativePoses& poses) {
  std::ofstream file(path);
  if (!file) throw std::runtime_error("cannot write gait poses file '" + path + "'");
  file << bodyModelsYaml({poses.begin(), poses.end()},
                         "s1..s4 of thesis 5.3 (body_gait_model/gait_poses_file.h)");
  if (!file) throw std::runtime_error("writing gait poses file '" + path + "' failed");
}

}  // namespace body_gait_model
