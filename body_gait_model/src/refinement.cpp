// Whole-model refinement with Ceres: one cost function holds all sampled points; its Jacobian
// is taken by forward differences over the 40 pose parameters (one forward kinematics per
// parameter), far cheaper than differentiating every residual separately.
#include <body_gait_model/refinement.h>
#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace body_gait_model {
namespace {

struct AssignedPoint {
  Eigen::Vector3d point;
  int segment;
};

bool isTerminal(int segment) {
  return segment == kHead || segment == kRightLowerArm || segment == kLeftLowerArm ||
         segment == kRightLowerLeg || segment == kLeftLowerLeg;
}

// The hips (lower torso's length) and knees (upper legs' lengths) stay where the direct fit put
// them: the hips lie inside the pelvis and a straight leg's knee anywhere along its line fits
// the surface equally well, so the surface distance has nothing to place them with. Measured
// on 10 subjects x 4 poses: segment-length error 4.6 -> 4.2 %, hips 33 -> 28 mm.
// In a walk the thighs may change: a knee bent in one scan shows where it is in all.
// The neck keeps its length too: its short surface barely shows where it ends, and refined in
// a walk it moved with the rest of the chain (CMU person 07's two walks: 98 and 82 mm, 95 and
// 90 held; identify_walks matched them again).
using HeldLengths = std::array<bool, kSegmentCount>;
HeldLengths heldLengths(bool hold_right_thigh, bool hold_left_thigh) {
  HeldLengths held{};
  for (int segment = 0; segment < kSegmentCount; ++segment)
    held[segment] = isTerminal(segment) || segment == kLowerTorso || segment == kNeck ||
                    (hold_right_thigh && segment == kRightUpperLeg) ||
                    (hold_left_thigh && segment == kLeftUpperLeg);
  return held;
}

BodyModel withParameters(const BodyModel& base, const double* p, const double* q, const double* r,
                         const HeldLengths& held) {
  BodyModel model = base;
  model.p = Eigen::Map<const PoseVector>(p);
  model.q = Eigen::Map<const JointAngles>(q);
  // Free ends (head, lower arms, lower legs) keep their lengths: a surface distance does not pull
  // an overlong cylinder back, so they would grow into the hands, feet and hair. The legs' other
  // lengths are held too (heldLength).
  for (int segment = 0; segment < kSegmentCount; ++segment)
    if (!held[segment]) model.r[segment] = r[segment];
  return model;
}

void residualsOf(const BodyModel& model, const std::vector<AssignedPoint>& points,
                 double* residuals) {
  const SegmentSurfaces surfaces = segmentSurfaces(forwardKinematics(model));
  for (size_t i = 0; i < points.size(); ++i)
    residuals[i] = surfaces[points[i].segment].distance(points[i].point);
}

// True if segment lies in the subtree of root (root included).
bool inSubtree(int segment, int root) {
  for (int s = segment; s != kWholeBody; s = segmentInfo(s).parent)
    if (s == root) return true;
  return false;
}

// The segments whose surface moves with parameter k of a block (p: all; q and r: the joint's or
// segment's subtree). Residuals of the others have zero derivative and are not recomputed.
std::array<bool, kSegmentCount> movedBy(int block, int k) {
  std::array<bool, kSegmentCount> moved{};
  for (int s = 0; s < kSegmentCount; ++s) {
    if (block == 0) {
      moved[s] = true;
    } else if (block == 1) {
      for (int joint = 0; joint < kSegmentCount; ++joint)
        if (jointAngleIndex(joint) >= 0 &&
            (k == jointAngleIndex(joint) || k == jointAngleIndex(joint) + 1))
          moved[s] = inSubtree(s, joint);
    } else {
      moved[s] = inSubtree(s, k);
    }
  }
  return moved;
}

class SurfaceDistanceCost : public ceres::CostFunction {
 public:
  SurfaceDistanceCost(const BodyModel& base, const std::vector<AssignedPoint>& points,
                      const HeldLengths& held)
      : base_(base), points_(points), held_(held) {
    set_num_residuals(int(points.size()));
    mutable_parameter_block_sizes()->push_back(6);
    mutable_parameter_block_sizes()->push_back(22);
    mutable_parameter_block_sizes()->push_back(12);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const BodyModel model =
        withParameters(base_, parameters[0], parameters[1], parameters[2], held_);
    residualsOf(model, points_, residuals);
    if (!jacobians) return true;
    constexpr double kStep = 1e-6;
    const int sizes[3] = {6, 22, 12};
    for (int block = 0; block < 3; ++block) {
      if (!jacobians[block]) continue;
      for (int k = 0; k < sizes[block]; ++k) {
        if (block == 2 && held_[k]) {  // a held length: no effect on any residual
          for (size_t i = 0; i < points_.size(); ++i) jacobians[block][i * sizes[block] + k] = 0;
          continue;
        }
        double copy[3][22];
        for (int b = 0; b < 3; ++b) std::copy(parameters[b], parameters[b] + sizes[b], copy[b]);
        copy[block][k] += kStep;
        const SegmentSurfaces shifted = segmentSurfaces(
            forwardKinematics(withParameters(base_, copy[0], copy[1], copy[2], held_)));
        const std::array<bool, kSegmentCount> moved = movedBy(block, k);
        for (size_t i = 0; i < points_.size(); ++i) {
          const int segment = points_[i].segment;
          jacobians[block][i * sizes[block] + k] =
              moved[segment] ? (shifted[segment].distance(points_[i].point) - residuals[i]) / kStep
                             : 0.0;
        }
      }
    }
    return true;
  }

 private:
  BodyModel base_;
  const std::vector<AssignedPoint>& points_;
  HeldLengths held_;
};

std::vector<AssignedPoint> assign(const BodyModel& model, const Cloud& sample) {
  const SegmentSurfaces surfaces = segmentSurfaces(forwardKinematics(model));
  std::vector<AssignedPoint> assigned;
  for (const auto& point : sample) {
    const int best_segment = nearestSegment(surfaces, point).segment;
    assigned.push_back({point, best_segment});
  }
  return assigned;
}

double rms(const BodyModel& model, const std::vector<AssignedPoint>& points) {
  std::vector<double> residuals(points.size());
  residualsOf(model, points, residuals.data());
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return points.empty() ? 0.0 : std::sqrt(sum / points.size());
}

}  // namespace

RefinementReport refineModel(BodyModel& model, const Cloud& cloud, const RefinementOptions& options,
                             const JointLimitSet& joint_limits) {
  std::vector<BodyModel> models{model};
  const RefinementReport report = refineWalk(models, {&cloud}, options, joint_limits);
  model = models.front();
  return report;
}

RefinementReport refineWalk(std::vector<BodyModel>& models, const std::vector<const Cloud*>& clouds,
                            const RefinementOptions& options, const JointLimitSet& joint_limits) {
  RefinementReport report;
  if (models.size() != clouds.size())
    throw std::invalid_argument("refineWalk: " + std::to_string(models.size()) + " models for " +
                                std::to_string(clouds.size()) + " clouds; pass one model per scan");
  if (models.empty() || options.sample_points < 1) return report;
  const size_t scans = models.size();
  std::vector<Cloud> samples(scans);
  size_t total_points = 0;
  for (size_t i = 0; i < scans; ++i) {
    const Cloud& cloud = *clouds[i];
    const size_t stride = std::max<size_t>(1, cloud.size() / options.sample_points);
    for (size_t k = 0; k < cloud.size(); k += stride) samples[i].push_back(cloud[k]);
    total_points += samples[i].size();
  }
  if (total_points == 0) return report;
  auto walkRms = [&] {
    double sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < scans; ++i) {
      const double value = rms(models[i], assign(models[i], samples[i]));
      sum += value * value * samples[i].size();
      count += samples[i].size();
    }
    return count > 0 ? std::sqrt(sum / count) : 0.0;
  };
  report.initial_rms = walkRms();
  // The lengths (and the shape) are the first model's: one body in every scan.
  const SegmentLengths initial_lengths = models.front().r;
  const bool hold_thighs = scans == 1 || options.hold_thighs_in_walks;
  const HeldLengths held =
      heldLengths(hold_thighs || options.straight_knee[0], hold_thighs || options.straight_knee[1]);
  for (int round = 0; round < options.rounds; ++round) {
    std::vector<std::vector<AssignedPoint>> assigned(scans);
    std::vector<std::array<double, 6>> p(scans);
    std::vector<std::array<double, 22>> q(scans);
    double r[12];
    Eigen::Map<SegmentLengths>{r} = models.front().r;
    ceres::Problem problem;
    // Lengths within +-max_length_change of the direct fit's (RefinementOptions).
    for (int i = 0; i < 12; ++i) {
      const double low =
          std::max(options.min_length, (1 - options.max_length_change) * initial_lengths[i]);
      const double high = std::max(low, (1 + options.max_length_change) * initial_lengths[i]);
      r[i] = std::clamp(r[i], low, high);
    }
    for (size_t i = 0; i < scans; ++i) {
      if (samples[i].empty()) continue;
      assigned[i] = assign(models[i], samples[i]);
      Eigen::Map<PoseVector>{p[i].data()} = models[i].p;
      Eigen::Map<JointAngles>{q[i].data()} = models[i].q;
      problem.AddResidualBlock(new SurfaceDistanceCost(models[i], assigned[i], held),
                               new ceres::HuberLoss(options.huber_scale), p[i].data(), q[i].data(),
                               r);
      // The whole body's tilt (theta_x, theta_z of p) stays the direct fit's (the body axes):
      // every segment hangs from the two torsos, whose joints turn about the same axes, so the
      // surface cannot tell a tilted root with counter-tilted torsos from an upright one. Left
      // free, the solver drifted along that valley: the torsos' theta_z 0.8 rad SD on the mesh
      // people of the full scanner (truth: 0), 0.54 rad between a person's two walks.
      problem.SetManifold(p[i].data(), new ceres::SubsetManifold(6, {3, 5}));
      // Each angle within its joint's limits; an axis whose limits are equal (the lower torso's
      // theta_z in the walking limits) is held at that value.
      std::vector<int> held_angles;
      for (int segment = 0; segment < kSegmentCount; ++segment) {
        const int index = jointAngleIndex(segment);
        if (index < 0) continue;
        const JointLimits& limits = joint_limits[segment];
        for (const auto& [k, low, high] : {std::tuple{index, limits.x_min, limits.x_max},
                                           std::tuple{index + 1, limits.z_min, limits.z_max}}) {
          if (low == high) {
            q[i][k] = low;
            held_angles.push_back(k);
            continue;
          }
          problem.SetParameterLowerBound(q[i].data(), k, low);
          problem.SetParameterUpperBound(q[i].data(), k, high);
        }
      }
      if (!held_angles.empty())
        problem.SetManifold(q[i].data(), new ceres::SubsetManifold(22, held_angles));
    }
    for (int i = 0; i < 12; ++i) {
      const double low =
          std::max(options.min_length, (1 - options.max_length_change) * initial_lengths[i]);
      const double high = std::max(low, (1 + options.max_length_change) * initial_lengths[i]);
      problem.SetParameterLowerBound(r, i, low);
      problem.SetParameterUpperBound(r, i, high + 1e-9);
    }
    ceres::Solver::Options solver;
    solver.max_num_iterations = options.max_iterations;
    // One scan: a small dense problem. A walk: each scan's rows touch only its own pose and the
    // shared lengths, so the normal equations are sparse (dense QR of 4 scans took ~1 s).
    solver.linear_solver_type = ceres::DENSE_QR;
    if (scans > 1 && ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE)) {
      solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      solver.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
    } else if (scans > 1) {
      solver.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    }
    solver.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    report.iterations += int(summary.iterations.size());
    for (size_t i = 0; i < scans; ++i)
      models[i] = samples[i].empty()
                      ? withParameters(models[i], models[i].p.data(), models[i].q.data(), r, held)
                      : withParameters(models[i], p[i].data(), q[i].data(), r, held);
  }
  report.final_rms = walkRms();
  return report;
}

}  // namespace body_gait_model
