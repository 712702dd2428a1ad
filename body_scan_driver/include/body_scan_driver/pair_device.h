// One projector-camera pair as the driver sees it, whatever is behind it: the simulator now,
// USB hardware later (the velodyne driver's Input/InputSocket/InputPCAP split).
#pragma once

#include <body_scan_driver/gray_code.h>
#include <body_scan_driver/pair_model.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace body_scan_driver {

struct PatternCapture {
  std::vector<cv::Mat> frames;  // CV_8UC1 in PatternLayout order
  cv::Mat texture;              // CV_8UC3 RGB
};

// Health of a device for /diagnostics (issue 8): what it is, its connection state, and why.
struct DeviceStatus {
  enum class Level { kOk, kWarn, kError };
  Level level = Level::kOk;
  std::string hardware_id;  // e.g. "simulator" or "uvc 046d:0825/SERIAL + display :0.0"
  std::string state;        // e.g. STREAMING, ERROR
  std::string message;      // one line: what is wrong and how to fix it, or "streaming"
  double frame_rate_hz = 0;
  uint64_t dropped_frames = 0;
  std::vector<std::pair<std::string, std::string>> values;  // further key/values
};

class PairDevice {
 public:
  virtual ~PairDevice() = default;
  // Projects the pattern sequence and captures it. Throws std::runtime_error on device failure.
  virtual PatternCapture capture(uint32_t scan_id) = 0;
  virtual const PatternLayout& layout() const = 0;
  // The camera model to announce in camera_info (from the factory or a calibration).
  virtual PinholeCamera camera() const = 0;
  // The calibration the device was built with, if it knows one (the simulator does).
  virtual std::optional<PairCalibration> factoryCalibration() const { return std::nullopt; }
  // The camera's pose in the world if the device knows it (the simulator does).
  virtual std::optional<Eigen::Isometry3d> factoryPose() const { return std::nullopt; }
  // Replaces the scene in front of the pair (scene file text). Only a simulated pair has a
  // scene to replace: the others throw std::runtime_error saying so.
  virtual void replaceScene(const std::string& /*scene_yaml*/) {
    throw std::runtime_error(
        "this pair captures the real world: its scene cannot be set; place the target by hand "
        "(or use backend:=sim)");
  }
  // The other pairs that project at the same time as the next capture(s) (the coordinator's
  // timing group). Real pairs ignore it: their light interferes physically. The simulator
  // renders those pairs' light into this pair's frames; it throws std::invalid_argument for an
  // id it does not know.
  virtual void setActivePairs(const std::vector<std::string>& /*pair_ids*/) {}
  // Called periodically by the driver: hardware reconnects here. Must not throw.
  virtual void poll() {}
  // Thread-safe: may be called while capture() runs. Not pure, so that devices written before
  // diagnostics existed (test doubles, replay) still compile; they report no health.
  virtual DeviceStatus status() const {
    DeviceStatus status;
    status.hardware_id = "none";
    status.state = "UNKNOWN";
    status.message = "this device reports no health";
    return status;
  }
};

// The virtual pair: renders the scene file seen by the pair file's camera.
// Throws std::runtime_error naming the file and the problem.
std::unique_ptr<PairDevice> makeSimulatedPair(const std::string& pair_file,
                                              const std::string& scene_file);
// One pair of a simulated rig (sim/rig.h): it knows every pair of the rig, so the light of the
// pairs named by setActivePairs() interferes with its frames. Throws std::runtime_error naming
// the file, or std::invalid_argument naming the pair id and the rig's ids.
std::unique_ptr<PairDevice> makeSimulatedRigPair(const std::string& rig_file,
                                                 const std::string& pair_id,
                                                 const std::string& scene_file);

}  // namespace body_scan_driver
