// Cross-walk identification: people recorded walking more than once (e.g. motion
// capture, several walks per person), one walk in the gallery and another as the probe, with the
// thesis's protocol (5.8.3): the gallery holds each person's training cycles eta1 and eta2 (2 x 20
// poses reconstructed from the 4 fitted representative poses, eqs 5.11-5.13), the probe walk's
// testing cycle eta3 is identified frame by frame (eq 5.16).
#pragma once

#include <body_gait_id/eval/recognition_metrics.h>
#include <body_gait_id/gait_features.h>
#include <body_gait_model/gait_cycle.h>

#include <string>
#include <vector>

namespace body_gait_id::eval {

// The 4 fitted representative poses (s1..s4, thesis 5.3 order) of one walk of one person.
struct WalkModels {
  std::string person, walk;
  body_gait_model::RepresentativePoses poses;
};

struct WalkIdentification {
  std::string probe_walk, person;
  std::vector<std::string> gallery_walks;  // one per enrolled person
  int frames_right = 0;                    // of the 20 testing frames, rank-1 correct
  std::string voted_person;                // the person most of the 20 frames chose
};

struct CrossWalkResult {
  RecognitionMetrics metrics;  // over every probe frame of every round
  std::vector<WalkIdentification> walks;
  int walks_right = 0;  // probe walks whose vote is the true person
};

// Rounds k = 0, 1, ...: the gallery is walk k of every person who has one, the probes are every
// other walk (identifyProbes of gait_id_evaluation.h, all 20 frames of eta3). A walk whose fits
// give no gait cycle (no forward stride) is left out with its person for that round. Throws
// std::invalid_argument when a person has fewer than 2 walks or fewer than 2 people are given.
CrossWalkResult identifyAcrossWalks(const std::vector<WalkModels>& walks, FeatureSet set,
                                    View view = View::k3D);

}  // namespace body_gait_id::eval
