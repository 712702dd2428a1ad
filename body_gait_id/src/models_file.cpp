// YAML body models and the gallery export (models_file.h).
#include <body_gait_id/models_file.h>
#include <body_gait_model/gait_poses_file.h>
#include <yaml-cpp/yaml.h>

#include <iomanip>
#include <limits>
#include <map>
#include <stdexcept>

namespace body_gait_id {
namespace {

using body_gait_model::BodyModel;

template <typename Vector>
YAML::Node list(const Vector& v) {
  YAML::Node node(YAML::NodeType::Sequence);
  for (Eigen::Index i = 0; i < Eigen::Index(v.size()); ++i) node.push_back(v[i]);
  node.SetStyle(YAML::EmitterStyle::Flow);
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
  return body_gait_model::loadBodyModels(path);
}

void writeBodyModels(std::ostream& out, const std::vector<BodyModel>& models) {
  out << body_gait_model::bodyModelsYaml(models);
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
    YAML::Node pose = body_gait_model::bodyModelToYaml(record.model);
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
