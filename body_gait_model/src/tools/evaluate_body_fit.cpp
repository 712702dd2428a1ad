// Evaluation CLI: fits simulated subjects in the four gait poses of 5.3 and compares each fit
// with the simulator's true skeleton, printing one line per fit and a summary, and writing a
// YAML report. Only this tool (and the tests) read ground truth; the fitter does not.
//
//   evaluate_body_fit [--subjects N] [--columns C] [--noise SIGMA_M] [--min-albedo A]
//                     [--missing-viewpoints i,j,...] [--abduction-deg D] [--direct]
//                     [--test-headings] [--per-joint] [--full-scanner]
//                     [--missing-pairs pole_c/pair_2,...] [--only SUBJECT]
//                     [--clouds DIR] [--clouds-from DIR] [--rig RIG.yaml] [--dark-albedo A]
//                     [--people N]
//                     [--lean-deg D] [--fit scan|walk] [--joint-limits walking|thesis]
//                     [--body ellipsoid|mesh]
//                     [--out report.yaml]        (all options: evaluate_body_fit --help)
//
// After the summary: per joint the mean error and mean offset (fitted - true) in the true body
// frame (forward, left, up), per limb segment the mean absolute and signed length error.
// --direct skips the refinement; --test-headings uses test_body_fitter's headings;
// --per-joint prints every fit's joint and segment errors. --full-scanner scans each subject
// with the simulated full scanner (the thesis rig's 12 pairs, as test_full_scanner_fit; headings
// within +-46 deg of the rig's front) instead of the ray-cast sampler (--columns, --noise,
// --min-albedo and --missing-viewpoints are the sampler's); --missing-pairs leaves pairs out;
// --rig scans with another rig file than the thesis rig; --dark-albedo sets the albedo of the
// hair and the trunks (default 0.15; below ~0.05 the full scanner decodes little of them).
// --only runs one subject (e.g. subject_9); --clouds writes every case's cloud to
// DIR/<subject>_pose<k>.ply (world frame) for a look in rviz or a viewer; --clouds-from DIR fits
// those files again instead of scanning (the same cases and scanner options). --people N fits
// simulatedPeople(N) (eval/gait_subjects.h: survey-drawn bodies, personal gait styles; walk 0)
// instead of simulatedSubjects. --lean-deg D sets every simulated body's forward torso lean
// (simulatedSubjects stand upright, simulatedPeople lean by their style, ~3 +- 2 deg).
// --fit walk fits each subject's or walk's 4 poses together (fitWalk: one body, a pose per
// scan); --fit scan (default) each scan alone. --joint-limits thesis uses Table 5.2's bounds
// instead of the walking ranges. The summary adds per-walk and per-pose lines, the
// Procrustes-aligned joint error, the joint error with each joint's mean offset (learned on the
// other people) removed, the fits reaching a joint limit and the low-quality flag's precision and
// recall for "mean joint error > 50 mm".
// --body mesh dresses every subject (and BVH walker) with the skinned mesh human
// (body_scan_driver/sim/mesh_human.h: a person of the subject's stature, sex and build) instead of
// the ellipsoids; the truth is the mesh's skeleton.
//
// Motion-capture subjects: --bvh [PERSON=]WALK.bvh,... replaces the simulated subjects
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
#include <body_scan_driver/sim/scene.h>
#include <body_scan_driver/tools/command_line.h>
#include <body_scan_driver/tools/package_file.h>
#include <body_scan_merge/ply_writer.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>
#include <string>

namespace {

constexpr double kPi = 3.14159265358979323846;

// The command line (see --help).
struct Settings {
  int subjects = 10;
  int people = 0;  // > 0: simulatedPeople instead of simulatedSubjects
  std::string out, only, clouds, clouds_from, models_out, picture, bvh_map;
  double abduction_deg = -1;
  double lean_deg = -100;  // > -90: every simulated body's forward torso lean (deg)
  double dark_albedo = -1;
  bool test_headings = false, per_joint = false, full_scanner = false;
  bool walk_fit = false;  // --fit walk: the 4 poses of each subject or walk fitted together
  std::vector<std::string> bvh_files;
  body_gait_model::eval::FullScannerOptions scanner;
  body_gait_model::FitOptions options;
  body_gait_model::eval::ScanRig rig;
};

// Returns the exit status when the tool should stop (--help, a usage error).
std::optional<int> parseSettings(int argc, char** argv, Settings& settings) {
  namespace tools = body_scan_driver::tools;
  CLI::App app(
      "Fits simulated subjects (or motion-capture walks) in the four gait poses of thesis 5.3 "
      "and compares each fit with the true skeleton: one line per fit, a summary, per-joint and "
      "per-segment errors, a YAML report.",
      "evaluate_body_fit");
  settings.rig.noise_sigma = 0.002;
  app.add_option("--subjects", settings.subjects, "simulatedSubjects(N)")
      ->capture_default_str()
      ->check(tools::atLeast(1));
  app.add_option("--people", settings.people,
                 "fit simulatedPeople(N) (survey-drawn bodies, personal gait styles; walk 0) "
                 "instead of simulatedSubjects")
      ->check(tools::atLeast(1));
  int columns = 0;
  app.add_option("--columns", columns,
                 "sampler: ray grid per viewpoint (rows = 13/16 of it; default 320)")
      ->check(tools::atLeast(20));
  app.add_option("--noise", settings.rig.noise_sigma, "sampler: range noise SD (m)")
      ->capture_default_str()
      ->check(tools::atLeast(0));
  app.add_option("--min-albedo", settings.rig.min_albedo,
                 "sampler: surfaces darker than this return no light");
  app.add_option("--missing-viewpoints", settings.rig.missing_viewpoints,
                 "sampler: viewpoints without data, pole * 4 + height, e.g. 0,5")
      ->delimiter(',');
  app.add_option("--abduction-deg", settings.abduction_deg, "both shoulders' abduction (deg)");
  app.add_option("--lean-deg", settings.lean_deg,
                 "every simulated body's forward torso lean (deg; simulatedSubjects stand "
                 "upright, simulatedPeople lean by their style)")
      ->check(tools::inRange(-90, 90, true));
  bool direct = false;
  app.add_flag("--direct", direct, "skip the refinement");
  app.add_flag("--test-headings", settings.test_headings, "test_body_fitter's headings");
  app.add_flag("--per-joint", settings.per_joint, "print every fit's joint and segment errors");
  app.add_flag("--full-scanner", settings.full_scanner,
               "scan with the simulated full scanner (the thesis rig's 12 pairs) instead of the "
               "ray-cast sampler");
  app.add_option("--missing-pairs", settings.scanner.missing_pairs,
                 "full scanner: pairs left out, e.g. pole_c/pair_2")
      ->delimiter(',');
  app.add_option("--rig", settings.scanner.rig_file, "full scanner: another rig file")
      ->check(CLI::ExistingFile);
  app.add_option("--dark-albedo", settings.dark_albedo,
                 "albedo of the hair and the trunks (default 0.15; below ~0.05 the full scanner "
                 "decodes little of them)");
  app.add_option("--only", settings.only, "one subject, e.g. subject_9");
  app.add_option("--clouds", settings.clouds,
                 "write every case's cloud to DIR/<subject>_pose<k>.ply (world frame)");
  app.add_option("--clouds-from", settings.clouds_from,
                 "read every case's cloud from DIR/<subject>_pose<k>.ply (written by --clouds "
                 "with the same cases and scanner options) instead of scanning it: refits in "
                 "seconds")
      ->check(CLI::ExistingDirectory);
  app.add_option("--bvh", settings.bvh_files,
                 "[PERSON=]WALK.bvh,...: motion-capture walks instead of simulated subjects "
                 "(scanned with the full scanner; PERSON defaults to the file name up to its "
                 "first '_')")
      ->delimiter(',');
  app.add_option("--bvh-map", settings.bvh_map,
                 "BVH joint map (default: body_scan_driver's config/bvh/cmu_joint_map.yaml)")
      ->check(CLI::ExistingFile);
  app.add_option("--models", settings.models_out,
                 "write each walk's 4 fitted models to DIR/<walk>.yaml (identify_walks reads "
                 "them)");
  app.add_option("--picture", settings.picture,
                 "PNG: every case's cloud from the side with the fitted (red) and true (green) "
                 "joints");
  std::string body = "ellipsoid";
  app.add_option("--body", body, "the simulated body: ellipsoid (default) or mesh")
      ->check(CLI::IsMember({"ellipsoid", "mesh"}));
  app.add_option("--out", settings.out, "YAML report");
  std::string fit_mode = "scan", joint_limits = "walking";
  app.add_option("--fit", fit_mode,
                 "scan: every scan fitted alone (fitBody); walk: the 4 poses of each subject or "
                 "walk fitted together (fitWalk: one body, a pose per scan)")
      ->check(CLI::IsMember({"scan", "walk"}))
      ->capture_default_str();
  app.add_option("--joint-limits", joint_limits,
                 "walking (gait ranges, config/body_fitter.yaml) or thesis (Table 5.2)")
      ->check(CLI::IsMember({"walking", "thesis"}))
      ->capture_default_str();
  if (const auto status = tools::parseCommandLine(app, argc, argv)) return status;
  if (columns > 0) {
    settings.rig.columns = columns;
    settings.rig.rows = columns * 13 / 16;
  }
  settings.options.refine = !direct;
  settings.walk_fit = fit_mode == "walk";
  settings.options.joint_limits = joint_limits == "thesis" ? body_gait_model::thesisJointLimits()
                                                           : body_gait_model::walkingJointLimits();
  settings.rig.body = settings.scanner.body = body_gait_model::eval::parseBodyKind(body);
  return std::nullopt;
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

// The simulated cases: every body x the 4 poses (simulatedSubjects, or simulatedPeople's walk 0).
// Returns nullopt after a usage error (an unknown --only).
std::optional<std::vector<Case>> simulatedCases(Settings& settings) {
  std::vector<body_scan_driver::sim::HumanBodySpec> bodies;
  std::vector<body_gait_model::eval::SimulatedPerson> persons;
  if (settings.people > 0) {
    persons = body_gait_model::eval::simulatedPeople(settings.people);
    for (const auto& person : persons) {
      bodies.emplace_back();
      bodies.back().name = person.name;
    }
    settings.subjects = settings.people;
  } else {
    bodies = body_gait_model::eval::simulatedSubjects(settings.subjects);
  }
  if (!settings.only.empty()) {
    bool known = false;
    for (const auto& body : bodies) known = known || body.name == settings.only;
    if (!known) {
      std::fprintf(stderr, "evaluate_body_fit: --only %s: no such subject among %s .. %s\n",
                   settings.only.c_str(), bodies.front().name.c_str(), bodies.back().name.c_str());
      return std::nullopt;
    }
  }
  std::vector<Case> cases;
  int index = 0;
  for (size_t k = 0; k < bodies.size(); ++k) {
    for (int pose = 1; pose <= 4; ++pose, ++index) {
      Case c;
      c.pose = pose;
      const double heading = settings.full_scanner
                                 ? body_gait_model::eval::fullScannerHeading(index)
                                 : 0.3 + 1.7 * (settings.test_headings ? pose : pose + index);
      if (settings.people > 0) {
        c.spec = body_gait_model::eval::walkingSubject(persons[k], pose, 0, heading);
      } else {
        c.spec = bodies[k];
        c.spec.pose = body_gait_model::eval::gaitPose(pose, heading);
      }
      if (settings.abduction_deg >= 0)
        c.spec.pose.left_shoulder_abduction = c.spec.pose.right_shoulder_abduction =
            settings.abduction_deg * kPi / 180;
      if (settings.lean_deg > -90) c.spec.pose.torso_lean = settings.lean_deg * kPi / 180;
      cases.push_back(c);
    }
  }
  return cases;
}

// Sums over the fits, for the summary.
struct Totals {
  double joint = 0, procrustes = 0, length = 0, swing = 0, seconds = 0, points = 0;
  int cases = 0, right = 0, low_quality = 0, reaching_limits = 0;
  // The flag against "mean joint error > 50 mm": flagged bad, flagged good, unflagged bad.
  int flagged_bad = 0, flagged_good = 0, unflagged_bad = 0;
  struct JointStats {
    double error = 0;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  };
  std::map<std::string, JointStats> joint_stats;
  std::map<std::string, std::pair<double, double>> segment_stats;  // |error|, signed error

  void add(const body_gait_model::eval::FitErrors& errors, const body_gait_model::BodyFit& fit,
           double fit_seconds, size_t point_count) {
    for (const auto& [name, error] : errors.joint_error) {
      joint_stats[name].error += error;
      joint_stats[name].offset += errors.joint_offset.at(name);
    }
    for (const auto& [name, bias] : errors.segment_length_bias) {
      segment_stats[name].first += std::abs(bias);
      segment_stats[name].second += bias;
    }
    joint += errors.mean_joint_error;
    procrustes += errors.procrustes_joint_error;
    length += errors.mean_length_error;
    swing += errors.mean_swing_error;
    seconds += fit_seconds;
    points += double(point_count);
    right += errors.front_right && errors.left_right;
    low_quality += fit.quality.low_quality;
    reaching_limits += !fit.quality.limits_reached.empty();
    const bool bad = errors.mean_joint_error > kBadFit;
    flagged_bad += fit.quality.low_quality && bad;
    flagged_good += fit.quality.low_quality && !bad;
    unflagged_bad += !fit.quality.low_quality && bad;
    ++cases;
  }
  // One line: errors, facing, flags.
  std::string line() const {
    char text[256];
    std::snprintf(text, sizeof text,
                  "%d fits: joint %.1f mm (Procrustes %.1f mm), length %.1f %%, swing %.2f deg, "
                  "front/left right %d/%d, low quality %d",
                  cases, 1000 * joint / cases, 1000 * procrustes / cases, 100 * length / cases,
                  swing / cases * 180 / kPi, right, cases, low_quality);
    return text;
  }
  static constexpr double kBadFit = 0.050;  // m: a fit this far off should be flagged
};

// One fit's joint offsets (fitted - true, in the true body frame) and whose body it was.
struct FitOffsets {
  std::string person;
  std::map<std::string, Eigen::Vector3d> joint_offset;
};

// Joint errors once each joint's systematic offset is removed, the offset learned on the OTHER
// people's fits (leave one person out). They separate how the fitter and the truth define a joint
// (a constant per joint, e.g. a rig's hip deeper in the pelvis than the thigh's axis) from the
// scatter of the fits. NaN with fewer than two people.
struct OffsetRemovedErrors {
  double mean = std::numeric_limits<double>::quiet_NaN();  // m, over fits and joints
  std::map<std::string, double> per_joint;                 // m, over fits
};

OffsetRemovedErrors offsetRemovedErrors(const std::vector<FitOffsets>& fits) {
  OffsetRemovedErrors errors;
  std::map<std::string, double> sums;
  double sum = 0;
  int count = 0;
  for (const FitOffsets& fit : fits) {
    for (const auto& [name, offset] : fit.joint_offset) {
      Eigen::Vector3d others = Eigen::Vector3d::Zero();
      int others_count = 0;
      for (const FitOffsets& other : fits)
        if (other.person != fit.person) {
          others += other.joint_offset.at(name);
          ++others_count;
        }
      if (others_count == 0) return errors;
      const double error = (offset - others / others_count).norm();
      sums[name] += error;
      sum += error;
      ++count;
    }
  }
  if (count == 0) return errors;
  errors.mean = sum / count;
  for (const auto& [name, joint_sum] : sums) errors.per_joint[name] = joint_sum / fits.size();
  return errors;
}

// Every fit's totals, and per subject or walk and per pose.
struct Summary {
  Totals all;
  std::map<std::string, Totals> by_walk, by_pose;
  std::vector<FitOffsets> offsets;
};

// What the run writes besides stdout.
struct Outputs {
  std::ostringstream yaml;
  std::map<std::string, YAML::Node> walk_models;  // walk -> its models file
  std::vector<cv::Mat> panels;
};

// The subject or walk a case belongs to: the cases fitted together by --fit walk.
std::string walkOf(const Case& each) { return each.walk.empty() ? each.spec.name : each.walk; }

// Scans one case (the full scanner or the sampler) and writes its cloud for --clouds. Throws
// when the scan or its cloud file fails.
body_gait_model::eval::SampledBody scanCase(const Case& each, const Settings& settings) {
  auto spec = each.spec;
  if (settings.dark_albedo >= 0)
    spec.materials.hair.albedo = spec.materials.clothing.albedo = settings.dark_albedo;
  const std::string cloud_name = spec.name + "_pose" + std::to_string(each.pose) + ".ply";
  body_gait_model::eval::SampledBody body;
  if (!settings.clouds_from.empty()) {
    // The truth as a scan would place it; the points from the file.
    body_scan_driver::sim::Scene scene;
    body.spec = body_gait_model::eval::addSimulatedBody(spec, settings.scanner.body, scene);
    body.skeleton = scene.skeleton();
    const std::vector<float> xyzrgb =
        body_scan_merge::readPly(settings.clouds_from + "/" + cloud_name);
    for (size_t i = 0; i + 4 <= xyzrgb.size(); i += 4)
      body.points.emplace_back(xyzrgb[i], xyzrgb[i + 1], xyzrgb[i + 2]);
  } else {
    body = settings.full_scanner
               ? body_gait_model::eval::scanBodyWithFullScanner(spec, settings.scanner)
               : body_gait_model::eval::sampleBody(spec, settings.rig);
  }
  if (!settings.clouds.empty()) {
    std::vector<float> xyz;
    for (const Eigen::Vector3d& p : body.points)
      xyz.insert(xyz.end(), {float(p.x()), float(p.y()), float(p.z())});
    const std::string path = settings.clouds + "/" + cloud_name;
    body_scan_merge::writePly(path, xyz.data(), body.points.size(), 3, -1);
  }
  return body;
}

// Compares one fit with the truth, prints its line and adds it to the summary and the outputs.
void reportFit(const Case& each, const body_gait_model::eval::SampledBody& body,
               const body_gait_model::BodyFit& fit, double fit_seconds, const Settings& settings,
               Summary& summary, Outputs& outputs) {
  const auto& spec = body.spec;
  const int pose = each.pose;
  const auto errors = body_gait_model::eval::compareWithTruth(fit.model, body);
  if (!settings.picture.empty()) {
    std::ostringstream title;
    title << spec.name << " pose " << pose;
    if (each.frame >= 0) title << " (frame " << each.frame + 1 << ")";
    title << ": " << std::lround(1000 * errors.mean_joint_error) << " mm";
    outputs.panels.push_back(sidePanel(body.points, body_gait_model::forwardKinematics(fit.model),
                                       body.skeleton, title.str()));
  }
  const bool heading_right = errors.front_right && errors.left_right;
  std::string limits;
  for (const std::string& limit : fit.quality.limits_reached)
    limits += (limits.empty() ? "" : "; ") + limit;
  std::printf(
      "%s pose %d: %zu points, joint %.1f mm (Procrustes %.1f mm), length %.1f %%, swing %.2f "
      "deg, front/left %s, RMS %.1f mm, explained %.0f %%%s, %.0f ms%s%s\n",
      (spec.name + (each.frame >= 0 ? " frame " + std::to_string(each.frame + 1) : "")).c_str(),
      pose, body.points.size(), 1000 * errors.mean_joint_error,
      1000 * errors.procrustes_joint_error, 100 * errors.mean_length_error,
      errors.mean_swing_error * 180 / kPi, heading_right ? "right" : "WRONG",
      1000 * fit.quality.rms_distance, 100 * fit.quality.explained_fraction,
      fit.quality.low_quality ? ", LOW QUALITY" : "", 1000 * fit_seconds,
      limits.empty() ? "" : "\n    limits reached: ", limits.c_str());
  if (fit.quality.low_quality && settings.per_joint)
    std::printf("    low quality: %s\n", fit.quality.reason.c_str());
  std::ostringstream& yaml = outputs.yaml;
  yaml << "  - {subject: " << spec.name << ", pose: " << pose << ", points: " << body.points.size()
       << ", joint_error_m: " << errors.mean_joint_error
       << ", procrustes_joint_error_m: " << errors.procrustes_joint_error
       << ", length_error: " << errors.mean_length_error
       << ", swing_error_rad: " << errors.mean_swing_error
       << ", heading_right: " << (heading_right ? "true" : "false")
       << ", rms_m: " << fit.quality.rms_distance
       << ", explained: " << fit.quality.explained_fraction
       << ", low_quality: " << (fit.quality.low_quality ? "true" : "false")
       << ", limits_reached: " << fit.quality.limits_reached.size()
       << ", fit_seconds: " << fit_seconds;
  yaml << ", joint_errors_m: {";
  for (const auto& [name, error] : errors.joint_error)
    yaml << (name == errors.joint_error.begin()->first ? "" : ", ") << name << ": " << error;
  yaml << "}";
  if (each.frame >= 0) yaml << ", person: '" << each.person << "', frame: " << each.frame + 1;
  yaml << "}\n";
  if (each.frame >= 0) {
    YAML::Node& file = outputs.walk_models[each.walk];
    if (!file["walk"]) {
      file["person"] = each.person;
      file["walk"] = each.walk;
    }
    YAML::Node pose_node = body_gait_model::bodyModelToYaml(fit.model);
    pose_node["frame"] = each.frame + 1;
    pose_node["low_quality"] = fit.quality.low_quality;
    file["poses"].push_back(pose_node);
  }
  if (settings.per_joint) {
    for (const auto& [name, error] : errors.joint_error)
      std::printf("    %-15s %6.1f mm (%+6.1f %+6.1f %+6.1f)\n", name.c_str(), 1000 * error,
                  1000 * errors.joint_offset.at(name).x(), 1000 * errors.joint_offset.at(name).y(),
                  1000 * errors.joint_offset.at(name).z());
    for (const auto& [name, bias] : errors.segment_length_bias)
      std::printf("    %-15s %+6.1f %%\n", name.c_str(), 100 * bias);
  }
  summary.offsets.push_back({each.person.empty() ? spec.name : each.person, errors.joint_offset});
  for (Totals* totals : {&summary.all, &summary.by_walk[walkOf(each)],
                         &summary.by_pose["pose " + std::to_string(pose)]})
    totals->add(errors, fit, fit_seconds, body.points.size());
}

// Scans a subject's or walk's cases and fits them (alone, or together with --fit walk).
void evaluateWalk(const std::vector<const Case*>& walk, const Settings& settings, Summary& summary,
                  Outputs& outputs) {
  std::vector<body_gait_model::eval::SampledBody> bodies;
  for (const Case* each : walk) bodies.push_back(scanCase(*each, settings));
  std::vector<body_gait_model::BodyFit> fits;
  std::vector<double> seconds;
  if (settings.walk_fit) {
    std::vector<body_gait_model::Cloud> clouds;
    for (const auto& body : bodies) clouds.push_back(body.points);
    const auto start = std::chrono::steady_clock::now();
    fits = body_gait_model::fitWalk(clouds, settings.options).scans;
    const double walk_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    seconds.assign(fits.size(), walk_seconds / double(fits.size()));
  } else {
    for (const auto& body : bodies) {
      const auto start = std::chrono::steady_clock::now();
      fits.push_back(body_gait_model::fitBody(body.points, settings.options));
      seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
  }
  for (size_t k = 0; k < walk.size(); ++k)
    reportFit(*walk[k], bodies[k], fits[k], seconds[k], settings, summary, outputs);
}

// The summary line, the per-walk, per-pose, per-joint and per-segment tables, and their YAML.
void summarize(const Summary& summary, int subjects, const Settings& settings,
               std::ostringstream& yaml) {
  const Totals& totals = summary.all;
  const int cases = totals.cases;
  if (cases == 0) return;
  std::printf(
      "SUMMARY %d fits (%d subjects or walks x 4 poses, %s fit, mean %.0f points): mean "
      "joint-centre error %.1f mm, segment-length error %.1f %%, swing-angle error %.2f deg, "
      "front/left right %d/%d, low quality %d, %.0f ms per fit\n",
      cases, subjects, settings.walk_fit ? "walk" : "scan", totals.points / cases,
      1000 * totals.joint / cases, 100 * totals.length / cases, totals.swing / cases * 180 / kPi,
      totals.right, cases, totals.low_quality, 1000 * totals.seconds / cases);
  const int flagged = totals.flagged_bad + totals.flagged_good;
  const int bad = totals.flagged_bad + totals.unflagged_bad;
  std::printf(
      "Procrustes-aligned joint error %.1f mm; fits reaching a joint limit %d; the low-quality "
      "flag against mean joint error > 50 mm: precision %d/%d, recall %d/%d\n",
      1000 * totals.procrustes / cases, totals.reaching_limits, totals.flagged_bad, flagged,
      totals.flagged_bad, bad);
  const OffsetRemovedErrors offset_removed = offsetRemovedErrors(summary.offsets);
  std::printf(
      "joint error with each joint's mean offset removed, learned on the other people: %.1f mm\n",
      1000 * offset_removed.mean);
  for (const auto& [title, groups] : {std::pair{"per subject or walk", &summary.by_walk},
                                      std::pair{"per pose", &summary.by_pose}}) {
    std::printf("%s:\n", title);
    for (const auto& [name, group] : *groups)
      std::printf("  %-12s %s\n", name.c_str(), group.line().c_str());
  }
  std::printf("%-16s %9s %28s %16s\n", "joint", "error mm", "offset fwd/left/up mm",
              "offset removed");
  auto perJointOffsetRemoved = [&](const std::string& name) {
    const auto found = offset_removed.per_joint.find(name);
    return found == offset_removed.per_joint.end() ? std::numeric_limits<double>::quiet_NaN()
                                                   : found->second;
  };
  for (const auto& [name, stats] : totals.joint_stats)
    std::printf("%-16s %9.1f %9.1f %8.1f %8.1f %16.1f\n", name.c_str(), 1000 * stats.error / cases,
                1000 * stats.offset.x() / cases, 1000 * stats.offset.y() / cases,
                1000 * stats.offset.z() / cases, 1000 * perJointOffsetRemoved(name));
  std::printf("%-16s %9s %9s\n", "segment", "|error| %", "signed %");
  for (const auto& [name, stats] : totals.segment_stats)
    std::printf("%-16s %9.1f %9.1f\n", name.c_str(), 100 * stats.first / cases,
                100 * stats.second / cases);
  yaml << "joints:\n";
  for (const auto& [name, stats] : totals.joint_stats)
    yaml << "  " << name << ": {error_m: " << stats.error / cases << ", offset_forward_left_up_m: ["
         << stats.offset.x() / cases << ", " << stats.offset.y() / cases << ", "
         << stats.offset.z() / cases << "]}\n";
  yaml << "segments:\n";
  for (const auto& [name, stats] : totals.segment_stats)
    yaml << "  " << name << ": {length_error: " << stats.first / cases
         << ", signed_length_error: " << stats.second / cases << "}\n";
  auto totalsYaml = [&](const Totals& t) {
    std::ostringstream text;
    text << "{fits: " << t.cases << ", mean_joint_error_m: " << t.joint / t.cases
         << ", procrustes_joint_error_m: " << t.procrustes / t.cases
         << ", mean_length_error: " << t.length / t.cases
         << ", mean_swing_error_rad: " << t.swing / t.cases << ", heading_right: " << t.right
         << ", low_quality: " << t.low_quality << "}";
    return text.str();
  };
  for (const auto& [key, groups] :
       {std::pair{"walks", &summary.by_walk}, std::pair{"poses", &summary.by_pose}}) {
    yaml << key << ":\n";
    for (const auto& [name, group] : *groups)
      yaml << "  '" << name << "': " << totalsYaml(group) << "\n";
  }
  yaml << "summary: {fits: " << cases << ", fit: " << (settings.walk_fit ? "walk" : "scan")
       << ", mean_points: " << totals.points / cases
       << ", mean_joint_error_m: " << totals.joint / cases
       << ", procrustes_joint_error_m: " << totals.procrustes / cases
       << ", offset_removed_joint_error_m: "
       << (std::isnan(offset_removed.mean) ? std::string(".nan")
                                           : std::to_string(offset_removed.mean))
       << ", mean_length_error: " << totals.length / cases
       << ", mean_swing_error_rad: " << totals.swing / cases << ", heading_right: " << totals.right
       << ", low_quality: " << totals.low_quality << ", flag_precision: [" << totals.flagged_bad
       << ", " << flagged << "]"
       << ", flag_recall: [" << totals.flagged_bad << ", " << bad << "]"
       << ", reaching_limits: " << totals.reaching_limits
       << ", mean_fit_seconds: " << totals.seconds / cases << "}\n";
}

// --picture, --models and --out. Throws when a file cannot be written.
void writeOutputs(const Settings& settings, const Outputs& outputs) {
  if (!settings.picture.empty() && !outputs.panels.empty()) {
    cv::Mat row;
    cv::hconcat(outputs.panels, row);
    if (!cv::imwrite(settings.picture, row))
      throw std::runtime_error("cannot write the picture '" + settings.picture + "'");
  }
  if (!settings.models_out.empty()) {
    std::filesystem::create_directories(settings.models_out);
    for (const auto& [walk, node] : outputs.walk_models) {
      YAML::Emitter text;
      text.SetDoublePrecision(17);
      text << node;
      body_scan_driver::writeFileAtomically(
          settings.models_out + "/" + walk + ".yaml",
          "# Fitted body models of walk " + walk +
              " (evaluate_body_fit --bvh --models): the 4 poses of\n# thesis 5.3 in order "
              "s1..s4 (body_gait_model/gait_poses_file.h, with the frame and fit quality).\n" +
              text.c_str() + "\n");
    }
  }
  if (!settings.out.empty())
    body_scan_driver::writeFileAtomically(settings.out, outputs.yaml.str());
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  if (const auto status = parseSettings(argc, argv, settings)) return *status;
  try {
    // The cases: simulated subjects x the 4 poses, or the 4 picked poses of every BVH walk.
    std::vector<Case> cases;
    if (settings.bvh_files.empty()) {
      std::optional<std::vector<Case>> simulated = simulatedCases(settings);
      if (!simulated) return 2;
      cases = std::move(*simulated);
    } else {
      settings.full_scanner = true;  // real motion is judged on the product's clouds
      if (settings.bvh_map.empty())
        settings.bvh_map = body_scan_driver::tools::packageFile(
            "body_scan_driver", "config/bvh/cmu_joint_map.yaml", "--bvh-map");
      cases = bvhCases(settings.bvh_files, settings.bvh_map);
      settings.subjects = int(settings.bvh_files.size());
    }
    Summary summary;
    Outputs outputs;
    outputs.yaml << "cases:\n";
    // Each subject's or walk's cases in turn (consecutive in the list).
    for (size_t begin = 0; begin < cases.size();) {
      std::vector<const Case*> walk;
      size_t end = begin;
      for (; end < cases.size() && walkOf(cases[end]) == walkOf(cases[begin]); ++end)
        if (settings.only.empty() || cases[end].spec.name == settings.only)
          walk.push_back(&cases[end]);
      if (!walk.empty()) evaluateWalk(walk, settings, summary, outputs);
      begin = end;
    }
    summarize(summary, settings.subjects, settings, outputs.yaml);
    writeOutputs(settings, outputs);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "evaluate_body_fit: %s\n", error.what());
    return 1;
  }
  return 0;
}
