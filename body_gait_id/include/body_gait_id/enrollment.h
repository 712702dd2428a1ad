// Enrolment of a person (thesis 5.8.3): the 4 fitted representative poses s1..s4 give two
// training gait sequences, eta1 = {s1, sb2, s3, sb4} and eta2 = {sb1, s2, sb3, s4} (sb = the
// symmetric pose), each reconstructed to a 20-frame cycle (eqs 5.11-5.13): 40 gallery poses.
#pragma once

#include <body_gait_id/gallery_database.h>
#include <body_gait_model/gait_cycle.h>

#include <vector>

namespace body_gait_id {

constexpr int kTrainingSequences = 2;  // eta1 (sequence 0), eta2 (sequence 1)
constexpr int kTrainingPoses = kTrainingSequences * body_gait_model::kGaitCycleFrames;  // 40

// The 40 training poses (subject_id left 0): sequence 0 = eta1, 1 = eta2, frames 1..20.
std::vector<PoseRecord> trainingPoses(const body_gait_model::RepresentativePoses& s);

// A walk's body measured robustly (beyond eq 5.13's mean): every pose's r and body shape
// replaced by the component-wise median over the four fits (median of 4 = mean of the middle
// two), so the cycle's mean of the four is that median and one bad fit of a segment cannot
// pull it. Joint angles and p stay. Cross-walk, 50 people: rank-1 up 2-5 points
// (docs/RESULTS.md).
body_gait_model::RepresentativePoses withMedianBody(const body_gait_model::RepresentativePoses& s);

// Four models as s1..s4; throws std::invalid_argument naming the count when it is not 4.
body_gait_model::RepresentativePoses representativePoses(
    const std::vector<body_gait_model::BodyModel>& s);

}  // namespace body_gait_id
