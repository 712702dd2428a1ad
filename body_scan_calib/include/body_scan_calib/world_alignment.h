// World alignment of projector-camera pairs (thesis sec. 4.3.2): the 12-parameter affine of
// eq 4.1 per pair by least squares, its polar split into a rigid part and a residual linear part
// (body_scan_driver::WorldAlignment), and the accuracy E_h of eq 4.2 on points seen by two pairs.
#pragma once

#include <body_scan_driver/pair_model.h>

#include <Eigen/Core>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_scan_calib {

struct WorldAlignmentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct AffineFit {
  Eigen::Matrix<double, 3, 4> affine;          // H_a's top three rows
  body_scan_driver::WorldAlignment alignment;  // its polar split
  int points = 0;                              // used in the fit
  double rms_m = 0, max_m = 0;                 // residuals |H_a M_c - M_w| of those points
  std::vector<int> outliers;                   // indices of the input points left out, ascending
};

// Least-squares H_a from >= 4 correspondences camera point -> world point that do not lie on
// one plane. Points farther than outlier_distance_m from the fit are left out one at a time
// (worst first) and the rest refitted. Throws WorldAlignmentError naming the problem and the
// fix (too few points, coplanar points, more than a quarter outliers).
AffineFit fitWorldAffine(const std::vector<Eigen::Vector3d>& camera_points,
                         const std::vector<Eigen::Vector3d>& world_points,
                         double outlier_distance_m = 0.005);

// One pair's aligned observations: grid point id -> camera-frame point.
struct AlignedPair {
  std::string pair_id;
  std::map<int, Eigen::Vector3d> camera_points;
  body_scan_driver::WorldAlignment alignment;
};

// E_h (eq 4.2) over every grid point seen by two pairs: for each such point and each two pairs
// that saw it, |M_w^l - M_w^r| with M_w from each pair's alignment.
struct SharedPointAccuracy {
  int shared_points = 0;  // distinct grid points seen by two or more pairs (N_h)
  int comparisons = 0;    // pair combinations over those points
  double mean_m = 0, std_m = 0, max_m = 0;
  struct PairOfPairs {
    std::string first, second;
    int points = 0;
    double mean_m = 0;
  };
  std::vector<PairOfPairs> by_pairs;
};
SharedPointAccuracy evaluateSharedPoints(const std::vector<AlignedPair>& pairs);

}  // namespace body_scan_calib
