#include <body_gait_id/walk_identification.h>

#include <algorithm>
#include <map>

namespace body_gait_id {

std::vector<WalkMatch> rankWalk(const Matcher& matcher,
                                const body_gait_model::RepresentativePoses& s, View view) {
  const body_gait_model::GaitCycle cycle = body_gait_model::reconstructGaitCycle(
      body_gait_model::gaitSet(s, body_gait_model::GaitSet::kEta3));
  std::map<std::int64_t, double> sum;
  for (const body_gait_model::BodyModel& frame : cycle.frames)
    for (const Match& match : matcher.rankSubjects(gaitFeatures(frame, view)))
      sum[match.subject_id] += match.score;
  std::vector<WalkMatch> ranked;
  for (const auto& [subject, total] : sum)
    ranked.push_back({subject, total / static_cast<double>(cycle.frames.size())});
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const WalkMatch& a, const WalkMatch& b) { return a.score < b.score; });
  return ranked;
}

}  // namespace body_gait_id
