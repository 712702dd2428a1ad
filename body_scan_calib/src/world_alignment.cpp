#include <body_scan_calib/world_alignment.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>

namespace body_scan_calib {
namespace {

// Plain least squares of eq 4.1 over all the given points.
AffineFit fitLeastSquares(const std::vector<Eigen::Vector3d>& camera_points,
                          const std::vector<Eigen::Vector3d>& world_points) {
  const size_t n = camera_points.size();
  if (n < 4)
    throw WorldAlignmentError("world alignment: " + std::to_string(n) +
                              " calibration points; eq 4.1 needs at least 4 (move the pair or "
                              "the cylinder so that more of its grid is seen)");
  // Centre both sets for conditioning; each row of H_a is an independent linear least-squares
  // problem [M_c^T 1] h_i = w_i (eq 4.1).
  Eigen::Vector3d camera_mean = Eigen::Vector3d::Zero(), world_mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    camera_mean += camera_points[i];
    world_mean += world_points[i];
  }
  camera_mean /= n;
  world_mean /= n;
  Eigen::MatrixX3d centred_camera(n, 3), centred_world(n, 3);
  for (size_t i = 0; i < n; ++i) {
    centred_camera.row(i) = (camera_points[i] - camera_mean).transpose();
    centred_world.row(i) = (world_points[i] - world_mean).transpose();
  }
  // Thin U and V need a dynamic column count (Eigen asserts it in a build without NDEBUG).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Eigen::MatrixXd(centred_camera),
                                              Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::Vector3d spread = svd.singularValues() / std::sqrt(static_cast<double>(n));
  if (!(spread[2] > 1e-4))
    throw WorldAlignmentError(
        "world alignment: the calibration points lie on one plane or line (spread " +
        std::to_string(spread[2] * 1000) +
        " mm off it); the affine is undetermined: observe a curved part of the cylinder");
  const Eigen::Matrix3d linear_transposed = svd.solve(centred_world);  // A^T
  AffineFit fit;
  fit.affine.leftCols<3>() = linear_transposed.transpose();
  fit.affine.col(3) = world_mean - fit.affine.leftCols<3>() * camera_mean;
  try {
    fit.alignment = body_scan_driver::WorldAlignment::fromAffine(fit.affine);
  } catch (const std::invalid_argument& e) {
    throw WorldAlignmentError(e.what());
  }
  fit.points = static_cast<int>(n);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double residual =
        (fit.affine.leftCols<3>() * camera_points[i] + fit.affine.col(3) - world_points[i]).norm();
    sum += residual * residual;
    fit.max_m = std::max(fit.max_m, residual);
  }
  fit.rms_m = std::sqrt(sum / n);
  return fit;
}

}  // namespace

AffineFit fitWorldAffine(const std::vector<Eigen::Vector3d>& camera_points,
                         const std::vector<Eigen::Vector3d>& world_points,
                         double outlier_distance_m) {
  if (camera_points.size() != world_points.size())
    throw WorldAlignmentError("world alignment: " + std::to_string(camera_points.size()) +
                              " camera points but " + std::to_string(world_points.size()) +
                              " world points");
  std::vector<int> inliers(camera_points.size());
  for (size_t i = 0; i < inliers.size(); ++i) inliers[i] = static_cast<int>(i);
  std::vector<int> outliers;
  while (true) {
    std::vector<Eigen::Vector3d> camera, world;
    for (int i : inliers) {
      camera.push_back(camera_points[i]);
      world.push_back(world_points[i]);
    }
    AffineFit fit = fitLeastSquares(camera, world);
    // Drop the worst point while it is farther than outlier_distance_m (a misread marker or a
    // corner on a depth edge), one at a time: one gross error drags every residual with it.
    size_t worst = 0;
    double worst_residual = -1;
    for (size_t k = 0; k < camera.size(); ++k) {
      const double residual =
          (fit.affine.leftCols<3>() * camera[k] + fit.affine.col(3) - world[k]).norm();
      if (residual > worst_residual) worst_residual = residual, worst = k;
    }
    if (worst_residual <= outlier_distance_m) {
      std::sort(outliers.begin(), outliers.end());
      fit.outliers = outliers;
      return fit;
    }
    outliers.push_back(inliers[worst]);
    inliers.erase(inliers.begin() + worst);
    if (outliers.size() * 4 > camera_points.size())
      throw WorldAlignmentError(
          "world alignment: more than a quarter of the " + std::to_string(camera_points.size()) +
          " calibration points are farther than " + std::to_string(outlier_distance_m * 1000) +
          " mm from the fitted affine; check the pair calibration and the cylinder's layout");
  }
}

SharedPointAccuracy evaluateSharedPoints(const std::vector<AlignedPair>& pairs) {
  SharedPointAccuracy accuracy;
  std::set<int> shared;
  std::vector<double> distances;
  for (size_t a = 0; a < pairs.size(); ++a)
    for (size_t b = a + 1; b < pairs.size(); ++b) {
      SharedPointAccuracy::PairOfPairs combination{pairs[a].pair_id, pairs[b].pair_id, 0, 0};
      for (const auto& [id, point_a] : pairs[a].camera_points) {
        const auto found = pairs[b].camera_points.find(id);
        if (found == pairs[b].camera_points.end()) continue;
        // Eq 4.2: the same calibration point mapped to the world by each pair.
        const double distance =
            (pairs[a].alignment.toWorld(point_a) - pairs[b].alignment.toWorld(found->second))
                .norm();
        distances.push_back(distance);
        shared.insert(id);
        ++combination.points;
        combination.mean_m += distance;
      }
      if (combination.points > 0) {
        combination.mean_m /= combination.points;
        accuracy.by_pairs.push_back(combination);
      }
    }
  accuracy.shared_points = static_cast<int>(shared.size());
  accuracy.comparisons = static_cast<int>(distances.size());
  if (distances.empty()) return accuracy;
  double sum = 0, squares = 0;
  for (double d : distances) {
    sum += d;
    squares += d * d;
    accuracy.max_m = std::max(accuracy.max_m, d);
  }
  accuracy.mean_m = sum / distances.size();
  accuracy.std_m =
      distances.size() > 1
          ? std::sqrt(std::max(0.0, (squares - sum * accuracy.mean_m) / (distances.size() - 1)))
          : 0.0;
  return accuracy;
}

}  // namespace body_scan_calib
