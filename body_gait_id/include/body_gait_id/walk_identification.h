// Identification of a walk (thesis 5.8.3-5.8.4): the gait cycle reconstructed from the walk's 4
// fitted representative poses s1..s4 (the testing set eta3, eqs 5.11-5.13) is identified frame
// by frame against the gallery (eq 5.16), and each subject's walk score is the mean over the 20
// frames of its nearest pose's distance: one decision per walk, which separates people far
// better than one scan (docs/RESULTS.md, "Recognition").
#pragma once

#include <body_gait_id/matcher.h>
#include <body_gait_model/gait_cycle.h>

#include <vector>

namespace body_gait_id {

// Open-set threshold of a walk's score with the recognition.launch defaults (dynamic + static +
// shape, the full scanner's noise weights, median body): the threshold at FNIR 5 % of 50
// simulated mesh-body people's walks on the full scanner, walks fitted together
// (evaluate_gait_id --per-walk, docs/RESULTS.md). gait_id_node's and gait_gallery's default.
constexpr double kDefaultWalkAcceptThreshold = 12.7;

struct WalkMatch {
  std::int64_t subject_id;
  double score;  // mean over the cycle's frames of the subject's nearest-pose distance
};

// Every enrolled subject, best (lowest mean score) first. Throws std::invalid_argument when the
// poses give no gait cycle (no forward stride, reconstructGaitCycle) or the view's features do
// not match the gallery's.
std::vector<WalkMatch> rankWalk(const Matcher& matcher,
                                const body_gait_model::RepresentativePoses& s,
                                View view = View::k3D);

}  // namespace body_gait_id
