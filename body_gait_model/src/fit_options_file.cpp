#include <body_gait_model/fit_options_file.h>
#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <stdexcept>

namespace body_gait_model {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180;

// Reads the keys of one map into their fields; an unknown key is an error.
class Section {
 public:
  Section(const std::string& path, std::string name) : path_(path), name_(std::move(name)) {}

  template <typename T>
  Section& field(const std::string& key, T& value) {
    readers_[key] = [this, key, &value](const YAML::Node& node) {
      try {
        value = node.as<T>();
      } catch (const YAML::Exception&) {
        throw std::runtime_error(path_ + ": '" + name_ + key + "' has value '" + YAML::Dump(node) +
                                 "' of the wrong type; fix it in the file");
      }
    };
    return *this;
  }
  Section& section(const std::string& key, const std::function<void(const YAML::Node&)>& read) {
    readers_[key] = read;
    return *this;
  }

  void read(const YAML::Node& node) const {
    if (!node || node.IsNull()) return;
    if (!node.IsMap())
      throw std::runtime_error(path_ + ": '" + (name_.empty() ? "the document" : name_) +
                               "' must be a map of FitOptions keys");
    for (const auto& entry : node) {
      const std::string key = entry.first.as<std::string>();
      const auto reader = readers_.find(key);
      if (reader == readers_.end()) {
        std::string known;
        for (const auto& [name, unused] : readers_) known += (known.empty() ? "" : ", ") + name;
        throw std::runtime_error(path_ + ": unknown key '" + name_ + key +
                                 "'; known keys here: " + known);
      }
      reader->second(entry.second);
    }
  }

 private:
  std::string path_, name_;
  std::map<std::string, std::function<void(const YAML::Node&)>> readers_;
};

}  // namespace

FitOptions loadFitOptions(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(
        "cannot read fit options '" + path + "': " + e.what() +
        "; pass an existing YAML file (body_gait_model/config/body_fitter.yaml)");
  }
  FitOptions options;
  Section axes(path, "axes.");
  axes.field("shoulder_band_low", options.axes.shoulder_band_low)
      .field("shoulder_band_high", options.axes.shoulder_band_high)
      .field("shoulder_width", options.axes.shoulder_width)
      .field("shoulder_top", options.axes.shoulder_top)
      .field("vertical_from_floor", options.axes.vertical_from_floor)
      .field("foot_band", options.axes.foot_band)
      .field("foot_radius", options.axes.foot_radius)
      .field("shank_band_low", options.axes.shank_band_low)
      .field("shank_band_high", options.axes.shank_band_high);
  Section torso(path, "torso.");
  torso.field("sectors", options.torso.sectors)
      .field("delta_ut", options.torso.delta_ut)
      .field("max_top_above_shoulders", options.torso.max_top_above_shoulders)
      .field("delta_lt", options.torso.delta_lt)
      .field("slice_step", options.torso.slice_step)
      .field("min_base_height", options.torso.min_base_height);
  Section quality(path, "quality.");
  quality.field("explained_distance", options.quality.explained_distance)
      .field("min_explained_fraction", options.quality.min_explained_fraction)
      .field("max_rms", options.quality.max_rms)
      .field("min_points_per_limb_segment", options.quality.min_points_per_limb_segment)
      .field("max_leg_share_deviation", options.quality.max_leg_share_deviation)
      .field("max_arm_share_deviation", options.quality.max_arm_share_deviation)
      .field("max_points", options.quality.max_points);
  Section refinement(path, "refinement.");
  refinement.field("sample_points", options.refinement.sample_points)
      .field("rounds", options.refinement.rounds)
      .field("max_iterations", options.refinement.max_iterations)
      .field("huber_scale", options.refinement.huber_scale)
      .field("min_length", options.refinement.min_length)
      .field("max_length_change", options.refinement.max_length_change)
      .field("hold_thighs_in_walks", options.refinement.hold_thighs_in_walks);
  Section limits(path, "joint_limits.");
  // Each joint kind: the segments it bounds (both sides alike) and its range in degrees.
  const std::pair<const char*, std::vector<int>> kJointKinds[] = {
      {"upper_torso", {kUpperTorso}},
      {"head", {kHead}},
      {"lower_torso", {kLowerTorso}},
      {"upper_arm", {kRightUpperArm, kLeftUpperArm}},
      {"lower_arm", {kRightLowerArm, kLeftLowerArm}},
      {"upper_leg", {kRightUpperLeg, kLeftUpperLeg}},
      {"lower_leg", {kRightLowerLeg, kLeftLowerLeg}}};
  for (const auto& [kind, segments] : kJointKinds) {
    const std::string name = kind;
    const std::vector<int> bounded = segments;
    limits.section(name, [&, name, bounded](const YAML::Node& node) {
      auto range = [&](const char* axis) {
        const YAML::Node pair = node.IsMap() ? node[axis] : YAML::Node();
        if (!pair || !pair.IsSequence() || pair.size() != 2 ||
            !(pair[0].as<double>() <= pair[1].as<double>()))
          throw std::runtime_error(path + ": 'joint_limits." + name + "' needs " + axis +
                                   ": [min, max] in degrees with min <= max, e.g. {x: [-10, "
                                   "80], z: [-10, 10]}; fix it in the file");
        return std::pair{pair[0].as<double>() * kDegree, pair[1].as<double>() * kDegree};
      };
      const auto [x_min, x_max] = range("x");
      const auto [z_min, z_max] = range("z");
      for (int segment : bounded) options.joint_limits[segment] = {x_min, x_max, z_min, z_max};
    });
  }
  Section top(path, "");
  top.section("axes", [&](const YAML::Node& n) { axes.read(n); })
      .section("torso", [&](const YAML::Node& n) { torso.read(n); })
      .section("quality", [&](const YAML::Node& n) { quality.read(n); })
      .section("refinement", [&](const YAML::Node& n) { refinement.read(n); })
      .section("joint_limits",
               [&](const YAML::Node& n) {
                 if (n.IsScalar() && n.as<std::string>() == "thesis")
                   options.joint_limits = thesisJointLimits();
                 else if (n.IsScalar() && n.as<std::string>() == "walking")
                   options.joint_limits = walkingJointLimits();
                 else if (n.IsScalar())
                   throw std::runtime_error(path + ": 'joint_limits' is '" + n.as<std::string>() +
                                            "'; use walking, thesis or a map of joint ranges");
                 else
                   limits.read(n);
               })
      .field("refine", options.refine)
      .field("foot_height", options.foot_height)
      .field("arm_split_window", options.arm_split_window)
      .field("leg_split_window", options.leg_split_window)
      .field("limb_track_radius", options.limb_track_radius)
      .field("hip_height", options.hip_height)
      .field("hip_depth_fraction", options.hip_depth_fraction)
      .field("shoulder_depth", options.shoulder_depth)
      .field("max_fit_points", options.max_fit_points);
  top.read(root);
  // Proportions outside the body: every fit would place these joints off the person.
  if (!(options.hip_height > 0 && options.hip_height < 1))
    throw std::runtime_error(path + ": 'hip_height' is " + std::to_string(options.hip_height) +
                             "; it is a fraction of the body height: use 0 < hip_height < 1 "
                             "(0.53 by default)");
  if (!(options.hip_depth_fraction > 0 && options.hip_depth_fraction < 1))
    throw std::runtime_error(path + ": 'hip_depth_fraction' is " +
                             std::to_string(options.hip_depth_fraction) +
                             "; it is a fraction of the body's depth from the back: use 0 < "
                             "hip_depth_fraction < 1 (0.40 by default)");
  if (!(options.shoulder_depth >= 0 && options.shoulder_depth <= 4))
    throw std::runtime_error(path + ": 'shoulder_depth' is " +
                             std::to_string(options.shoulder_depth) +
                             "; it counts arm radii below the shoulder's top: use 0 .. 4 (2 by "
                             "default)");
  return options;
}

}  // namespace body_gait_model
