// Cross-walk identification (cross_walk.h), on the evaluation's identifyProbes (one gallery and
// matcher path for every protocol).
#include <body_gait_id/eval/cross_walk.h>
#include <body_gait_id/eval/gait_id_evaluation.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace body_gait_id::eval {

CrossWalkResult identifyAcrossWalks(const std::vector<WalkModels>& walks, FeatureSet set,
                                    View view) {
  // People in order of first appearance, each with its walks in input order: fitted[person][t].
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
  FittedWalks fitted(people.size(),
                     std::vector<std::optional<body_gait_model::RepresentativePoses>>(rounds));
  auto walkName = [&](size_t person, size_t trial) {
    const auto& list = walks_of[people[person]];
    return trial < list.size() ? list[trial]->walk : std::string();
  };
  for (size_t person = 0; person < people.size(); ++person)
    for (size_t t = 0; t < walks_of[people[person]].size(); ++t)
      fitted[person][t] = walks_of[people[person]][t]->poses;

  const FeatureRow row{"cross-walk", view, set, std::nullopt};
  CrossWalkResult result;
  std::vector<ProbeResult> probes;
  for (size_t gallery = 0; gallery < rounds; ++gallery) {
    std::vector<std::string> gallery_walks;
    for (size_t person = 0; person < people.size(); ++person)
      if (!walkName(person, gallery).empty()) gallery_walks.push_back(walkName(person, gallery));
    for (size_t probe = 0; probe < rounds; ++probe) {
      if (probe == gallery) continue;
      const ProbeSet set_of_round = identifyProbes(fitted, row, int(gallery), int(probe),
                                                   int(people.size()), ProbeFrames::kAll);
      // One entry per probed walk: its frames right and the person most of them chose.
      std::map<std::int64_t, std::vector<int>> votes;  // true subject -> votes per person
      std::map<std::int64_t, int> right;
      for (const ProbeResult& p : set_of_round.probes) {
        std::vector<int>& v = votes[p.true_subject];
        v.resize(people.size(), 0);
        const std::int64_t chosen = p.candidates.front().subject_id;
        ++v[chosen - 1];  // subject ids are person + 1
        right[p.true_subject] += chosen == p.true_subject;
        probes.push_back(p);
      }
      for (const auto& [subject, v] : votes) {
        const size_t person = size_t(subject - 1);
        WalkIdentification identified;
        identified.probe_walk = walkName(person, probe);
        identified.person = people[person];
        identified.gallery_walks = gallery_walks;
        identified.frames_right = right[subject];
        identified.voted_person = people[std::max_element(v.begin(), v.end()) - v.begin()];
        result.walks_right += identified.voted_person == identified.person;
        result.walks.push_back(identified);
      }
    }
  }
  result.metrics = evaluateRecognition(probes);
  return result;
}

}  // namespace body_gait_id::eval
