// The mesh human: kit loading, macro morphing, the person spec, segment skinning.
#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_driver/sim/mesh_human.h>
#include <body_scan_driver/sim/triangle_mesh.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <set>
#include <stdexcept>

#include "../yaml_file.h"

namespace body_scan_driver::sim {

// ---------------------------------------------------------------------------------------------
// Loading.
namespace {

class Reader {
 public:
  Reader(std::vector<char> bytes, std::string path) : bytes_(std::move(bytes)), path_(path) {}
  template <typename T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::string str() {
    const size_t length = get<uint16_t>();
    need(length);
    std::string text(bytes_.data() + at_, length);
    at_ += length;
    return text;
  }
  bool done() const { return at_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& problem) const {
    throw std::runtime_error("mesh human kit '" + path_ + "': " + problem +
                             " (rebuild it with scripts/pack_mesh_human.py)");
  }

 private:
  void need(size_t count) const {
    if (at_ + count > bytes_.size()) fail("truncated at byte " + std::to_string(at_));
  }
  std::vector<char> bytes_;
  std::string path_;
  size_t at_ = 0;
};

// The state tokens of a target name: every '-'/'/'-separated token that names a state.
std::vector<std::string> stateTokens(const std::string& name) {
  static const std::set<std::string> kStates = {
      "female",    "male",          "young",     "old",           "african",
      "asian",     "caucasian",     "minmuscle", "averagemuscle", "maxmuscle",
      "minweight", "averageweight", "maxweight", "minheight",     "maxheight"};
  std::vector<std::string> tokens;
  std::string token;
  for (const char c : name + "-") {
    if (c == '-' || c == '/' || c == '_' || c == '.') {
      if (kStates.count(token)) tokens.push_back(token);
      token.clear();
    } else {
      token += c;
    }
  }
  return tokens;
}

}  // namespace

MeshHumanModel MeshHumanModel::load(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file)
    throw std::runtime_error("cannot read the mesh human kit '" + path +
                             "' (data/mesh_human/mesh_human.bin of body_scan_driver)");
  Reader in(std::vector<char>(std::istreambuf_iterator<char>(file), {}), path);
  if (in.get<uint32_t>() != 0x484d5342u || in.get<uint32_t>() != 1)
    in.fail("not a version 1 kit (magic BSMH)");
  MeshHumanModel model;
  const uint32_t vertex_count = in.get<uint32_t>();
  if (vertex_count == 0 || vertex_count > 65535) in.fail("bad vertex count");
  model.base.resize(vertex_count);
  for (auto& v : model.base)
    for (int i = 0; i < 3; ++i) v[i] = in.get<float>();
  model.body_vertex_count = static_cast<int>(in.get<uint32_t>());
  if (model.body_vertex_count <= 0 || model.body_vertex_count > static_cast<int>(vertex_count))
    in.fail("bad skin vertex count");
  auto vertex = [&](int limit) {
    const uint16_t index = in.get<uint16_t>();
    if (index >= limit) in.fail("vertex index " + std::to_string(index) + " out of range");
    return index;
  };
  model.quads.resize(in.get<uint32_t>());
  for (auto& quad : model.quads)
    for (auto& index : quad) index = vertex(model.body_vertex_count);
  model.joints.resize(in.get<uint32_t>());
  for (size_t j = 0; j < model.joints.size(); ++j) {
    Joint& joint = model.joints[j];
    joint.name = in.str();
    joint.vertices.resize(in.get<uint16_t>());
    if (joint.vertices.empty()) in.fail("joint '" + joint.name + "' has no vertices");
    for (auto& index : joint.vertices) index = vertex(vertex_count);
    model.joint_index[joint.name] = static_cast<int>(j);
  }
  model.bones.resize(in.get<uint32_t>());
  for (size_t b = 0; b < model.bones.size(); ++b) {
    Bone& bone = model.bones[b];
    bone.name = in.str();
    bone.parent = in.str();
    const std::string head = in.str(), tail = in.str();
    if (!model.joint_index.count(head) || !model.joint_index.count(tail))
      in.fail("bone '" + bone.name + "' names an unknown joint");
    bone.head = model.joint_index[head];
    bone.tail = model.joint_index[tail];
    bone.weights.resize(in.get<uint32_t>());
    for (auto& [index, weight] : bone.weights) {
      index = vertex(model.body_vertex_count);
      weight = in.get<float>();
    }
    model.bone_index[bone.name] = static_cast<int>(b);
  }
  for (const Bone& bone : model.bones)
    if (!bone.parent.empty() && !model.bone_index.count(bone.parent))
      in.fail("bone '" + bone.name + "' has an unknown parent");
  model.targets.resize(in.get<uint32_t>());
  for (size_t t = 0; t < model.targets.size(); ++t) {
    Target& target = model.targets[t];
    target.name = in.str();
    target.states = stateTokens(target.name);
    target.height = target.name.rfind("height/", 0) == 0;
    const int32_t same_as = in.get<int32_t>();
    if (same_as >= static_cast<int32_t>(t)) in.fail("target '" + target.name + "' refers ahead");
    if (same_as >= 0) {
      target.data = model.targets[same_as].data;
      continue;
    }
    target.data = static_cast<int>(model.offsets.size());
    std::vector<Offset>& offsets = model.offsets.emplace_back(in.get<uint32_t>());
    for (Offset& offset : offsets) {
      offset.vertex = vertex(vertex_count);
      for (auto& d : offset.delta) d = in.get<int16_t>();
    }
  }
  if (!in.done()) in.fail("trailing bytes");
  return model;
}

int MeshHumanModel::jointIndex(const std::string& name) const {
  const auto found = joint_index.find(name);
  if (found == joint_index.end())
    throw std::out_of_range("mesh human: no joint '" + name +
                            "' (names are '<bone>____head' or '<bone>____tail')");
  return found->second;
}

const MeshHumanModel& meshHumanModel(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<MeshHumanModel>> models;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& model = models[path];
  if (!model) model = std::make_unique<MeshHumanModel>(MeshHumanModel::load(path));
  return *model;
}

// ---------------------------------------------------------------------------------------------
// Morphing.
namespace {

// MakeHuman's three-state slider split: min, average, max.
void threeStates(double value, const char* lo, const char* mid, const char* hi,
                 std::map<std::string, double>& states) {
  const double low = std::max(0.0, 1 - 2 * value), high = std::max(0.0, 2 * value - 1);
  states[lo] = low;
  states[mid] = 1 - low - high;
  states[hi] = high;
}

void checkSlider(double value, double lo, double hi, const char* name) {
  if (!(value >= lo && value <= hi))
    throw std::invalid_argument(std::string("mesh human: macro '") + name + "' must be in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                std::to_string(value));
}

}  // namespace

std::vector<double> targetWeights(const MeshHumanModel& model, const MacroParameters& m) {
  checkSlider(m.gender, 0, 1, "gender");
  checkSlider(m.age, 0.5, 1, "age (the kit holds adults only: 0.5 = 25 years .. 1 = 90)");
  checkSlider(m.muscle, 0, 1, "muscle");
  checkSlider(m.weight, 0, 1, "weight");
  checkSlider(m.height, 0, 1, "height");
  for (double race : {m.african, m.asian, m.caucasian}) checkSlider(race, 0, 1, "ethnic blend");
  const double races = m.african + m.asian + m.caucasian;
  if (!(races > 0)) throw std::invalid_argument("mesh human: the ethnic blend sums to 0");
  std::map<std::string, double> states = {{"female", 1 - m.gender},
                                          {"male", m.gender},
                                          {"old", 2 * m.age - 1},
                                          {"young", 2 - 2 * m.age},
                                          {"african", m.african / races},
                                          {"asian", m.asian / races},
                                          {"caucasian", m.caucasian / races},
                                          {"minheight", std::max(0.0, 1 - 2 * m.height)},
                                          {"maxheight", std::max(0.0, 2 * m.height - 1)}};
  threeStates(m.muscle, "minmuscle", "averagemuscle", "maxmuscle", states);
  threeStates(m.weight, "minweight", "averageweight", "maxweight", states);
  std::vector<double> weights;
  weights.reserve(model.targets.size());
  for (const MeshHumanModel::Target& target : model.targets) {
    double weight = 1;
    for (const std::string& state : target.states)
      if (!(target.height && (state == "young" || state == "old"))) weight *= states[state];
    weights.push_back(weight);
  }
  return weights;
}

MorphedMesh morphMesh(const MeshHumanModel& model, const MacroParameters& macros) {
  const std::vector<double> weights = targetWeights(model, macros);
  std::vector<Eigen::Vector3d> shape(model.base.size());
  for (size_t i = 0; i < shape.size(); ++i) shape[i] = model.base[i].cast<double>();
  for (size_t t = 0; t < model.targets.size(); ++t) {
    if (std::abs(weights[t]) < 1e-9) continue;
    const double scale = weights[t] * 1e-3;  // stored in 1/1000 decimetre
    for (const MeshHumanModel::Offset& offset : model.offsets[model.targets[t].data])
      shape[offset.vertex] +=
          scale * Eigen::Vector3d(offset.delta[0], offset.delta[1], offset.delta[2]);
  }
  // MakeHuman axes (decimetres, y up, face +z, left +x) -> world (metres, z up, x front, y left).
  double floor = std::numeric_limits<double>::infinity(), top = -floor;
  for (int i = 0; i < model.body_vertex_count; ++i) {
    floor = std::min(floor, shape[i].y());
    top = std::max(top, shape[i].y());
  }
  MorphedMesh mesh;
  mesh.vertices.resize(shape.size());
  for (size_t i = 0; i < shape.size(); ++i)
    mesh.vertices[i] =
        Eigen::Vector3f(0.1 * shape[i].z(), 0.1 * shape[i].x(), 0.1 * (shape[i].y() - floor));
  mesh.stature = 0.1 * (top - floor);
  for (const MeshHumanModel::Joint& joint : model.joints) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const uint16_t v : joint.vertices) sum += mesh.vertices[v].cast<double>();
    mesh.joints.push_back(sum / joint.vertices.size());
  }
  // Signed volume of the closed skin (divergence theorem over its triangles).
  double volume = 0;
  for (const auto& quad : model.quads)
    for (const auto& [a, b, c] : {std::array<int, 3>{quad[0], quad[1], quad[2]},
                                  std::array<int, 3>{quad[0], quad[2], quad[3]}})
      volume += mesh.vertices[a].cast<double>().dot(
          mesh.vertices[b].cast<double>().cross(mesh.vertices[c].cast<double>()));
  mesh.volume = volume / 6;
  return mesh;
}

std::vector<std::array<int, 3>> skinTriangles(const MeshHumanModel& model) {
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(2 * model.quads.size());
  for (const auto& q : model.quads) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
  return triangles;
}

int boundaryEdgeCount(const MeshHumanModel& model) {
  // An edge of a closed 2-manifold is used once in each direction.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& q : model.quads)
    for (int k = 0; k < 4; ++k) ++directed[{q[k], q[(k + 1) % 4]}];
  int boundary = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++boundary;
  }
  return boundary;
}

// ---------------------------------------------------------------------------------------------
// The person spec.
namespace {

constexpr double kBodyDensity = 1000.0;  // kg/m^3: the BMI-like weight's mass per skin volume

double bmiOf(const MorphedMesh& mesh) {
  return kBodyDensity * mesh.volume / (mesh.stature * mesh.stature);
}

// The slider in [0, 1] at which measure(slider) = goal (measure increasing), by bisection.
template <typename Measure>
double solveSlider(Measure measure, double goal, double tolerance, const char* what,
                   double spec_value) {
  double lo = 0, hi = 1;
  const double at_lo = measure(lo), at_hi = measure(hi);
  if (goal < at_lo - tolerance || goal > at_hi + tolerance)
    throw std::invalid_argument("mesh human: " + std::string(what) + " " +
                                std::to_string(spec_value) +
                                " is outside what the body kit reaches (" + std::to_string(at_lo) +
                                " .. " + std::to_string(at_hi) + " for this person)");
  for (int iteration = 0; iteration < 40 && hi - lo > 1e-6; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    const double value = measure(mid);
    if (std::abs(value - goal) < tolerance) return mid;
    (value < goal ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

MacroParameters personMacros(const MeshHumanModel& model, const MeshPersonSpec& person) {
  if (!(person.stature >= 1.40 && person.stature <= 2.10))
    throw std::invalid_argument("mesh human: stature must be 1.40-2.10 m, got " +
                                std::to_string(person.stature));
  if (!(person.age >= 25 && person.age <= 90))
    throw std::invalid_argument(
        "mesh human: age must be 25-90 years (the kit has adults only), got " +
        std::to_string(person.age));
  MacroParameters macros;
  macros.gender = person.gender;
  macros.age = 0.5 + (person.age - 25) / 130;
  macros.muscle = person.muscle;
  macros.african = person.african;
  macros.asian = person.asian;
  macros.caucasian = person.caucasian;
  targetWeights(model, macros);  // validates the sliders
  auto stature_at = [&](double h) {
    MacroParameters m = macros;
    m.height = h;
    return morphMesh(model, m).stature;
  };
  auto bmi_at = [&](double MacroParameters::*slider, double value) {
    MacroParameters m = macros;
    m.*slider = value;
    return bmiOf(morphMesh(model, m));
  };
  for (int round = 0; round < 2; ++round) {
    macros.height = solveSlider(stature_at, person.stature, 0.0005, "stature", person.stature);
    // Body fat first; beyond its range the muscle makes up the rest (a heavy or a slight build).
    macros.muscle = person.muscle;
    const double heaviest = bmi_at(&MacroParameters::weight, 1);
    const double lightest = bmi_at(&MacroParameters::weight, 0);
    if (person.bmi > heaviest || person.bmi < lightest) {
      macros.weight = person.bmi > heaviest ? 1 : 0;
      const double from = person.muscle, to = person.bmi > heaviest ? 1.0 : 0.0;
      macros.muscle =
          from + (to - from) * solveSlider(
                                   [&](double f) {
                                     const double value =
                                         bmi_at(&MacroParameters::muscle, from + (to - from) * f);
                                     return to > from ? value : -value;
                                   },
                                   to > from ? person.bmi : -person.bmi, 0.05, "bmi", person.bmi);
    } else {
      macros.weight = solveSlider([&](double w) { return bmi_at(&MacroParameters::weight, w); },
                                  person.bmi, 0.05, "bmi", person.bmi);
    }
  }
  // The body fat moves the vertex by a fraction of a millimetre: settle the stature last.
  macros.height = solveSlider(stature_at, person.stature, 0.0005, "stature", person.stature);
  return macros;
}

// ---------------------------------------------------------------------------------------------
// The retarget map.
MeshRetargetMap loadMeshRetargetMap(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "mesh retarget map");
  const std::string where = "mesh retarget map '" + path + "'";
  requireKnownKeys(root, {"segments", "joints"}, where);
  MeshRetargetMap map;
  try {
    if (!root["segments"] || !root["segments"].IsMap())
      throw std::runtime_error("'segments' must map each body segment to a list of bones");
    for (const auto& entry : root["segments"])
      map.segment_bones[entry.first.as<std::string>()] =
          entry.second.as<std::vector<std::string>>();
    if (!root["joints"] || !root["joints"].IsMap())
      throw std::runtime_error("'joints' must map skeleton joints to mesh joints");
    for (const auto& entry : root["joints"])
      map.joints[entry.first.as<std::string>()] = entry.second.as<std::string>();
  } catch (const std::exception& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
  for (int s = 0; s < MeshHumanRig::kSegmentCount; ++s)
    if (!map.segment_bones.count(MeshHumanRig::segmentName(s)))
      throw std::runtime_error(where + ": 'segments' lacks '" + MeshHumanRig::segmentName(s) + "'");
  for (const char* joint :
       {"left_shoulder", "left_elbow", "left_wrist", "left_hand_tip", "left_hip", "left_knee",
        "left_ankle", "right_shoulder", "right_elbow", "right_wrist", "right_hand_tip", "right_hip",
        "right_knee", "right_ankle"})
    if (!map.joints.count(joint))
      throw std::runtime_error(where + ": 'joints' lacks '" + joint + "'");
  return map;
}

// ---------------------------------------------------------------------------------------------
// The rig.
namespace {

const char* const kSegmentNames[MeshHumanRig::kSegmentCount] = {
    "pelvis",        "torso",      "neck",        "left_upper_arm", "left_forearm",
    "left_hand",     "left_thigh", "left_shank",  "left_foot",      "right_upper_arm",
    "right_forearm", "right_hand", "right_thigh", "right_shank",    "right_foot"};
enum Segment { kPelvis, kTorso, kNeck, kUpperArm, kForearm, kHand, kThigh, kShank, kFoot };
// Index of a limb segment of a side (0 left, 1 right).
int limb(int kind, int side) { return kind + 6 * side; }

SegmentFrame limbFrameAt(const Eigen::Vector3d& proximal, const Eigen::Vector3d& distal) {
  const Eigen::Vector3d z = (proximal - distal).normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  x.normalize();
  SegmentFrame frame;
  frame.origin = proximal;
  frame.rotation << x, z.cross(x), z;
  return frame;
}

SegmentFrame trunkFrameAt(const Eigen::Vector3d& origin, const Eigen::Vector3d& top,
                          const Eigen::Vector3d& left) {
  const Eigen::Vector3d z = (top - origin).normalized();
  const Eigen::Vector3d y = (left - left.dot(z) * z).normalized();
  SegmentFrame frame;
  frame.origin = origin;
  frame.rotation << y.cross(z), y, z;
  return frame;
}

// The mesh's shoulder, hip ... of the retarget map.
Eigen::Vector3d mapped(const MeshHumanModel& model, const MorphedMesh& mesh,
                       const MeshRetargetMap& map, const std::string& joint) {
  return mesh.joints[model.jointIndex(map.joints.at(joint))];
}

}  // namespace

const char* MeshHumanRig::segmentName(int segment) { return kSegmentNames[segment]; }

MeshHumanRig::MeshHumanRig(const MeshHumanModel& model, MorphedMesh mesh,
                           const MeshRetargetMap& map)
    : model_(model), mesh_(std::move(mesh)) {
  // Rest frames in the FK conventions of human_body.h (limbs: bone along -z, x to the front).
  auto joint = [&](const std::string& name) { return mapped(model, mesh_, map, name); };
  const char* const sides[2] = {"left_", "right_"};
  auto sided = [&](int side, const char* name) { return joint(sides[side] + std::string(name)); };
  const Eigen::Vector3d hip_mid = 0.5 * (sided(0, "hip") + sided(1, "hip"));
  const Eigen::Vector3d shoulder_mid = 0.5 * (sided(0, "shoulder") + sided(1, "shoulder"));
  const Eigen::Vector3d hip_line = sided(0, "hip") - sided(1, "hip");
  const Eigen::Vector3d shoulder_line = sided(0, "shoulder") - sided(1, "shoulder");
  // Landmarks: the vertex (highest skin vertex) and each foot's toe (its foremost vertex).
  head_top_vertex_ = 0;
  toe_vertex_ = {-1, -1};
  for (int i = 0; i < model.body_vertex_count; ++i) {
    const Eigen::Vector3f& p = mesh_.vertices[i];
    if (p.z() > mesh_.vertices[head_top_vertex_].z()) head_top_vertex_ = i;
    if (p.z() < 0.1) {
      int& toe = toe_vertex_[p.y() > 0 ? 0 : 1];
      if (toe < 0 || p.x() > mesh_.vertices[toe].x()) toe = i;
    }
  }
  const Eigen::Vector3d head_top = mesh_.vertices[head_top_vertex_].cast<double>();

  BodySegmentFrames& rest = rest_frames_;
  rest.pelvis = trunkFrameAt(hip_mid, hip_mid + Eigen::Vector3d::UnitZ(), hip_line);
  rest.torso = trunkFrameAt(hip_mid, shoulder_mid, shoulder_line);
  // The neck frame keeps the torso's orientation at rest, as forward kinematics has it.
  rest.neck = {rest.torso.rotation, shoulder_mid};
  rest_length_[kPelvis] = 1;
  rest_length_[kTorso] = (shoulder_mid - hip_mid).norm();
  rest_length_[kNeck] = (head_top - shoulder_mid).dot(rest.neck.rotation.col(2));
  rest_width_ = {hip_line.norm(), shoulder_line.norm()};
  Anthropometry& a = anthropometry_;
  a = Anthropometry::fromStature(mesh_.stature);
  a.hip_width = rest_width_[0];
  a.shoulder_width = rest_width_[1];
  a.torso_length = rest_length_[kTorso];
  a.head_height = rest_length_[kNeck] * 0.130 / (0.130 + 0.052);
  a.neck_length = rest_length_[kNeck] - a.head_height;
  a.upper_arm_length = a.forearm_length = a.hand_length = 0;
  a.thigh_length = a.shank_length = a.ankle_height = a.foot_length = 0;
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3d shoulder = sided(side, "shoulder"), elbow = sided(side, "elbow"),
                          wrist = sided(side, "wrist"), tip = sided(side, "hand_tip"),
                          hip = sided(side, "hip"), knee = sided(side, "knee"),
                          ankle = sided(side, "ankle");
    rest.upper_arm[side] = limbFrameAt(shoulder, elbow);
    rest.forearm[side] = limbFrameAt(elbow, wrist);
    rest.hand[side] = limbFrameAt(wrist, tip);
    rest.thigh[side] = limbFrameAt(hip, knee);
    rest.shank[side] = limbFrameAt(knee, ankle);
    rest.foot[side] = {Eigen::Matrix3d::Identity(), ankle};
    rest_length_[limb(kUpperArm, side)] = (elbow - shoulder).norm();
    rest_length_[limb(kForearm, side)] = (wrist - elbow).norm();
    rest_length_[limb(kHand, side)] = (tip - wrist).norm();
    rest_length_[limb(kThigh, side)] = (knee - hip).norm();
    rest_length_[limb(kShank, side)] = (ankle - knee).norm();
    rest_length_[limb(kFoot, side)] = 1;
    a.upper_arm_length += 0.5 * rest_length_[limb(kUpperArm, side)];
    a.forearm_length += 0.5 * rest_length_[limb(kForearm, side)];
    a.hand_length += 0.5 * rest_length_[limb(kHand, side)];
    a.thigh_length += 0.5 * rest_length_[limb(kThigh, side)];
    a.shank_length += 0.5 * rest_length_[limb(kShank, side)];
    a.ankle_height += 0.5 * ankle.z();
    double heel = ankle.x(), toe = ankle.x();
    for (int i = 0; i < model.body_vertex_count; ++i) {
      const Eigen::Vector3f& p = mesh_.vertices[i];
      if (p.z() < 0.5 * ankle.z() && (p.y() > 0) == (side == 0)) {
        heel = std::min<double>(heel, p.x());
        toe = std::max<double>(toe, p.x());
      }
    }
    a.foot_length += 0.5 * (toe - heel);
  }

  // Each bone's segment: named in the map, else its parent's.
  std::vector<int> bone_segment(model.bones.size(), -1);
  for (int s = 0; s < kSegmentCount; ++s)
    for (const std::string& bone : map.segment_bones.at(kSegmentNames[s])) {
      const auto found = model.bone_index.find(bone);
      if (found == model.bone_index.end())
        throw std::runtime_error("mesh retarget map: segment '" + std::string(kSegmentNames[s]) +
                                 "' names an unknown bone '" + bone + "'");
      bone_segment[found->second] = s;
    }
  for (size_t b = 0; b < model.bones.size(); ++b) {
    int segment = bone_segment[b];
    for (const MeshHumanModel::Bone* bone = &model.bones[b];
         segment < 0 && !bone->parent.empty();) {
      bone = &model.bones[model.bone_index.at(bone->parent)];
      segment = bone_segment[model.bone_index.at(bone->name)];
    }
    if (segment < 0)
      throw std::runtime_error("mesh retarget map: bone '" + model.bones[b].name +
                               "' and its ancestors have no segment (map the root)");
    bone_segment[b] = segment;
  }
  // Per skin vertex: bone weights summed per segment, the 4 largest kept, renormalized.
  std::vector<std::array<float, kSegmentCount>> sums(model.body_vertex_count);
  for (auto& s : sums) s.fill(0.f);
  for (size_t b = 0; b < model.bones.size(); ++b)
    for (const auto& [vertex, weight] : model.bones[b].weights)
      sums[vertex][bone_segment[b]] += weight;
  influences_.resize(model.body_vertex_count);
  for (int v = 0; v < model.body_vertex_count; ++v) {
    std::array<int, kSegmentCount> order;
    for (int s = 0; s < kSegmentCount; ++s) order[s] = s;
    std::partial_sort(order.begin(), order.begin() + 4, order.end(),
                      [&](int x, int y) { return sums[v][x] > sums[v][y]; });
    float total = 0;
    for (int k = 0; k < 4; ++k) total += sums[v][order[k]] >= 1e-4f ? sums[v][order[k]] : 0.f;
    for (int k = 0; k < 4; ++k) {
      const float w = sums[v][order[k]] >= 1e-4f ? sums[v][order[k]] : 0.f;
      // An unweighted vertex follows the pelvis (the root's segment).
      influences_[v][k] = {static_cast<uint8_t>(total > 0 ? order[k] : kPelvis),
                           total > 0 ? w / total : (k == 0 ? 1.f : 0.f)};
    }
  }

  // Materials: a hair cap on the scalp and briefs over the pelvis (rest positions).
  triangles_ = skinTriangles(model);
  material_.assign(triangles_.size(), 0);
  triangle_segment_.assign(triangles_.size(), 0);
  double head_front = -1e9;
  for (int v = 0; v < model.body_vertex_count; ++v)
    if (mesh_.vertices[v].z() > head_top.z() - 0.12)
      head_front = std::max<double>(head_front, mesh_.vertices[v].x());
  const double hip_z = hip_mid.z();
  for (size_t t = 0; t < triangles_.size(); ++t) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    std::array<float, kSegmentCount> segment_weight{};
    for (const int v : triangles_[t]) {
      centre += mesh_.vertices[v].cast<double>() / 3;
      for (const Influence& influence : influences_[v])
        segment_weight[influence.segment] += influence.weight;
    }
    const int dominant = static_cast<int>(
        std::max_element(segment_weight.begin(), segment_weight.end()) - segment_weight.begin());
    triangle_segment_[t] = static_cast<uint8_t>(dominant);
    const double below_top = head_top.z() - centre.z();
    if (dominant == kNeck &&
        (below_top < 0.05 || (below_top < 0.13 && centre.x() < head_front - 0.10)))
      material_[t] = 1;
    const bool hips = dominant == kPelvis || dominant == kTorso || dominant == limb(kThigh, 0) ||
                      dominant == limb(kThigh, 1);
    if (hips && centre.z() > hip_z - 0.10 && centre.z() < hip_z + 0.09) material_[t] = 2;
  }
}

std::array<SegmentFrame, MeshHumanRig::kSegmentCount> MeshHumanRig::segmentFrames(
    const BodySegmentFrames& f) const {
  std::array<SegmentFrame, kSegmentCount> frames;
  frames[kPelvis] = f.pelvis;
  frames[kTorso] = f.torso;
  frames[kNeck] = f.neck;
  for (int side = 0; side < 2; ++side) {
    frames[limb(kUpperArm, side)] = f.upper_arm[side];
    frames[limb(kForearm, side)] = f.forearm[side];
    frames[limb(kHand, side)] = f.hand[side];
    frames[limb(kThigh, side)] = f.thigh[side];
    frames[limb(kShank, side)] = f.shank[side];
    frames[limb(kFoot, side)] = f.foot[side];
  }
  return frames;
}

std::array<Eigen::Matrix<double, 3, 4>, MeshHumanRig::kSegmentCount> MeshHumanRig::segmentMaps(
    const BodySegmentFrames& posed, const Anthropometry& b) const {
  const auto rest = segmentFrames(rest_frames_);
  const auto target = segmentFrames(posed);
  // Posed lengths along each segment (the measured sides' when the frames carry them).
  std::array<double, kSegmentCount> length{};
  length[kPelvis] = 1;
  length[kTorso] = b.torso_length;
  length[kNeck] = b.neck_length + b.head_height;
  for (int side = 0; side < 2; ++side) {
    const BodySegmentFrames::Lengths& measured = posed.side_lengths[side];
    auto pick = [](double m, double common) { return m > 0 ? m : common; };
    length[limb(kUpperArm, side)] = pick(measured.upper_arm, b.upper_arm_length);
    length[limb(kForearm, side)] = pick(measured.forearm, b.forearm_length);
    length[limb(kHand, side)] = pick(measured.hand, b.hand_length);
    length[limb(kThigh, side)] = pick(measured.thigh, b.thigh_length);
    length[limb(kShank, side)] = pick(measured.shank, b.shank_length);
    length[limb(kFoot, side)] = 1;
  }
  std::array<Eigen::Matrix<double, 3, 4>, kSegmentCount> maps;
  for (int s = 0; s < kSegmentCount; ++s) {
    // Rest frame -> posed frame, the bone stretched to its posed length. The trunk's y column
    // is the posed hip (shoulder) line over the rest one: both joints land on the posed ones
    // even where that line is not square to the frame's z (a tilted pelvis, a shrug).
    Eigen::Matrix3d columns = target[s].rotation;
    columns.col(2) *= length[s] / rest_length_[s];
    if (s == kPelvis)
      columns.col(1) = (posed.thigh[0].origin - posed.thigh[1].origin) / rest_width_[0];
    if (s == kTorso)
      columns.col(1) = (posed.upper_arm[0].origin - posed.upper_arm[1].origin) / rest_width_[1];
    const Eigen::Matrix3d linear = columns * rest[s].rotation.transpose();
    maps[s].leftCols<3>() = linear;
    maps[s].col(3) = target[s].origin - linear * rest[s].origin;
  }
  return maps;
}

std::vector<Eigen::Vector3f> MeshHumanRig::pose(const BodySegmentFrames& frames,
                                                const Anthropometry& lengths) const {
  const auto maps = segmentMaps(frames, lengths);
  std::array<Eigen::Matrix<float, 3, 4>, kSegmentCount> mapsf;
  for (int s = 0; s < kSegmentCount; ++s) mapsf[s] = maps[s].cast<float>();
  std::vector<Eigen::Vector3f> posed(influences_.size());
  for (size_t v = 0; v < posed.size(); ++v) {
    Eigen::Matrix<float, 3, 4> blend = influences_[v][0].weight * mapsf[influences_[v][0].segment];
    for (int k = 1; k < 4; ++k)
      if (influences_[v][k].weight > 0)
        blend += influences_[v][k].weight * mapsf[influences_[v][k].segment];
    posed[v] = blend.leftCols<3>() * mesh_.vertices[v] + blend.col(3);
  }
  return posed;
}

Eigen::Vector3d MeshHumanRig::posedMeshJoint(const std::string& joint, const std::string& segment,
                                             const BodySegmentFrames& frames,
                                             const Anthropometry& lengths) const {
  int s = 0;
  while (s < kSegmentCount && segment != kSegmentNames[s]) ++s;
  if (s == kSegmentCount) throw std::out_of_range("mesh human: no segment '" + segment + "'");
  const auto map = segmentMaps(frames, lengths)[s];
  return map.leftCols<3>() * mesh_.joints[model_.jointIndex(joint)] + map.col(3);
}

std::vector<SkeletonJoint> MeshHumanRig::skeleton(const BodySegmentFrames& frames,
                                                  const Anthropometry& lengths) const {
  HumanBodySpec spec;
  spec.body = lengths;
  spec.segment_frames = frames;
  std::vector<SkeletonJoint> joints = humanSkeleton(spec);
  // The far ends from the posed skin: the vertex and the toes.
  const auto maps = segmentMaps(frames, lengths);
  auto landmark = [&](int vertex) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (const Influence& influence : influences_[vertex])
      p += influence.weight *
           (maps[influence.segment].leftCols<3>() * mesh_.vertices[vertex].cast<double>() +
            maps[influence.segment].col(3));
    return p;
  };
  for (SkeletonJoint& joint : joints) {
    if (joint.name == "head_top") joint.position = landmark(head_top_vertex_);
    if (joint.name == "left_toe") joint.position = landmark(toe_vertex_[0]);
    if (joint.name == "right_toe") joint.position = landmark(toe_vertex_[1]);
  }
  return joints;
}

// ---------------------------------------------------------------------------------------------
std::shared_ptr<const MeshHumanRig> meshHumanRig(const MeshPersonSpec& person,
                                                 const MeshHumanFiles& files) {
  const MeshHumanModel& model = meshHumanModel(files.model);
  return std::make_shared<MeshHumanRig>(model, morphMesh(model, personMacros(model, person)),
                                        loadMeshRetargetMap(files.retarget_map));
}

void addMeshHuman(const MeshHumanRig& rig, const HumanBodySpec& body, Scene& scene) {
  HumanBodySpec spec = body;
  if (!spec.segment_frames) {
    spec.body = rig.anthropometry();
    spec.segment_frames = bodySegmentFrames(spec);
  }
  const std::vector<Eigen::Vector3f> posed = rig.pose(*spec.segment_frames, spec.body);
  auto mesh = std::make_unique<TriangleMesh>(
      posed, rig.triangles(),
      std::vector<Material>{spec.materials.skin, spec.materials.hair, spec.materials.clothing},
      rig.triangleMaterial());
  mesh->name = spec.name + "/skin";
  std::vector<std::string> segments;
  for (int s = 0; s < MeshHumanRig::kSegmentCount; ++s)
    segments.push_back(MeshHumanRig::segmentName(s));
  mesh->setParts(segments, rig.triangleSegment());
  scene.add(std::move(mesh));
  scene.addJoints(rig.skeleton(*spec.segment_frames, spec.body));
}

void addMeshHuman(const MeshHumanSpec& spec, const MeshHumanFiles& files, Scene& scene) {
  addMeshHuman(*meshHumanRig(spec.person, files), spec.body, scene);
}

MeshPersonSpec meshPersonFromYaml(const YAML::Node& node, const std::string& where) {
  MeshPersonSpec person;
  const std::pair<const char*, double MeshPersonSpec::*> keys[] = {
      {"stature", &MeshPersonSpec::stature}, {"gender", &MeshPersonSpec::gender},
      {"age", &MeshPersonSpec::age},         {"bmi", &MeshPersonSpec::bmi},
      {"muscle", &MeshPersonSpec::muscle},   {"african", &MeshPersonSpec::african},
      {"asian", &MeshPersonSpec::asian},     {"caucasian", &MeshPersonSpec::caucasian}};
  for (const auto& [key, field] : keys) {
    if (!node[key]) continue;
    try {
      person.*field = node[key].as<double>();
    } catch (const YAML::Exception&) {
      throw std::runtime_error(where + ": '" + key + "' must be a number");
    }
  }
  return person;
}

void addMeshHumanFromYaml(const YAML::Node& object, const std::string& where,
                          const std::string& base_dir, Scene& scene) {
  requireKnownKeys(object, {"type",      "name",        "stature",   "gender",    "age",
                            "bmi",       "muscle",      "african",   "asian",     "caucasian",
                            "position",  "heading_deg", "pose",      "materials", "bvh",
                            "joint_map", "frame",       "gait_pose", "model",     "retarget_map"},
                   where);
  auto file = [&](const char* key, const char* fallback) {
    const std::filesystem::path path = object[key] ? object[key].as<std::string>() : fallback;
    return (path.is_relative() && !base_dir.empty() ? std::filesystem::path(base_dir) / path : path)
        .string();
  };
  const MeshHumanFiles files{file("model", "../../data/mesh_human/mesh_human.bin"),
                             file("retarget_map", "../mesh/mesh_retarget.yaml")};
  MeshPersonSpec person = meshPersonFromYaml(object, where);
  try {
    std::shared_ptr<const MeshHumanRig> rig;
    HumanBodySpec body;
    if (object["bvh"]) {
      if (object["pose"]) throw std::runtime_error("give 'pose' or 'bvh', not both");
      YAML::Node bvh(YAML::NodeType::Map);
      for (const char* key : {"name", "bvh", "joint_map", "frame", "gait_pose", "position",
                              "heading_deg", "materials"})
        if (object[key]) bvh[key] = object[key];
      // The walker's stature from its legs unless the scene gives one.
      body = bvhHumanFromYaml(bvh, where, base_dir, [&](double estimated_stature) {
        if (!object["stature"]) person.stature = estimated_stature;
        rig = meshHumanRig(person, files);
        return rig->anthropometry();
      });
    } else {
      YAML::Node human(YAML::NodeType::Map);
      for (const char* key : {"name", "position", "heading_deg", "pose", "materials"})
        if (object[key]) human[key] = object[key];
      body = humanBodyFromYaml(human);
      rig = meshHumanRig(person, files);
    }
    addMeshHuman(*rig, body, scene);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(where + ": " + e.what());
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    throw std::runtime_error(message.rfind(where, 0) == 0 ? message : where + ": " + message);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(where + ": " + e.what());
  }
}

}  // namespace body_scan_driver::sim
