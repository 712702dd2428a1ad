// Cross-walk identification (cross_walk.h).
#include <body_gait_id/eval/cross_walk.h>
#include <body_gait_id/matcher.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace body_gait_id::eval {

CrossWalkResult identifyAcrossWalks(const std::vector<WalkModels>& walks, FeatureSet set,
                                    View view) {
  // People in order of first appearance, each with its walks in input order.
  std::vector<std::string> people;
  std::map<std::string, std::vector<const WalkModels*>> walks_of;
  for (const WalkModels& walk : walks) {
    if (!walks_of.count(walk.person)) people.push_back(walk.person);
    walks_of[walk.person].push_back(&walk);
  }
  if (people.size() < 2)
    throw std::invalid_argument("cross-walk identification needs at least 2 people, got " +
                                std::to_string(people.size()));
  size_t rounds = 0;
  for (const auto& [person, list] : walks_of) {
    if (list.size() < 2)
      throw std::invalid_argument("cross-walk identification: person '" + person +
                                  "' has 1 walk; every person needs 2 or more (gallery + probe)");
    rounds = std::max(rounds, list.size());
  }

  CrossWalkResult result;
  std::vector<ProbeResult> probes;
  for (size_t round = 0; round < rounds; ++round) {
    std::vector<GalleryPose> gallery;
    std::vector<std::string> gallery_walks;
    for (size_t id = 0; id < people.size(); ++id) {
      const auto& list = walks_of[people[id]];
      const WalkModels& enrolled = *list[round % list.size()];
      gallery_walks.push_back(enrolled.walk);
      const body_gait::GaitSet kTraining[] = {body_gait::GaitSet::kEta1, body_gait::GaitSet::kEta2};
      for (int sequence = 0; sequence < 2; ++sequence) {
        const body_gait::GaitCycle cycle = body_gait::reconstructGaitCycle(
            body_gait::gaitSet(enrolled.poses, kTraining[sequence]));
        for (int f = 0; f < body_gait::kGaitCycleFrames; ++f)
          gallery.push_back(
              {std::int64_t(id), sequence, f + 1, gaitFeatures(cycle.frames[f], view)});
      }
    }
    const Matcher matcher(gallery, set);
    for (size_t id = 0; id < people.size(); ++id) {
      const auto& list = walks_of[people[id]];
      for (size_t w = 0; w < list.size(); ++w) {
        if (w == round % list.size()) continue;
        WalkIdentification identified;
        identified.probe_walk = list[w]->walk;
        identified.person = people[id];
        identified.gallery_walks = gallery_walks;
        std::vector<int> votes(people.size(), 0);
        const body_gait::GaitCycle cycle = body_gait::reconstructGaitCycle(
            body_gait::gaitSet(list[w]->poses, body_gait::GaitSet::kEta3));
        for (int f = 0; f < body_gait::kGaitCycleFrames; ++f) {
          ProbeResult probe;
          probe.true_subject = std::int64_t(id);
          probe.true_frame = f + 1;
          for (const Match& match : matcher.rankSubjects(gaitFeatures(cycle.frames[f], view)))
            probe.candidates.push_back({match.subject_id, match.frame, match.score});
          ++votes[probe.candidates.front().subject_id];
          identified.frames_right += probe.candidates.front().subject_id == std::int64_t(id);
          probes.push_back(probe);
        }
        identified.voted_person =
            people[std::max_element(votes.begin(), votes.end()) - votes.begin()];
        result.walks_right += identified.voted_person == identified.person;
        result.walks.push_back(identified);
      }
    }
  }
  result.metrics = evaluateRecognition(probes);
  return result;
}

}  // namespace body_gait_id::eval
