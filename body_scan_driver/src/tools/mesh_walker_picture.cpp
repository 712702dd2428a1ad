// Draws the mesh human posed on the four representative poses of thesis 5.3 found in a BVH walk
// (sim/mesh_human.h, sim/bvh_body.h), seen from the side (the subject's right), shaded skin with
// the true skeleton on top (joints as dots, bones as lines), one panel per pose:
//
//   mesh_walker_picture WALK.bvh --out poses.png [--map MAP.yaml] [--gender 0..1] [--bmi B]
//
// The person's stature is the one the walk's legs imply.
#include <body_scan_driver/sim/bvh_body.h>
#include <body_scan_driver/sim/data_paths.h>
#include <body_scan_driver/sim/mesh_human.h>
#include <body_scan_driver/sim/triangle_mesh.h>
#include <body_scan_driver/tools/command_line.h>

#include <cstdio>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace body_scan_driver::sim;

constexpr double kPixel = 0.004;  // m per pixel
constexpr int kWidth = 360, kHeight = 500;

// The panel of one pose: orthographic rays from the subject's right (-y) toward +y.
cv::Mat3b drawPanel(const Scene& scene, const std::string& title) {
  cv::Mat3b panel(kHeight, kWidth, cv::Vec3b(255, 255, 255));
  const Eigen::Vector3d light = Eigen::Vector3d(0.4, -1.0, 0.6).normalized();
  std::vector<Ray> rays(kWidth);
  std::vector<Hit> hits(kWidth);
  auto toPixel = [&](const Eigen::Vector3d& p) {
    return cv::Point(static_cast<int>(kWidth / 2 + p.x() / kPixel),
                     static_cast<int>(kHeight - 20 - p.z() / kPixel));
  };
  for (int row = 0; row < kHeight; ++row) {
    const double z = (kHeight - 20 - row) * kPixel;
    for (int col = 0; col < kWidth; ++col)
      rays[col] =
          Ray{Eigen::Vector3d((col - kWidth / 2) * kPixel, -3.0, z), Eigen::Vector3d::UnitY()};
    scene.intersectMany(rays.data(), kWidth, hits.data());
    for (int col = 0; col < kWidth; ++col) {
      if (!hits[col].surface) continue;
      const Eigen::Vector3d point = rays[col].origin + hits[col].distance * rays[col].direction;
      const Eigen::Vector3d color = hits[col].surface->colorAtHit(hits[col], point);
      const double shade = 0.35 + 0.65 * std::max(0.0, hits[col].normal.dot(-light));
      panel(row, col) = cv::Vec3b(cv::saturate_cast<uchar>(255 * shade * color.z()),
                                  cv::saturate_cast<uchar>(255 * shade * color.y()),
                                  cv::saturate_cast<uchar>(255 * shade * color.x()));
    }
  }
  std::map<std::string, Eigen::Vector3d> joints;
  for (const SkeletonJoint& joint : scene.skeleton()) joints[joint.name] = joint.position;
  const std::vector<std::pair<std::string, std::string>> bones = {
      {"head_top", "neck"},       {"neck", "pelvis"},     {"neck", "left_shoulder"},
      {"neck", "right_shoulder"}, {"pelvis", "left_hip"}, {"pelvis", "right_hip"}};
  for (const auto& [a, b] : bones)
    cv::line(panel, toPixel(joints[a]), toPixel(joints[b]), cv::Scalar(0, 140, 0), 2, cv::LINE_AA);
  for (const char* side : {"left_", "right_"}) {
    const std::string s = side;
    const std::vector<std::string> chain_arm = {s + "shoulder", s + "elbow", s + "wrist",
                                                s + "hand_tip"};
    const std::vector<std::string> chain_leg = {s + "hip", s + "knee", s + "ankle", s + "toe"};
    // The far side (left, seen from the right) in a lighter green.
    const cv::Scalar colour = s == "left_" ? cv::Scalar(120, 200, 120) : cv::Scalar(0, 140, 0);
    for (const auto* chain : {&chain_arm, &chain_leg})
      for (size_t i = 0; i + 1 < chain->size(); ++i)
        cv::line(panel, toPixel(joints[(*chain)[i]]), toPixel(joints[(*chain)[i + 1]]), colour, 2,
                 cv::LINE_AA);
  }
  for (const auto& [name, position] : joints)
    cv::circle(panel, toPixel(position), 4, cv::Scalar(0, 0, 200), cv::FILLED, cv::LINE_AA);
  cv::putText(panel, title, {8, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  return panel;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Draws the mesh human on the four gait poses of a BVH walk with its true skeleton.",
               "mesh_walker_picture");
  std::string bvh, out, map_path;
  MeshPersonSpec person;
  app.add_option("WALK.bvh", bvh, "motion-capture walk")->required()->check(CLI::ExistingFile);
  app.add_option("--out", out, "PNG file")->required();
  app.add_option("--map", map_path, "BVH joint map (default: the CMU map of body_scan_driver)");
  app.add_option("--gender", person.gender, "0 female .. 1 male")->capture_default_str();
  app.add_option("--bmi", person.bmi, "kg/m^2")->capture_default_str();
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    if (map_path.empty()) map_path = driverConfigDir() + "/bvh/cmu_joint_map.yaml";
    const BvhSubject subject(loadBvh(bvh), loadBvhJointMap(map_path), "walker");
    person.stature = subject.estimatedStature();
    const auto rig = meshHumanRig(person, meshHumanFiles());
    const GaitPoseFrames poses = pickGaitPoses(subject);
    std::vector<cv::Mat> panels;
    for (int k = 0; k < 4; ++k) {
      Scene scene;
      addMeshHuman(*rig, subject.body(poses.frame[k], rig->anthropometry()), scene);
      panels.push_back(drawPanel(scene, "pose " + std::to_string(k + 1) + " (frame " +
                                            std::to_string(poses.frame[k] + 1) + ")"));
    }
    cv::Mat picture;
    cv::hconcat(panels, picture);
    // Written beside, then renamed: a reader never sees half a picture.
    const std::string partial = out + ".partial.png";
    if (!cv::imwrite(partial, picture) || std::rename(partial.c_str(), out.c_str()) != 0)
      throw std::runtime_error("cannot write '" + out + "' (check the folder exists)");
    std::printf("%s: stature %.3f m, frames %d %d %d %d -> %s\n", bvh.c_str(), person.stature,
                poses.frame[0] + 1, poses.frame[1] + 1, poses.frame[2] + 1, poses.frame[3] + 1,
                out.c_str());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "mesh_walker_picture: %s\n", error.what());
    return 1;
  }
  return 0;
}
