// Finding the calibration cylinder's grid points in one pair's images (thesis sec. 4.4.1) and
// triangulating them in the pair's camera frame. The cylinder's printed layout
// (body_scan_driver/cylinder_layout.h) names each grid point; its ArUco markers tell a pair
// which grid points it sees, so pairs far apart agree on the ids without any search.
#pragma once

#include <body_scan_driver/cylinder_layout.h>
#include <body_scan_driver/pair_model.h>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

namespace body_scan_calib {

// 3D grid point in the cylinder frame (base centre at the origin, axis +z, metres).
inline Eigen::Vector3d cylinderGridPoint(const body_scan_driver::CalibrationCylinderLayout& layout,
                                         int id) {
  return layout.gridPoint(id);
}

struct GridPointDetection {
  int id;                 // CalibrationCylinderLayout::gridPointId
  Eigen::Vector2d pixel;  // subpixel checker corner (distorted image)
};

struct CylinderDetectionStats {
  int markers = 0;           // markers decoded with a valid id
  int predicted = 0;         // grid points predicted from the markers
  int rejected_grazing = 0;  // squares seen more than ~60 deg off their normal
  int rejected_refine = 0;   // corners whose refinement wandered away from the prediction
};

// Detects the markers, predicts the checker corners of each marker's square through the
// marker's homography and refines them with cv::cornerSubPix. gray: CV_8UC1.
std::vector<GridPointDetection> detectCylinderGridPoints(
    const cv::Mat& gray, const body_scan_driver::CalibrationCylinderLayout& layout,
    CylinderDetectionStats* stats = nullptr);

// Camera-frame point of a grid point: the stripe coordinate at its subpixel pixel from a local
// least-squares plane s = a + b du + c dv over the decoded pixels within `radius`, then the
// undistorted ray meets that stripe's plane (eqs 3.9-3.12). nullopt when too few pixels decode
// around it, the fit is poor or the stripe was never calibrated.
std::optional<Eigen::Vector3d> triangulateAtPixel(
    const cv::Mat1f& stripe_coordinate, const Eigen::Vector2d& pixel,
    const body_scan_driver::PairCalibration& calibration, int radius = 4);

struct TriangulatedGridPoint {
  int id;
  Eigen::Vector2d pixel;
  Eigen::Vector3d camera_point;  // metres, camera optical frame
};

// One pair's view of the cylinder: detections on the texture (or lit) image, stripe
// coordinates decoded from the pattern set, triangulated grid points.
struct CylinderObservation {
  std::vector<GridPointDetection> detections;
  std::vector<TriangulatedGridPoint> points;
  CylinderDetectionStats stats;
};

CylinderObservation observeCylinder(const cv::Mat& gray, const cv::Mat1f& stripe_coordinate,
                                    const body_scan_driver::PairCalibration& calibration,
                                    const body_scan_driver::CalibrationCylinderLayout& layout);

}  // namespace body_scan_calib
