// YAML body models and the gallery export (models_file.h).
#include <body_gait_id/models_file.h>
#include <yaml-cpp/yaml.h>

#include <iomanip>
#include <limits>
#include <map>
#include <stdexcept>

namespace body_gait_id {
namespace {

using body_gait::BodyModel;

template <typename Vector>
void readArray(const YAML::Node& pose, const char* key, Vector& out, const std::string& where) {
  const YAML::Node node = pose[key];
  if (!node || !node.IsSequence() || node.size() != std::size_t(out.size()))
    throw std::runtime_error(where + ": '" + key + "' must be a list of " +
                             std::to_string(out.size()) + " numbers");
  for (std::size_t i = 0; i < node.size(); ++i) out[i] = node[i].as<double>();
}

template <typename Vector>
YAML::Node list(const Vector& v) {
  YAML::Node node(YAML::NodeType::Sequence);
  for (Eigen::Index i = 0; i < Eigen::Index(v.size()); ++i) node.push_back(v[i]);
  node.SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

YAML::Node modelNode(const BodyModel& m) {
  YAML::Node node;
  node["p"] = list(m.p);
  node["q"] = list(m.q);
  node["r"] = list(m.r);
  node["proximal_radius"] = list(
      Eigen::Map<const Eigen::VectorXd>(m.shape.proximal_radius.data(), body_gait::kSegmentCount));
  node["distal_radius"] = list(
      Eigen::Map<const Eigen::VectorXd>(m.shape.distal_radius.data(), body_gait::kSegmentCount));
  node["shoulder_half_width"] = m.shape.shoulder_half_width;
  node["shoulder_drop"] = m.shape.shoulder_drop;
  node["hip_half_width"] = m.shape.hip_half_width;
  node["hip_rise"] = m.shape.hip_rise;
  return node;
}

void emit(std::ostream& out, const YAML::Node& node) {
  YAML::Emitter emitter;
  emitter.SetDoublePrecision(std::numeric_limits<double>::max_digits10);  // exact round trip
  emitter << node;
  out << emitter.c_str() << "\n";
}

}  // namespace

std::vector<BodyModel> readBodyModels(const std::string& path) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAllFromFile(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error("body models file '" + path +
                             "' cannot be read: check the path (a YAML file with 'poses:')");
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("body models file '" + path + "' is not valid YAML: " + e.what());
  }
  // Either one document with a 'poses:' list, or BodyModel messages one per document as
  // `rostopic echo /body_gait/model` prints them (same keys).
  std::vector<YAML::Node> poses;
  if (documents.size() == 1 && documents[0].IsMap() && documents[0]["poses"]) {
    if (!documents[0]["poses"].IsSequence())
      throw std::runtime_error("body models file '" + path + "': 'poses' must be a list");
    for (const YAML::Node& pose : documents[0]["poses"]) poses.push_back(pose);
  } else {
    for (const YAML::Node& document : documents)
      if (document.IsMap() && document["p"]) poses.push_back(document);
  }
  if (poses.empty())
    throw std::runtime_error("body models file '" + path +
                             "' has no 'poses:' list and no BodyModel messages (each pose: p, q, "
                             "r; see models_file.h)");
  std::vector<BodyModel> models;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string where = "body models file '" + path + "', pose " + std::to_string(i + 1);
    const YAML::Node& pose = poses[i];
    try {
      BodyModel m;
      m.shape = body_gait::standingModel(1.70).shape;
      readArray(pose, "p", m.p, where);
      readArray(pose, "q", m.q, where);
      readArray(pose, "r", m.r, where);
      if (pose["proximal_radius"]) {
        Eigen::Map<Eigen::VectorXd> proximal(m.shape.proximal_radius.data(),
                                             body_gait::kSegmentCount);
        Eigen::Map<Eigen::VectorXd> distal(m.shape.distal_radius.data(), body_gait::kSegmentCount);
        readArray(pose, "proximal_radius", proximal, where);
        readArray(pose, "distal_radius", distal, where);
      }
      for (auto [key, value] : {std::pair{"shoulder_half_width", &m.shape.shoulder_half_width},
                                {"shoulder_drop", &m.shape.shoulder_drop},
                                {"hip_half_width", &m.shape.hip_half_width},
                                {"hip_rise", &m.shape.hip_rise}})
        if (pose[key]) *value = pose[key].as<double>();
      models.push_back(m);
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(where + ": not a number (" + e.what() + ")");
    }
  }
  return models;
}

void writeBodyModels(std::ostream& out, const std::vector<BodyModel>& models) {
  YAML::Node root;
  for (const BodyModel& m : models) root["poses"].push_back(modelNode(m));
  emit(out, root);
}

void exportGalleryYaml(const GalleryDatabase& db, std::ostream& out) {
  YAML::Node root;
  root["database"] = db.path();
  root["schema_version"] = GalleryDatabase::kSchemaVersion;
  const std::vector<Subject> subjects = db.subjects();
  std::map<std::int64_t, std::size_t> index;
  for (const Subject& s : subjects) {
    YAML::Node node;
    node["id"] = s.id;
    node["name"] = s.info.name;
    node["gender"] = s.info.gender;
    node["age"] = s.info.age;
    node["enrolled"] = s.enrolled;
    node["scans"] = YAML::Node(YAML::NodeType::Sequence);
    for (const std::string& scan : s.scans) node["scans"].push_back(scan);
    node["poses"] = YAML::Node(YAML::NodeType::Sequence);
    index[s.id] = root["subjects"].size();
    root["subjects"].push_back(node);
  }
  for (const PoseRecord& record : db.poseRecords()) {
    YAML::Node pose = modelNode(record.model);
    pose["sequence"] = record.sequence;
    pose["frame"] = record.frame;
    root["subjects"][index.at(record.subject_id)]["poses"].push_back(pose);
  }
  if (!subjects.empty()) {
    const FeatureNormalization n = db.normalization(View::k3D);
    root["normalization_3d"]["mean_dynamic"] = list(n.mean_dynamic);
    root["normalization_3d"]["sigma_dynamic"] = list(n.sigma_dynamic);
    root["normalization_3d"]["mean_static"] = list(n.mean_static);
    root["normalization_3d"]["sigma_static"] = list(n.sigma_static);
  }
  emit(out, root);
}

void exportGalleryCsv(const GalleryDatabase& db, std::ostream& out) {
  std::map<std::int64_t, std::string> names;
  for (const Subject& s : db.subjects()) names[s.id] = s.info.name;
  out << "subject_id,name,sequence,frame";
  for (int i = 0; i < 22; ++i) out << ",q" << i;
  for (int i = 0; i < 12; ++i) out << ",r" << i;
  out << "\n" << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (const GalleryPose& pose : db.poses(View::k3D)) {
    std::string name = names[pose.subject_id];
    // RFC 4180: quote a name holding a comma, quote or line break, doubling its quotes.
    if (name.find_first_of(",\"\n") != std::string::npos) {
      std::string quoted = "\"";
      for (char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
      name = quoted + "\"";
    }
    out << pose.subject_id << "," << name << "," << pose.sequence << "," << pose.frame;
    for (Eigen::Index i = 0; i < pose.features.dynamic.size(); ++i)
      out << "," << pose.features.dynamic[i];
    for (Eigen::Index i = 0; i < pose.features.statics.size(); ++i)
      out << "," << pose.features.statics[i];
    out << "\n";
  }
}

}  // namespace body_gait_id
