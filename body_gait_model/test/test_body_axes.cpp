// PCA body axes (5.5.1): vertical axis, centroid and heading against the simulator's subject,
// and front/left right for every heading x gait pose x subject (fitters of others face
// backwards). A cloud that cannot be a standing body is refused with a clear error.
#include <body_gait_model/body_axes.h>
#include <body_gait_model/eval/body_cloud_sampler.h>
#include <gtest/gtest.h>

#include <cmath>

namespace body_gait_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(BodyAxes, FrontAndLeftAreRightForEveryHeadingPoseAndSubject) {
  const auto subjects = eval::simulatedSubjects(3);
  eval::ScanRig rig;
  rig.columns = 120;
  rig.rows = 100;
  rig.noise_sigma = 0.002;
  int cases = 0, right = 0;
  double worst_heading_error = 0, sum_heading_error = 0, worst_pca_tilt = 0;
  for (const auto& subject : subjects) {
    for (int pose = 1; pose <= 4; ++pose) {
      for (double heading : {0.3, 0.3 + kPi / 2, 0.3 + kPi, 0.3 + 3 * kPi / 2}) {
        auto spec = subject;
        spec.pose = eval::gaitPose(pose, heading);
        const auto body = eval::sampleBody(spec, rig);
        const BodyAxes axes = estimateBodyAxes(body.points);
        const Eigen::Vector3d true_front(std::cos(heading), std::sin(heading), 0);
        const Eigen::Vector3d true_left(-std::sin(heading), std::cos(heading), 0);
        const double heading_error =
            std::acos(std::clamp(axes.axes.col(2).dot(true_front), -1.0, 1.0));
        const double pca_tilt = std::acos(std::clamp(axes.pca_vertical.z(), -1.0, 1.0));
        worst_heading_error = std::max(worst_heading_error, heading_error);
        sum_heading_error += heading_error;
        worst_pca_tilt = std::max(worst_pca_tilt, pca_tilt);
        const bool ok =
            axes.axes.col(2).dot(true_front) > 0.9 && axes.axes.col(0).dot(true_left) > 0.9;
        EXPECT_TRUE(ok) << spec.name << " pose " << pose << " heading " << heading << ": front "
                        << axes.axes.col(2).transpose() << ", foot reach " << axes.foot_reach;
        right += ok;
        ++cases;
        // The centroid is the body's middle: between the hips and the shoulders.
        const double pelvis_z = eval::trueJoint(body, "pelvis").z();
        EXPECT_GT(axes.centroid.z(), pelvis_z - 0.1);
        EXPECT_LT(axes.centroid.z(), eval::trueJoint(body, "neck").z());
        // Eq 5.4: the head's top is the highest model point, the left shoulder at +X_m.
        EXPECT_GT(axes.toModel(eval::trueJoint(body, "left_shoulder")).x(), 0.1);
        EXPECT_LT(axes.toModel(eval::trueJoint(body, "right_shoulder")).x(), -0.1);
      }
    }
  }
  std::printf(
      "[ figure ] front/left right in %d of %d cases (%.0f %%); heading error mean %.1f "
      "deg, worst %.1f deg (before refinement); PCA e_1 tilt up to %.1f deg\n",
      right, cases, 100.0 * right / cases, sum_heading_error / cases * 180 / kPi,
      worst_heading_error * 180 / kPi, worst_pca_tilt * 180 / kPi);
  EXPECT_EQ(right, cases);
  EXPECT_LT(sum_heading_error / cases, 6 * kPi / 180);
  EXPECT_LT(worst_heading_error, 15 * kPi / 180);
}

TEST(BodyAxes, RefusesCloudsThatCannotBeAStandingBody) {
  Cloud few(10, Eigen::Vector3d::Zero());
  EXPECT_THROW(estimateBodyAxes(few), std::invalid_argument);
  // A long horizontal bar: its main axis is not vertical.
  Cloud bar;
  for (int i = 0; i < 5000; ++i)
    bar.emplace_back(2.0 * i / 5000, 0.01 * std::sin(i), 1.0 + 0.01 * std::cos(i * 0.7));
  try {
    estimateBodyAxes(bar);
    FAIL() << "a horizontal bar was accepted as a body";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("vertical"), std::string::npos) << error.what();
  }
}

TEST(BodyAxes, StrayPointsAboveTheHeadDoNotMoveTheShouldersTop) {
  // Undecoded dark hair leaves a few stray points in the air around the head: the highest slices
  // are sparse and their extreme points must not make them as wide as shoulders.
  auto spec = eval::simulatedSubjects(1).front();
  spec.pose = eval::gaitPose(1, 0.7);
  eval::ScanRig rig;
  rig.columns = 120;
  rig.rows = 100;
  const auto body = eval::sampleBody(spec, rig);
  const BodyAxes clean = estimateBodyAxes(body.points);
  Cloud cloud = body.points;
  double top = 0;
  for (const auto& p : cloud) top = std::max(top, p.z());
  const Eigen::Vector3d head = eval::trueJoint(body, "head_top");
  for (int k = 0; k < 20; ++k)  // a sparse top slice, two points of it far to the sides
    cloud.emplace_back(head.x() + 0.002 * k, head.y(), top + 0.005);
  cloud.emplace_back(head.x() - 0.45, head.y(), top + 0.004);
  cloud.emplace_back(head.x() + 0.2, head.y() - 0.1, top + 0.006);
  const BodyAxes axes = estimateBodyAxes(cloud);
  std::printf("[ figure ] shoulders' top %.3f m with stray points, %.3f m without\n",
              axes.shoulder_top - axes.lowest, clean.shoulder_top - clean.lowest);
  EXPECT_NEAR(axes.shoulder_top - axes.lowest, clean.shoulder_top - clean.lowest, 0.02);
  EXPECT_GT(axes.axes.col(2).dot(clean.axes.col(2)), std::cos(5 * kPi / 180));
}

}  // namespace
}  // namespace body_gait_model
