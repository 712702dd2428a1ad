#include <body_scan_calib/joint_refinement.h>
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>
#include <cmath>
#include <sstream>

namespace body_scan_calib {
namespace {

// Intrinsics block: alpha, beta, gamma, u0, v0, k1, k2 (eqs 3.1, 3.3).
template <typename T>
void distort(const T* intrinsics, const T& x, const T& y, T* pixel) {
  const T r2 = x * x + y * y;
  const T factor = T(1) + intrinsics[5] * r2 + intrinsics[6] * r2 * r2;
  const T xd = x * factor, yd = y * factor;
  pixel[0] = intrinsics[0] * xd + intrinsics[2] * yd + intrinsics[3];
  pixel[1] = intrinsics[1] * yd + intrinsics[4];
}

struct CornerResidual {
  Eigen::Vector3d board_point;
  Eigen::Vector2d observed;
  double weight;
  template <typename T>
  bool operator()(const T* intrinsics, const T* pose, T* residual) const {
    const T point[3] = {T(board_point.x()), T(board_point.y()), T(board_point.z())};
    T camera_point[3];
    ceres::AngleAxisRotatePoint(pose, point, camera_point);
    for (int i = 0; i < 3; ++i) camera_point[i] += pose[3 + i];
    T pixel[2];
    distort(intrinsics, camera_point[0] / camera_point[2], camera_point[1] / camera_point[2],
            pixel);
    residual[0] = weight * (pixel[0] - observed.x());
    residual[1] = weight * (pixel[1] - observed.y());
    return true;
  }
};

// A stripe-centre pixel lifted onto its board (eq 3.30 after undistortion) must lie on its
// stripe's plane.
struct StripePointResidual {
  Eigen::Vector2d pixel;
  double weight;
  template <typename T>
  bool operator()(const T* intrinsics, const T* pose, const T* plane, T* residual) const {
    const T yd = (T(pixel.y()) - intrinsics[4]) / intrinsics[1];
    const T xd = (T(pixel.x()) - intrinsics[3] - intrinsics[2] * yd) / intrinsics[0];
    T x = xd, y = yd;
    for (int iteration = 0; iteration < 12; ++iteration) {  // inverse of eq 3.3
      const T r2 = x * x + y * y;
      const T factor = T(1) + intrinsics[5] * r2 + intrinsics[6] * r2 * r2;
      x = xd / factor;
      y = yd / factor;
    }
    // Board normal r3 = R e_z and its point t: the ray (x, y, 1) meets it at scale s.
    const T unit_z[3] = {T(0), T(0), T(1)};
    T normal[3];
    ceres::AngleAxisRotatePoint(pose, unit_z, normal);
    const T s = (normal[0] * pose[3] + normal[1] * pose[4] + normal[2] * pose[5]) /
                (normal[0] * x + normal[1] * y + normal[2]);
    const T point[3] = {s * x, s * y, s};
    const T norm = ceres::sqrt(plane[0] * plane[0] + plane[1] * plane[1] + plane[2] * plane[2]);
    residual[0] = weight *
                  (plane[0] * point[0] + plane[1] * point[1] + plane[2] * point[2] + plane[3]) /
                  norm;
    return true;
  }
};

void toBlock(const Eigen::Isometry3d& pose, double* block) {
  const Eigen::AngleAxisd rotation(pose.linear());
  const Eigen::Vector3d axis = rotation.angle() * rotation.axis();
  for (int i = 0; i < 3; ++i) {
    block[i] = axis[i];
    block[3 + i] = pose.translation()[i];
  }
}

Eigen::Isometry3d fromBlock(const double* block) {
  const Eigen::Vector3d axis(block[0], block[1], block[2]);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (axis.norm() > 0) pose.linear() = Eigen::AngleAxisd(axis.norm(), axis.normalized()).matrix();
  pose.translation() = Eigen::Vector3d(block[3], block[4], block[5]);
  return pose;
}

}  // namespace

JointRefinementResult refineJointly(const JointRefinementInput& input) {
  if (!input.planes || input.board_to_camera.size() != input.corners.size())
    throw std::invalid_argument(
        "joint refinement needs the initial planes and one corner set per board pose");
  const ProjectorCalibrationResult& planes = *input.planes;
  const body_scan_driver::PinholeCamera& camera = input.camera;
  double intrinsics[7] = {camera.alpha, camera.beta, camera.gamma, camera.u0,
                          camera.v0,    camera.k1,   camera.k2};
  std::vector<std::array<double, 6>> poses(input.board_to_camera.size());
  for (size_t k = 0; k < poses.size(); ++k) toBlock(input.board_to_camera[k], poses[k].data());
  std::vector<Eigen::Vector4d> plane_blocks = planes.projector.planes;

  // Initial rms of both kinds of residual: their weights (noise levels).
  double corner_squared = 0;
  size_t corner_count = 0;
  for (size_t k = 0; k < poses.size(); ++k)
    for (size_t c = 0; c < input.corners[k].size(); ++c) {
      const Eigen::Vector2d projected =
          camera.project(input.board_to_camera[k] * input.board_points[c]);
      corner_squared += (projected - input.corners[k][c]).squaredNorm();
      corner_count += 2;
    }
  const double corner_sigma = std::max(1e-3, std::sqrt(corner_squared / corner_count));
  const double plane_sigma = std::max(1e-6, planes.rms_m);

  ceres::Problem problem;
  for (size_t k = 0; k < poses.size(); ++k)
    for (size_t c = 0; c < input.corners[k].size(); ++c)
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<CornerResidual, 2, 7, 6>(
              new CornerResidual{input.board_points[c], input.corners[k][c], 1.0 / corner_sigma}),
          nullptr, intrinsics, poses[k].data());
  // Inliers of the initial fits only (checker edges blur some), spread evenly.
  std::vector<size_t> inliers;
  for (size_t i = 0; i < planes.points.size(); ++i) {
    const int stripe = planes.point_stripes[i];
    const Eigen::Vector4d& plane = plane_blocks[stripe];
    // Planes of the smooth model (few poses) have no free per-stripe parameters here.
    if (!plane.allFinite() || planes.poses_per_stripe[stripe] < 3) continue;
    if (std::abs(plane.head<3>().dot(planes.points[i]) + plane[3]) <=
        3 * planes.rms_per_stripe_m[stripe])
      inliers.push_back(i);
  }
  const size_t step = std::max<size_t>(1, inliers.size() / std::max(1, input.max_stripe_points));
  // Neighbouring stripe points share their pose's error (decoding bias along a checker edge,
  // the board's print): they are not independent samples. With balance_groups their total
  // weight is capped at the corners' so that their count (hundreds to one) cannot outvote them.
  const size_t plane_points = (inliers.size() + step - 1) / step;
  const double plane_group_weight =
      input.balance_groups ? std::min(1.0, std::sqrt(static_cast<double>(corner_count) /
                                                     std::max<size_t>(1, plane_points)))
                           : 1.0;
  std::vector<char> plane_used(plane_blocks.size(), 0);
  double plane_squared_before = 0;
  size_t plane_count = 0;
  for (size_t n = 0; n < inliers.size(); n += step) {
    const size_t i = inliers[n];
    const int stripe = planes.point_stripes[i];
    const double distance =
        plane_blocks[stripe].head<3>().dot(planes.points[i]) + plane_blocks[stripe][3];
    plane_squared_before += distance * distance;
    ++plane_count;
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<StripePointResidual, 1, 7, 6, 4>(
            new StripePointResidual{planes.point_pixels[i], plane_group_weight / plane_sigma}),
        new ceres::HuberLoss(3.0 * plane_group_weight), intrinsics,
        poses[planes.point_poses[i]].data(), plane_blocks[stripe].data());
    plane_used[stripe] = 1;
  }
  for (size_t stripe = 0; stripe < plane_blocks.size(); ++stripe)
    if (plane_used[stripe])
      problem.SetManifold(plane_blocks[stripe].data(), new ceres::SphereManifold<4>());
  // Skew stays as given (the camera model's gamma is estimated by the camera calibration).
  problem.SetManifold(intrinsics, new ceres::SubsetManifold(7, {2}));

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 30;
  options.num_threads = 2;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  JointRefinementResult result;
  result.camera = camera;
  result.camera.alpha = intrinsics[0];
  result.camera.beta = intrinsics[1];
  result.camera.gamma = intrinsics[2];
  result.camera.u0 = intrinsics[3];
  result.camera.v0 = intrinsics[4];
  result.camera.k1 = intrinsics[5];
  result.camera.k2 = intrinsics[6];
  for (const auto& block : poses) result.board_to_camera.push_back(fromBlock(block.data()));
  double corner_after = 0;
  for (size_t k = 0; k < poses.size(); ++k)
    for (size_t c = 0; c < input.corners[k].size(); ++c)
      corner_after += (result.camera.project(result.board_to_camera[k] * input.board_points[c]) -
                       input.corners[k][c])
                          .squaredNorm();
  result.corner_rms_px_before = std::sqrt(corner_squared / (corner_count / 2));
  result.corner_rms_px_after = std::sqrt(corner_after / (corner_count / 2));
  result.plane_rms_m_before = plane_count ? std::sqrt(plane_squared_before / plane_count) : 0;
  result.iterations = static_cast<int>(summary.iterations.size());
  std::ostringstream line;
  line << "Ceres LM, " << plane_count << " stripe points + " << corner_count / 2 << " corners, "
       << result.iterations << " iterations, " << summary.message;
  result.summary = line.str();
  return result;
}

}  // namespace body_scan_calib
