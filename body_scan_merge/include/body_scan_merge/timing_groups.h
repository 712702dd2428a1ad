// Timing groups of a calibrated rig (thesis 4.3, Fig 4.7): pairs whose light reaches another
// pair's view must not project at the same time, so the ScanCoordinator triggers the rig in
// groups; as few groups as possible keeps the acquisition short (groups x GroupTiming).
// ROS-agnostic: from each pair's calibration (camera + stripe planes) and world pose.
#pragma once

#include <body_scan_driver/pair_model.h>

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

namespace body_scan_merge {

struct PairGeometry {
  std::string pair_id;
  body_scan_driver::PairCalibration calibration;  // camera and stripe planes in the camera frame
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
};

// A vertical elliptic cylinder of the subject proxy (world frame, metres).
struct ProxyCylinder {
  double center_x = 0, center_y = 0;
  double semi_axis_x = 0.1, semi_axis_y = 0.1;
  double min_z = 0, max_z = 1;
};

// The surfaces the light can fall on: a proxy of a subject standing at the origin facing +x
// (DESIGN.md section 3), sampled every `spacing` on its sides and tops. A point counts as lit (seen) when it faces
// the projector (camera), lies in its sweep (image) and no other part is in between; light
// reaching the inner side of an arm or leg through a gap counts. Default: an adult envelope
// (torso, arms held a little away, legs, head), larger than most subjects, and the floor around
// it: a floor pixel decoded from two pairs' mixed stripes triangulates to a wrong depth that
// can land inside the scan volume (a layer of false points 0.2 m above the floor, measured).
struct InterferenceProxy {
  std::vector<ProxyCylinder> parts = {{0, 0, 0.15, 0.21, 0.80, 1.50},      // torso
                                      {0, 0.31, 0.06, 0.06, 0.75, 1.45},   // left arm
                                      {0, -0.31, 0.06, 0.06, 0.75, 1.45},  // right arm
                                      {0, 0.10, 0.08, 0.08, 0.0, 0.85},    // left leg
                                      {0, -0.10, 0.08, 0.08, 0.0, 0.85},   // right leg
                                      {0, 0, 0.10, 0.09, 1.45, 1.95}};     // neck and head
  double spacing = 0.01;                                                   // m between samples
  double floor_radius = 1.5;  // m of floor around the subject; 0 = no floor
  double image_margin = 20;   // px: a point this close outside an image still counts as seen
  // m: the lit region grows this far beyond the first and last calibrated stripe planes (the
  // calibration may miss the outermost stripes; conservative).
  double light_margin = 0.02;
  // Overlaps smaller than this (m^2) are tolerated: grazing light through the narrow gap between
  // an arm and the torso reaches a few square centimetres that pairs on opposite poles both see.
  double min_overlap_area = 0.0;
};

struct TimingPlan {
  std::vector<std::vector<std::string>> groups;                // in trigger order
  std::vector<std::pair<std::string, std::string>> conflicts;  // (lighting pair, seeing pair)
};

// conflicts[i][j]: pair i's light reaches a proxy point that pair j's camera sees (i != j).
std::vector<std::vector<bool>> lightConflicts(const std::vector<PairGeometry>& pairs,
                                              const InterferenceProxy& proxy = {});

// The fraction of the proxy's body surface (its parts, not the floor) that at least one pair
// both lights and sees (the lit-and-seen tests of lightConflicts): a coarse coverage figure for
// comparing rig layouts before simulating them (eval/rig_design.h).
double proxyCoverage(const std::vector<PairGeometry>& pairs, const InterferenceProxy& proxy = {});

// A minimum colouring of the undirected conflict graph (exact), the most balanced one among
// the minimum colourings (least sum of squared group sizes). Deterministic: pairs keep their
// input order inside a group and groups are ordered by their first pair.
std::vector<std::vector<int>> minimumGroups(const std::vector<std::vector<bool>>& conflicts);

// How long one timing group takes on the hardware (thesis sec. 4.2.4: 0.5 s): the pairs of a
// group show their pattern frames together, each frame held for its camera frame plus the
// `settle_frames` the sequencer discards after a pattern change (hw/pattern_sequencer.h).
struct GroupTiming {
  int pattern_frames = 18;  // PatternLayout::frameCount(): 8 bits with inverse frames
  double camera_fps = 36;   // the thesis's 18 frames in 0.5 s
  int settle_frames = 0;    // a synchronized projector needs none
  // Throws std::invalid_argument naming the bad value.
  double seconds() const;
};

TimingPlan planTimingGroups(const std::vector<PairGeometry>& pairs,
                            const InterferenceProxy& proxy = {});

}  // namespace body_scan_merge
