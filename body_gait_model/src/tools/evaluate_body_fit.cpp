// Evaluation CLI: fits simulated subjects in the four gait poses of 5.3 and compares each fit
// with the simulator's true skeleton, printing one line per fit and a summary, and writing a
// YAML report. Only this tool (and the tests) read ground truth; the fitter does not.
//
//   evaluate_body_fit [--subjects N] [--columns C] [--noise SIGMA_M] [--min-albedo A]
//                     [--missing-viewpoints i,j,...] [--abduction-deg D] [--direct 1]
//                     [--test-headings 1] [--per-joint 1] [--full-scanner 1]
//                     [--missing-pairs pole_c/pair_2,...] [--only SUBJECT]
//                     [--clouds DIR] [--rig RIG.yaml] [--dark-albedo A] [--people N]
//                     [--lean-deg D]
//                     [--out report.yaml]
//
// After the summary: per joint the mean error and mean offset (fitted - true) in the true body
// frame (forward, left, up), per limb segment the mean absolute and signed length error.
// --direct 1 skips the refinement; --test-headings 1 uses test_body_fitter's headings;
// --per-joint 1 prints every fit's joint and segment errors. --full-scanner 1 scans each subject
// with the simulated full scanner (the thesis rig's 12 pairs, as test_full_scanner_fit; headings
// within +-46 deg of the rig's front) instead of the ray-cast sampler (--columns, --noise,
// --min-albedo and --missing-viewpoints are the sampler's); --missing-pairs leaves pairs out;
// --rig scans with another rig file than the thesis rig; --dark-albedo sets the albedo of the
// hair and the trunks (default 0.15; below ~0.05 the full scanner decodes little of them).
// --only runs one subject (e.g. subject_9); --clouds writes every case's cloud to
// DIR/<subject>_pose<k>.ply (world frame) for a look in rviz or a viewer. --people N fits
// simulatedPeople(N) (eval/gait_subjects.h: survey-drawn bodies, personal gait styles; walk 0)
// instead of simulatedSubjects. --lean-deg D sets every simulated body's forward torso lean
// (simulatedSubjects stand upright, simulatedPeople lean by their style, ~3 +- 2 deg).
//
// Motion-capture subjects (issue 7): --bvh [PERSON=]WALK.bvh,... replaces the simulated subjects
// by real walks: in each walk the 4 poses of 5.3 are picked (body_scan_driver's pickGaitPoses),
// the body is posed on those BVH frames and scanned with the full scanner; errors are against the
// BVH joints. PERSON defaults to the file name up to its first '_' (CMU: 07_02.bvh -> 07).
// --bvh-map sets the joint map (default: body_scan_driver/config/bvh/cmu_joint_map.yaml);
// --models DIR writes each walk's 4 fitted models to DIR/<walk>.yaml (body_gait_id's models
// file: poses s1..s4 with p, q, r and shape, plus person, walk and frame) for the recognizer
// (body_gait_id's identify_walks); --picture FILE.png draws every case's cloud from the side with
// the fitted joints (red) and the true ones (green), side by side.
#include <body_gait_model/body_fitter.h>
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <body_gait_model/eval/full_scanner_body.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/gait_poses_file.h>
#include <body_scan_driver/atomic_file.h>
#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_merge/ply_writer.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void usage(const std::string& problem) {
  std::fprintf(
      stderr,
      "evaluate_body_fit: %s\nusage: evaluate_body_fit [--subjects N (>= 1)] [--columns "
      "C (ray grid per viewpoint, >= 20)] [--noise SIGMA_M] [--min-albedo A] "
      "[--missing-viewpoints i,j] [--abduction-deg D] [--direct 1] [--test-headings 1] "
      "[--per-joint 1] [--full-scanner 1] [--missing-pairs id,id] [--only SUBJECT] "
      "[--clouds DIR] [--rig RIG.yaml] [--people N] [--lean-deg D] [--bvh [PERSON=]WALK.bvh,...] "
      "[--bvh-map MAP.yaml] "
      "[--models DIR] [--out report.yaml]\n",
      problem.c_str());
  std::exit(2);
}

double number(const char* text, const std::string& flag) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0') usage(flag + " needs a number, got '" + text + "'");
  return value;
}

// One scan to fit: a body, its gait pose (1..4) and, for motion capture, where it came from.
struct Case {
  body_scan_driver::sim::HumanBodySpec spec;
  int pose = 0;
  int frame = -1;  // 0-based BVH frame; -1 = a simulated pose
  std::string person, walk;
};

// The 4 poses of every walk, posed on the BVH frames the picker chose (prints them).
std::vector<Case> bvhCases(const std::vector<std::string>& items, const std::string& map_path) {
  namespace sim = body_scan_driver::sim;
  const sim::BvhJointMap map = sim::loadBvhJointMap(map_path);
  std::vector<Case> cases;
  for (const std::string& item : items) {
    const auto [person, walk, file] = sim::parseBvhWalkFile(item);
    const sim::BvhSubject subject(sim::loadBvh(file), map, walk);
    const sim::GaitPoseFrames poses = sim::pickGaitPoses(subject);
    std::printf("%s (person %s): poses 1-4 at frames %d %d %d %d (1-based), %.2f m/s\n",
                walk.c_str(), person.c_str(), poses.frame[0] + 1, poses.frame[1] + 1,
                poses.frame[2] + 1, poses.frame[3] + 1, poses.walking_speed);
    for (int pose = 1; pose <= 4; ++pose) {
      Case c;
      c.spec = subject.body(poses.frame[pose - 1]);
      c.pose = pose;
      c.frame = poses.frame[pose - 1];
      c.person = person;
      c.walk = walk;
      cases.push_back(c);
    }
  }
  return cases;
}

// One panel of --picture: the cloud seen from the subject's left (x forward = right, z up),
// shaded by depth, with the fitted (red) and true (green) joints and the limb segments.
cv::Mat sidePanel(const std::vector<Eigen::Vector3d>& points,
                  const body_gait_model::PosedModel& fitted,
                  const std::vector<body_scan_driver::sim::SkeletonJoint>& truth,
                  const std::string& title) {
  constexpr int kWidth = 420, kHeight = 760;
  constexpr double kPixelsPerMetre = 360, kMinX = -0.55, kTopZ = 2.0;
  cv::Mat panel(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  auto pixel = [&](const Eigen::Vector3d& p) {
    return cv::Point(int((p.x() - kMinX) * kPixelsPerMetre),
                     int((kTopZ - p.z()) * kPixelsPerMetre));
  };
  // Far points first so the near side (the subject's left, +y) is drawn on top.
  std::vector<const Eigen::Vector3d*> order;
  for (const Eigen::Vector3d& p : points)
    if (p.z() > 0.01) order.push_back(&p);
  std::sort(order.begin(), order.end(), [](auto a, auto b) { return a->y() < b->y(); });
  for (const Eigen::Vector3d* p : order) {
    const cv::Point at = pixel(*p);
    if (at.x < 0 || at.y < 0 || at.x >= kWidth || at.y >= kHeight) continue;
    const int shade = std::clamp(int(150 - 300 * p->y()), 40, 230);
    panel.at<cv::Vec3b>(at) = cv::Vec3b(shade, shade, shade);
  }
  const char* const kBones[][2] = {
      {"left_shoulder", "left_elbow"},   {"left_elbow", "left_hand_tip"},
      {"left_hip", "left_knee"},         {"left_knee", "left_ankle"},
      {"right_shoulder", "right_elbow"}, {"right_elbow", "right_hand_tip"},
      {"right_hip", "right_knee"},       {"right_knee", "right_ankle"}};
  auto trueJoint = [&](const std::string& name) {
    for (const auto& joint : truth)
      if (joint.name == name) return joint.position;
    return Eigen::Vector3d(Eigen::Vector3d::Constant(NAN));
  };
  for (const auto& bone : kBones) {
    cv::line(panel, pixel(trueJoint(bone[0])), pixel(trueJoint(bone[1])), cv::Scalar(0, 160, 0), 2);
    const std::string far_end =
        std::string(bone[1]).find("ankle") != std::string::npos
            ? std::string(bone[1]).replace(std::string(bone[1]).find("ankle"), 5, "sole")
            : std::string(bone[1]);
    cv::line(panel, pixel(fitted.joint(bone[0])), pixel(fitted.joint(far_end)),
             cv::Scalar(0, 0, 220), 2);
  }
  cv::putText(panel, title, cv::Point(10, 25), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0),
              1, cv::LINE_AA);
  return panel;
}

}  // namespace

int main(int argc, char** argv) {
  int subjects = 10;
  int people = 0;  // > 0: simulatedPeople instead of simulatedSubjects
  std::string out;
  double abduction_deg = -1;
  double lean_deg = -100;  // > -90: every simulated body's forward torso lean (deg)
  bool test_headings = false, per_joint = false, full_scanner = false;
  body_gait_model::eval::FullScannerOptions scanner;
  std::string only, clouds, models_out, picture;
  std::vector<cv::Mat> panels;
  std::string bvh_map = BODY_SCAN_DRIVER_CONFIG_DIR "/bvh/cmu_joint_map.yaml";
  std::vector<std::string> bvh_files;
  double dark_albedo = -1;
  body_gait_model::FitOptions options;
  body_gait_model::eval::ScanRig rig;
  rig.noise_sigma = 0.002;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) usage("missing value after " + flag);
    const char* value = argv[++i];
    if (flag == "--subjects") {
      subjects = int(number(value, flag));
    } else if (flag == "--people") {
      people = int(number(value, flag));
      if (people < 1) usage("--people must be >= 1");
    } else if (flag == "--columns") {
      rig.columns = int(number(value, flag));
      rig.rows = rig.columns * 13 / 16;
    } else if (flag == "--noise") {
      rig.noise_sigma = number(value, flag);
    } else if (flag == "--min-albedo") {
      rig.min_albedo = number(value, flag);
    } else if (flag == "--missing-viewpoints") {
      std::stringstream list(value);
      std::string item;
      while (std::getline(list, item, ',')) rig.missing_viewpoints.push_back(std::stoi(item));
    } else if (flag == "--abduction-deg") {
      abduction_deg = number(value, flag);
    } else if (flag == "--lean-deg") {
      lean_deg = number(value, flag);
      if (!(lean_deg > -90 && lean_deg < 90)) usage("--lean-deg must be within (-90, 90)");
    } else if (flag == "--direct") {
      options.refine = number(value, flag) == 0;
    } else if (flag == "--per-joint") {
      per_joint = number(value, flag) != 0;
    } else if (flag == "--test-headings") {
      test_headings = number(value, flag) != 0;
    } else if (flag == "--full-scanner") {
      full_scanner = number(value, flag) != 0;
    } else if (flag == "--missing-pairs") {
      std::stringstream list(value);
      for (std::string id; std::getline(list, id, ',');) scanner.missing_pairs.push_back(id);
    } else if (flag == "--dark-albedo") {
      dark_albedo = number(value, flag);
    } else if (flag == "--rig") {
      scanner.rig_file = value;
    } else if (flag == "--only") {
      only = value;
    } else if (flag == "--clouds") {
      clouds = value;
    } else if (flag == "--bvh") {
      std::stringstream list(value);
      for (std::string file; std::getline(list, file, ',');) bvh_files.push_back(file);
    } else if (flag == "--bvh-map") {
      bvh_map = value;
    } else if (flag == "--picture") {
      picture = value;
    } else if (flag == "--models") {
      models_out = value;
    } else if (flag == "--out") {
      out = value;
    } else {
      usage("unknown option " + flag);
    }
  }
  if (subjects < 1 || rig.columns < 20) usage("--subjects must be >= 1 and --columns >= 20");
  // Simulated bodies: simulatedSubjects (the fit figures' subjects) or simulatedPeople.
  std::vector<body_scan_driver::sim::HumanBodySpec> bodies;
  std::vector<body_gait_model::eval::SimulatedPerson> persons;
  if (people > 0) {
    persons = body_gait_model::eval::simulatedPeople(people);
    for (const auto& person : persons) {
      bodies.emplace_back();
      bodies.back().name = person.name;
    }
    subjects = people;
  } else {
    bodies = body_gait_model::eval::simulatedSubjects(subjects);
  }
  if (!only.empty() && bvh_files.empty()) {
    bool known = false;
    for (const auto& body : bodies) known = known || body.name == only;
    if (!known)
      usage("--only " + only + ": no such subject among " + bodies.front().name + " .. " +
            bodies.back().name);
  }

  // The cases: simulated subjects x the 4 poses, or the 4 picked poses of every BVH walk.
  std::vector<Case> all_cases;
  if (!bvh_files.empty()) {
    full_scanner = true;  // real motion is judged on the product's clouds
    try {
      all_cases = bvhCases(bvh_files, bvh_map);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "evaluate_body_fit: %s\n", error.what());
      return 1;
    }
    subjects = int(bvh_files.size());
  } else {
    int index = 0;
    for (size_t k = 0; k < bodies.size(); ++k) {
      for (int pose = 1; pose <= 4; ++pose, ++index) {
        Case c;
        c.pose = pose;
        const double heading = full_scanner ? body_gait_model::eval::fullScannerHeading(index)
                                            : 0.3 + 1.7 * (test_headings ? pose : pose + index);
        if (people > 0) {
          c.spec = body_gait_model::eval::walkingSubject(persons[k], pose, 0, heading);
        } else {
          c.spec = bodies[k];
          c.spec.pose = body_gait_model::eval::gaitPose(pose, heading);
        }
        if (abduction_deg >= 0)
          c.spec.pose.left_shoulder_abduction = c.spec.pose.right_shoulder_abduction =
              abduction_deg * kPi / 180;
        if (lean_deg > -90) c.spec.pose.torso_lean = lean_deg * kPi / 180;
        all_cases.push_back(c);
      }
    }
  }

  std::ostringstream yaml;
  std::map<std::string, YAML::Node> walk_models;  // walk -> its models file
  yaml << "cases:\n";
  double joint = 0, length = 0, swing = 0, seconds = 0, points = 0;
  int cases = 0, right = 0, low_quality = 0;
  struct JointStats {
    double error = 0;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  };
  std::map<std::string, JointStats> joint_stats;
  std::map<std::string, std::pair<double, double>> segment_stats;  // |error|, signed error
  for (const Case& each : all_cases) {
    if (!only.empty() && each.spec.name != only) continue;
    auto spec = each.spec;
    const int pose = each.pose;
    if (dark_albedo >= 0) spec.materials.hair.albedo = spec.materials.clothing.albedo = dark_albedo;
    body_gait_model::eval::SampledBody body;
    try {
      body = full_scanner ? body_gait_model::eval::scanBodyWithFullScanner(spec, scanner)
                          : body_gait_model::eval::sampleBody(spec, rig);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "evaluate_body_fit: %s\n", error.what());
      return 1;
    }
    if (!clouds.empty()) {
      std::vector<float> xyz;
      for (const Eigen::Vector3d& p : body.points)
        xyz.insert(xyz.end(), {float(p.x()), float(p.y()), float(p.z())});
      const std::string path = clouds + "/" + spec.name + "_pose" + std::to_string(pose) + ".ply";
      try {
        body_scan_merge::writePly(path, xyz.data(), body.points.size(), 3, -1);
      } catch (const std::exception& error) {
        std::fprintf(stderr, "evaluate_body_fit: %s\n", error.what());
        return 1;
      }
    }
    const auto start = std::chrono::steady_clock::now();
    const body_gait_model::BodyFit fit = body_gait_model::fitBody(body.points, options);
    const double fit_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto errors = body_gait_model::eval::compareWithTruth(fit.model, body);
    if (!picture.empty()) {
      std::ostringstream title;
      title << spec.name << " pose " << pose;
      if (each.frame >= 0) title << " (frame " << each.frame + 1 << ")";
      title << ": " << std::lround(1000 * errors.mean_joint_error) << " mm";
      panels.push_back(sidePanel(body.points, body_gait_model::forwardKinematics(fit.model),
                                 body.skeleton, title.str()));
    }
    const bool heading_right = errors.front_right && errors.left_right;
    std::printf(
        "%s pose %d: %zu points, joint %.1f mm, length %.1f %%, swing %.2f deg, "
        "front/left %s, RMS %.1f mm, explained %.0f %%%s, %.0f ms\n",
        (spec.name + (each.frame >= 0 ? " frame " + std::to_string(each.frame + 1) : "")).c_str(),
        pose, body.points.size(), 1000 * errors.mean_joint_error, 100 * errors.mean_length_error,
        errors.mean_swing_error * 180 / kPi, heading_right ? "right" : "WRONG",
        1000 * fit.quality.rms_distance, 100 * fit.quality.explained_fraction,
        fit.quality.low_quality ? ", LOW QUALITY" : "", 1000 * fit_seconds);
    yaml << "  - {subject: " << spec.name << ", pose: " << pose
         << ", points: " << body.points.size() << ", joint_error_m: " << errors.mean_joint_error
         << ", length_error: " << errors.mean_length_error
         << ", swing_error_rad: " << errors.mean_swing_error
         << ", heading_right: " << (heading_right ? "true" : "false")
         << ", rms_m: " << fit.quality.rms_distance
         << ", explained: " << fit.quality.explained_fraction
         << ", low_quality: " << (fit.quality.low_quality ? "true" : "false")
         << ", fit_seconds: " << fit_seconds;
    if (each.frame >= 0) yaml << ", person: '" << each.person << "', frame: " << each.frame + 1;
    yaml << "}\n";
    if (each.frame >= 0) {
      YAML::Node& file = walk_models[each.walk];
      if (!file["walk"]) {
        file["person"] = each.person;
        file["walk"] = each.walk;
      }
      YAML::Node pose_node = body_gait_model::bodyModelToYaml(fit.model);
      pose_node["frame"] = each.frame + 1;
      pose_node["low_quality"] = fit.quality.low_quality;
      file["poses"].push_back(pose_node);
    }
    if (per_joint) {
      for (const auto& [name, error] : errors.joint_error)
        std::printf("    %-15s %6.1f mm (%+6.1f %+6.1f %+6.1f)\n", name.c_str(), 1000 * error,
                    1000 * errors.joint_offset.at(name).x(),
                    1000 * errors.joint_offset.at(name).y(),
                    1000 * errors.joint_offset.at(name).z());
      for (const auto& [name, bias] : errors.segment_length_bias)
        std::printf("    %-15s %+6.1f %%\n", name.c_str(), 100 * bias);
    }
    for (const auto& [name, error] : errors.joint_error) {
      joint_stats[name].error += error;
      joint_stats[name].offset += errors.joint_offset.at(name);
    }
    for (const auto& [name, bias] : errors.segment_length_bias) {
      segment_stats[name].first += std::abs(bias);
      segment_stats[name].second += bias;
    }
    joint += errors.mean_joint_error;
    length += errors.mean_length_error;
    swing += errors.mean_swing_error;
    seconds += fit_seconds;
    points += double(body.points.size());
    right += heading_right;
    low_quality += fit.quality.low_quality;
    ++cases;
  }
  std::printf(
      "SUMMARY %d fits (%d subjects or walks x 4 poses, mean %.0f points): mean joint-centre error "
      "%.1f mm, segment-length error %.1f %%, swing-angle error %.2f deg, front/left right "
      "%d/%d, low quality %d, %.0f ms per fit\n",
      cases, subjects, points / cases, 1000 * joint / cases, 100 * length / cases,
      swing / cases * 180 / kPi, right, cases, low_quality, 1000 * seconds / cases);
  std::printf("%-16s %9s %28s\n", "joint", "error mm", "offset fwd/left/up mm");
  for (const auto& [name, stats] : joint_stats)
    std::printf("%-16s %9.1f %9.1f %8.1f %8.1f\n", name.c_str(), 1000 * stats.error / cases,
                1000 * stats.offset.x() / cases, 1000 * stats.offset.y() / cases,
                1000 * stats.offset.z() / cases);
  std::printf("%-16s %9s %9s\n", "segment", "|error| %", "signed %");
  for (const auto& [name, stats] : segment_stats)
    std::printf("%-16s %9.1f %9.1f\n", name.c_str(), 100 * stats.first / cases,
                100 * stats.second / cases);
  yaml << "joints:\n";
  for (const auto& [name, stats] : joint_stats)
    yaml << "  " << name << ": {error_m: " << stats.error / cases << ", offset_forward_left_up_m: ["
         << stats.offset.x() / cases << ", " << stats.offset.y() / cases << ", "
         << stats.offset.z() / cases << "]}\n";
  yaml << "segments:\n";
  for (const auto& [name, stats] : segment_stats)
    yaml << "  " << name << ": {length_error: " << stats.first / cases
         << ", signed_length_error: " << stats.second / cases << "}\n";
  yaml << "summary: {fits: " << cases << ", mean_points: " << points / cases
       << ", mean_joint_error_m: " << joint / cases << ", mean_length_error: " << length / cases
       << ", mean_swing_error_rad: " << swing / cases << ", heading_right: " << right
       << ", low_quality: " << low_quality << ", mean_fit_seconds: " << seconds / cases << "}\n";
  if (!picture.empty() && !panels.empty()) {
    cv::Mat row;
    cv::hconcat(panels, row);
    if (!cv::imwrite(picture, row)) {
      std::fprintf(stderr, "evaluate_body_fit: cannot write the picture '%s'\n", picture.c_str());
      return 1;
    }
  }
  if (!models_out.empty()) {
    try {
      std::filesystem::create_directories(models_out);
      for (const auto& [walk, node] : walk_models) {
        YAML::Emitter text;
        text.SetDoublePrecision(17);
        text << node;
        body_scan_driver::writeFileAtomically(
            models_out + "/" + walk + ".yaml",
            "# Fitted body models of walk " + walk +
                " (evaluate_body_fit --bvh --models): the 4 poses of\n# thesis 5.3 in order "
                "s1..s4 (body_gait_model/gait_poses_file.h, with the frame and fit quality).\n" +
                text.c_str() + "\n");
      }
    } catch (const std::exception& error) {
      std::fprintf(stderr, "evaluate_body_fit: %s\n", error.what());
      return 1;
    }
  }
  if (!out.empty()) {
    try {
      body_scan_driver::writeFileAtomically(out, yaml.str());
    } catch (const std::exception& error) {
      std::fprintf(stderr, "evaluate_body_fit: %s\n", error.what());
      return 1;
    }
  }
  return 0;
}
