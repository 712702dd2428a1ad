// Enrolment poses of thesis 5.8.3 from body_gait_model's gait-cycle reconstruction.
#include <body_gait_id/enrollment.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace body_gait_id {

std::vector<PoseRecord> trainingPoses(const body_gait_model::RepresentativePoses& s) {
  std::vector<PoseRecord> poses;
  poses.reserve(kTrainingPoses);
  const body_gait_model::GaitSet sets[kTrainingSequences] = {body_gait_model::GaitSet::kEta1,
                                                             body_gait_model::GaitSet::kEta2};
  for (int sequence = 0; sequence < kTrainingSequences; ++sequence) {
    const body_gait_model::GaitCycle cycle =
        body_gait_model::reconstructGaitCycle(body_gait_model::gaitSet(s, sets[sequence]));
    for (std::size_t f = 0; f < cycle.frames.size(); ++f)
      poses.push_back({0, sequence, static_cast<int>(f) + 1, cycle.frames[f]});
  }
  return poses;
}

body_gait_model::RepresentativePoses withMedianBody(const body_gait_model::RepresentativePoses& s) {
  body_gait_model::RepresentativePoses out = s;
  // Sets one body measure (picked by `get`) of every pose to the median of the four.
  const auto median = [&out](auto get) {
    std::array<double, 4> v;
    for (int i = 0; i < 4; ++i) v[i] = get(out[i]);
    std::sort(v.begin(), v.end());
    for (body_gait_model::BodyModel& pose : out) get(pose) = (v[1] + v[2]) / 2;
  };
  for (int k = 0; k < body_gait_model::kSegmentCount; ++k) {
    median([k](body_gait_model::BodyModel& m) -> double& { return m.r[k]; });
    median([k](body_gait_model::BodyModel& m) -> double& { return m.shape.proximal_radius[k]; });
    median([k](body_gait_model::BodyModel& m) -> double& { return m.shape.distal_radius[k]; });
  }
  for (const auto& placement : body_gait_model::kJointPlacements)
    median([&placement](body_gait_model::BodyModel& m) -> double& {
      return m.shape.*placement.field;
    });
  return out;
}

body_gait_model::RepresentativePoses representativePoses(
    const std::vector<body_gait_model::BodyModel>& s) {
  if (s.size() != 4)
    throw std::invalid_argument(
        "enrolment needs exactly 4 representative poses s1..s4 (thesis "
        "5.3 order), got " +
        std::to_string(s.size()));
  return {s[0], s[1], s[2], s[3]};
}

}  // namespace body_gait_id
