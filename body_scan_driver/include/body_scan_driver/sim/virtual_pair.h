// The virtual projector-camera pair (DESIGN.md section 4): renders the Gray code pattern set a
// real pair would capture of a scene, with its exact ground truth.
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_model.h>
#include <body_scan_driver/rig_layout.h>
#include <body_scan_driver/sim/scene.h>

#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_driver::sim {

// A laser line generator whose fan is swept by a rotating mirror (the thesis's projector,
// sec. 4.2.1). The mirror face is offset from its rotation axis, so the point where the laser
// meets the mirror moves with the angle and the stripe planes do NOT share one line: a pinhole
// projector model fits it worse than the plane-per-stripe model (Table 3.2).
// Everything is in the camera optical frame (metres, radians). Defaults: a pole pair with the
// projector 330 mm above the camera sweeping a horizontal line down over the camera's view.
struct SweptLaserProjector {
  Eigen::Vector3d mirror_axis_point{0.0, -0.33, 0.0};
  Eigen::Vector3d mirror_axis{1.0, 0.004, -0.006};  // slightly misaligned, as built
  double mirror_offset = 0.008;                     // rotation axis to mirror face
  Eigen::Vector3d laser_origin{0.0, -0.37, 0.0};    // line generator above the mirror
  Eigen::Vector3d laser_direction{0.0, 1.0, 0.0};   // pointing down at the mirror
  Eigen::Vector3d laser_fan_axis{1.0, 0.0, 0.0};    // direction the laser line spreads in
  double fan_half_angle = 0.6;
  double first_mirror_angle = 0.7505;  // at stripe coordinate 0 (~43 deg): beam 4 deg up
  double last_mirror_angle = 1.0996;   // at coordinate stripe_count (~63 deg): beam 36 deg down
  // Width of the projected line (the projector's pixel footprint), in stripes: each frame's
  // pattern is box-averaged over it, on top of the camera pixel's own footprint. 0: a sharp line
  // (ideal edges); > 1: a projector pixel wider than its stripe, which blurs the finest bits.
  double line_width = 0.0;

  struct Plane {
    Eigen::Vector3d normal;   // unit
    double offset;            // plane: normal . x + offset = 0
    Eigen::Vector3d source;   // where the light leaves the mirror
    Eigen::Vector3d spread;   // direction of the line within the plane
    Eigen::Vector3d central;  // central ray direction
  };
  // The light plane at mirror angle `angle`.
  Plane planeAtAngle(double angle) const;
  // planeAtAngle's angle-independent part, for callers that evaluate many angles.
  struct MirrorFrame {
    Eigen::Vector3d e1, e2;           // mirror normal = cos(angle) e1 + sin(angle) e2
    Eigen::Vector3d laser;            // unit laser direction
    Eigen::Vector3d laser_from_axis;  // laser_origin - mirror_axis_point
  };
  MirrorFrame mirrorFrame() const;
  Plane planeAtAngle(double angle, const MirrorFrame& frame) const;
};

// Optics and noise. Defaults are the suite's documented defaults used by every test unless it
// says otherwise: sensor noise 2 grey levels (of 255) at every level, blur 0.7 px, ambient light
// 10% of the projector's brightness, no blooming or stray light.
struct SensorModel {
  // Per-pixel Gaussian noise before 8-bit quantization, of variance
  // noise_sigma^2 + shot_noise_gain * level (grey levels): a read-noise floor plus shot noise
  // that grows with the pixel's signal. shot_noise_gain 0: the same noise_sigma everywhere.
  double noise_sigma = 2.0;
  double shot_noise_gain = 0.0;  // grey levels (noise variance per grey level of signal)
  double blur_sigma = 0.7;
  double ambient = 0.1;
  // Blooming: this share of every pixel's light spreads over a Gaussian of bloom_sigma pixels
  // (bright squares spill into dark ones); stray light: this share of the frame's mean level
  // added everywhere (interreflection, veiling glare). 0: off.
  double bloom_share = 0.0;
  double bloom_sigma = 8.0;
  double stray_light = 0.0;
  double projector_level = 200.0;  // grey level of a white (albedo 1) surface lit head-on at 1 m
  uint32_t seed = 1;
};

struct VirtualPairConfig {
  std::string pair_id = "pole_a/pair_1";
  PinholeCamera camera{640, 480, 810, 810, 0, 319.5, 239.5, -0.08, 0.03};
  SweptLaserProjector projector;
  SensorModel sensor;
  int bits = 8;
  bool inverse_frames = true;
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
};

// The optics and sensor noise of real captures, matched on a public real capture set (a DLP
// projector's Gray code on a printed board; body_scan_calib's evaluate_pattern_contrast): the
// finest bit's |pattern - inverse| on the board's dark and light squares has the real set's
// percentiles. The projected line is 2.5 stripes wide (the finest bit keeps about half its
// contrast), 10% of the light blooms over 10 px and 2% of the frame's mean is stray light. The
// sensor noise is the real camera's (evaluate_pattern_contrast's noise table): pure shot noise,
// variance 0.055 grey levels per grey level (sigma 0.7 at level 10, 2.3 at 100); its read noise
// is below the 8-bit step. The simulated calibration tools render with it unless told
// --ideal-optics.
struct RealCaptureOptics {
  double line_width = 2.5;  // stripes (SweptLaserProjector::line_width)
  double bloom_share = 0.1, bloom_sigma = 10.0, stray_light = 0.02;  // SensorModel
  double noise_sigma = 0.0, shot_noise_gain = 0.055;                 // SensorModel
};
// `config` with these optics where it leaves them off (0), so a pair file's own values stay; its
// sensor noise is replaced unless it has shot noise (shot_noise_gain > 0).
VirtualPairConfig withRealCaptureOptics(VirtualPairConfig config,
                                        const RealCaptureOptics& optics = {});

// Camera pose from a position and a heading: the rig layout's (rig_layout.h), for pair files.
using body_scan_driver::cameraPose;

// Reads a pair file (see config/pairs/default_pair.yaml). Throws std::runtime_error naming
// the file and the bad key.
VirtualPairConfig loadVirtualPairConfig(const std::string& path);

// Exact ground truth of one render. Only the simulator, tests and evaluation tools use it.
struct GroundTruth {
  cv::Mat3f points;   // camera-frame point seen at each pixel centre; NaN = nothing
  cv::Mat3f normals;  // camera-frame outward unit normal there (meshes: interpolated); NaN
  cv::Mat1f stripe;   // continuous stripe coordinate lighting it; NaN = unlit/shadow
  cv::Mat1i surface;  // index into Scene::surfaces(); -1 = nothing
  std::vector<SkeletonJoint> skeleton;  // world frame
};

struct RenderedPatternSet {
  std::vector<cv::Mat> frames;  // CV_8UC1, PatternLayout order
  cv::Mat texture;              // CV_8UC3, RGB
  GroundTruth truth;
};

class VirtualPair {
 public:
  VirtualPair(VirtualPairConfig config, std::shared_ptr<const Scene> scene);
  // A pair used only as another pair's interference source (render's also_projecting): it
  // skips the camera's ray and noise tables (about 8 MB), so it must not render itself.
  static VirtualPair projectorOnly(VirtualPairConfig config, std::shared_ptr<const Scene> scene);

  // Deterministic for a given config, scene, scan id and set of other pairs. also_projecting:
  // pairs of the same rig projecting their sequences at the same moment (thesis 4.3,
  // Fig 4.7): wherever their light falls on a surface this camera sees, it adds to this pair's
  // frames (interference). Their poses are their world_from_camera; they must render the same
  // scene. The ground truth stays this pair's own light.
  RenderedPatternSet render(uint32_t scan_id = 0,
                            const std::vector<const VirtualPair*>& also_projecting = {}) const;
  // The true geometry in the calibration model: intrinsics + the plane at each stripe centre.
  PairCalibration factoryCalibration() const;

  const VirtualPairConfig& config() const { return config_; }
  const PatternLayout& layout() const { return layout_; }

 private:
  struct SurfaceSample;
  struct ForeignLight;
  // Light of this pair's projector at a surface point (in this pair's camera frame, and in the
  // world for the shadow test) with outward normal (camera frame): the stripe coordinate and
  // the grey level it adds, or false where it does not reach (outside the
  // sweep or fan, facing away, shadowed). level: the grey level it adds on a surface of that
  // albedo (a line laser's irradiance falls as 1/distance; normalized at 1 m).
  bool lightAt(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
               const Eigen::Vector3d& point_world, double albedo, float& stripe,
               float& level) const;
  double trueStripe(const Eigen::Vector3d& point_camera, SweptLaserProjector::Plane* plane) const;
  // render's steps. traceSurfaces: what each pixel sees (the ground truth, samples) and the
  // light of also_projecting there (foreign, per row, by increasing column).
  void traceSurfaces(const std::vector<const VirtualPair*>& also_projecting, GroundTruth& truth,
                     std::vector<SurfaceSample>& samples,
                     std::vector<std::vector<ForeignLight>>& foreign) const;
  // Each pixel's footprint in stripes: the camera pixel's and the projector's line_width.
  static std::vector<float> stripeFootprints(const std::vector<SurfaceSample>& samples, int rows,
                                             int cols, double line_width);
  // Every frame's image before optics and noise, rows [row_begin, row_end): lit_frames[k] has
  // bit f set where frame f lights stripe k.
  void shadeFrames(const std::vector<uint32_t>& lit_frames,
                   const std::vector<SurfaceSample>& samples, const std::vector<float>& footprint,
                   const std::vector<std::vector<ForeignLight>>& foreign, int row_begin,
                   int row_end, std::vector<cv::Mat1f>& images) const;

  VirtualPair(VirtualPairConfig config, std::shared_ptr<const Scene> scene, bool with_camera);

  VirtualPairConfig config_;
  std::shared_ptr<const Scene> scene_;
  PatternLayout layout_;
  std::vector<Eigen::Vector3f> camera_rays_;  // unit rays per pixel (camera frame)
  struct SweepPlane {  // normal . x + offset = 0 (only what the search needs: compact)
    Eigen::Vector3d normal;
    double offset;
  };
  std::vector<SweepPlane> sweep_;  // planes at fine steps of the coordinate
  double sweep_step_;              // stripe coordinate between sweep_ entries
  SweptLaserProjector::MirrorFrame mirror_frame_;
  double tan_fan_half_angle_;
  std::vector<float> noise_;  // unit Gaussian samples
};

}  // namespace body_scan_driver::sim
