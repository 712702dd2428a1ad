// Simulated people: statures against ANSUR II, proportions varying as people's
// do, walks of one person closer to each other than to other people's, every pose within
// Table 5.2, and a forward stride from every person's gait cycle.
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/eval/skeleton_model.h>
#include <body_gait_model/gait_cycle.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace body_gait_model::eval {
namespace {

struct Statistics {
  double mean = 0, sd = 0;
  int count = 0;
};

Statistics statistics(const std::vector<double>& values) {
  Statistics s;
  s.count = static_cast<int>(values.size());
  for (double v : values) s.mean += v / s.count;
  for (double v : values) s.sd += (v - s.mean) * (v - s.mean) / (s.count - 1);
  s.sd = std::sqrt(s.sd);
  return s;
}

std::vector<double> collect(const std::vector<SimulatedPerson>& people,
                            const std::function<bool(const SimulatedPerson&)>& which,
                            const std::function<double(const SimulatedPerson&)>& value) {
  std::vector<double> values;
  for (const auto& person : people)
    if (which(person)) values.push_back(value(person));
  return values;
}

TEST(GaitSubjects, StatureByGenderFollowsAnsurII) {
  const auto people = simulatedPeople(1000, 7);
  const auto stature = [](const SimulatedPerson& p) { return p.body.stature; };
  const Statistics women = statistics(collect(
      people, [](const auto& p) { return p.gender == "female"; }, stature));
  const Statistics men = statistics(collect(
      people, [](const auto& p) { return p.gender == "male"; }, stature));
  // Means within 3 standard errors, SDs within 10 % of the survey's.
  EXPECT_NEAR(women.mean, 1.6285, 3 * 0.0642 / std::sqrt(women.count));
  EXPECT_NEAR(men.mean, 1.7562, 3 * 0.0686 / std::sqrt(men.count));
  EXPECT_NEAR(women.sd, 0.0642, 0.1 * 0.0642);
  EXPECT_NEAR(men.sd, 0.0686, 0.1 * 0.0686);
  EXPECT_NEAR(double(women.count) / people.size(), 0.5, 0.05);
  const auto ages = statistics(collect(
      people, [](const auto&) { return true; }, [](const auto& p) { return double(p.age); }));
  EXPECT_NEAR(ages.mean, 44, 2);
}

TEST(GaitSubjects, ProportionsVaryAsPeoplesDo) {
  const auto people = simulatedPeople(1000, 7);
  const auto all = [](const SimulatedPerson&) { return true; };
  auto coefficientOfVariation = [&](const std::function<double(const SimulatedPerson&)>& ratio) {
    const Statistics s = statistics(collect(people, all, ratio));
    return s.sd / s.mean;
  };
  // Segment lengths relative to stature: a shared limb factor (3 %) and the segment's own (2 %).
  const double thigh =
      coefficientOfVariation([](const auto& p) { return p.body.thigh_length / p.body.stature; });
  const double upper_arm = coefficientOfVariation(
      [](const auto& p) { return p.body.upper_arm_length / p.body.stature; });
  const double shoulders =
      coefficientOfVariation([](const auto& p) { return p.body.shoulder_width / p.body.stature; });
  const double waist =
      coefficientOfVariation([](const auto& p) { return p.body.waist_girth / p.body.stature; });
  EXPECT_GT(thigh, 0.03);
  EXPECT_LT(thigh, 0.045);
  EXPECT_GT(upper_arm, 0.03);
  EXPECT_LT(upper_arm, 0.045);
  EXPECT_GT(shoulders, 0.04);
  EXPECT_LT(shoulders, 0.07);
  EXPECT_GT(waist, 0.05);
  EXPECT_LT(waist, 0.08);
  // The torso takes up the rest: the parts still add up to the stature.
  for (const auto& p : people) {
    const auto& b = p.body;
    EXPECT_NEAR(b.ankle_height + b.shank_length + b.thigh_length + b.torso_length + b.neck_length +
                    b.head_height,
                b.stature, 1e-12);
  }
}

TEST(GaitSubjects, DeterministicFromTheSeed) {
  const auto a = simulatedPeople(5, 3), b = simulatedPeople(5, 3), c = simulatedPeople(5, 4);
  const auto longer = simulatedPeople(9, 3);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(a[i].body.stature, b[i].body.stature);
    EXPECT_EQ(a[i].style.hip_swing, longer[i].style.hip_swing) << "person i whatever the count";
    EXPECT_NE(a[i].body.stature, c[i].body.stature);
    const auto walk_a = walkingSubject(a[i], 1, 2), walk_b = walkingSubject(b[i], 1, 2);
    EXPECT_EQ(walk_a.pose.right_hip_flexion, walk_b.pose.right_hip_flexion);
    EXPECT_EQ(walk_a.position, walk_b.position);
  }
}

// The joint angles (q) of a walk's four poses, as the gait features will see them.
Eigen::VectorXd walkAngles(const SimulatedPerson& person, int trial) {
  Eigen::VectorXd angles(4 * 22);
  for (int index = 1; index <= 4; ++index)
    angles.segment<22>(22 * (index - 1)) =
        modelFromSkeleton(walkingSubject(person, index, trial)).q;
  return angles;
}

TEST(GaitSubjects, TwoWalksOfOnePersonDifferLessThanTwoPeople) {
  const auto people = simulatedPeople(50, 11);
  std::vector<Eigen::VectorXd> first, second;
  for (const auto& person : people) {
    first.push_back(walkAngles(person, 0));
    second.push_back(walkAngles(person, 1));
  }
  double within = 0, between = 0;
  int between_pairs = 0, nearest_is_self = 0;
  for (size_t i = 0; i < people.size(); ++i) {
    within += (second[i] - first[i]).norm() / people.size();
    size_t nearest = 0;
    for (size_t j = 0; j < people.size(); ++j) {
      if ((second[i] - first[j]).norm() < (second[i] - first[nearest]).norm()) nearest = j;
      if (j == i) continue;
      between += (first[j] - first[i]).norm();
      ++between_pairs;
    }
    nearest_is_self += nearest == i;
  }
  between /= between_pairs;
  RecordProperty("within_rad", std::to_string(within));
  RecordProperty("between_rad", std::to_string(between));
  RecordProperty("nearest_is_self", nearest_is_self);
  std::printf(
      "q distance over 4 poses: within a person %.4f rad, between people %.4f rad; "
      "second walk nearest its own first walk: %d of %zu\n",
      within, between, nearest_is_self, people.size());
  EXPECT_GT(within, 0.02) << "two walks of one person are not identical";
  EXPECT_LT(within, 0.5 * between) << "walks of one person are closer than two people's";
  EXPECT_GE(nearest_is_self, 40) << "of 50: the angles alone mostly tell people apart";
}

TEST(GaitSubjects, EveryPoseIsWithinTable52AndWalksForward) {
  const auto people = simulatedPeople(200, 5);
  std::vector<double> stride_per_stature;
  for (const auto& person : people) {
    for (int trial = 0; trial < 3; ++trial) {
      RepresentativePoses poses;
      for (int index = 1; index <= 4; ++index) {
        poses[index - 1] = modelFromSkeleton(walkingSubject(person, index, trial, 0.5 * trial));
        EXPECT_TRUE(withinJointLimits(poses[index - 1]))
            << person.name << " pose " << index << " trial " << trial;
      }
      const GaitCycle cycle = reconstructGaitCycle(poses);
      stride_per_stature.push_back(cycle.stride_length / person.body.stature);
    }
  }
  const Statistics stride = statistics(stride_per_stature);
  std::printf("stride / stature: %.3f +- %.3f\n", stride.mean, stride.sd);
  // Adults' comfortable stride is ~0.8 of the stature (thesis 5.3's poses: the longest stride).
  EXPECT_GT(stride.mean, 0.6);
  EXPECT_LT(stride.mean, 1.0);
  EXPECT_GT(stride.sd, 0.03) << "people take strides of their own";
}

TEST(GaitSubjects, BadArgumentsAreNamed) {
  const auto person = simulatedPeople(1)[0];
  EXPECT_THROW(walkingSubject(person, 0, 0), std::invalid_argument);
  EXPECT_THROW(walkingSubject(person, 5, 0), std::invalid_argument);
  EXPECT_THROW(walkingSubject(person, 1, -1), std::invalid_argument);
  EXPECT_THROW(simulatedPeople(-1), std::invalid_argument);
}

}  // namespace
}  // namespace body_gait_model::eval
