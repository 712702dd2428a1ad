// Motion capture in the BVH format (Biovision Hierarchy): a joint tree with per-joint Euler
// channels, then one line of channel values per frame. The reader is strict: anything it does not
// understand is an error naming the line and the fix, never a silently wrong skeleton.
// Units and axes are the file's own (CMU: 0.056444 m per unit, Y up); sim/bvh_body.h maps them
// to the simulator's world.
#pragma once

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>
#include <vector>

namespace body_scan_driver::sim {

enum class BvhChannel { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };

struct BvhJoint {
  std::string name;
  int parent = -1;                                   // index into BvhMotion::joints; -1 = root
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // from the parent, in the parent's frame
  std::vector<BvhChannel> channels;                  // in file order
  int first_channel = 0;                             // column of channels[0] in a frame
  bool has_end_site = false;
  Eigen::Vector3d end_site = Eigen::Vector3d::Zero();  // offset of the end site, if any
};

struct BvhMotion {
  std::vector<BvhJoint> joints;  // depth first, file order: every parent before its children
  int channel_count = 0;         // values per frame
  double frame_time = 0;         // s
  std::vector<std::vector<double>> frames;  // frames[f][column]; angles in degrees

  // Index of the joint with this name, or -1.
  int jointIndex(const std::string& name) const;
  double frameRate() const { return 1.0 / frame_time; }
};

// A frame posed in the file's world: positions in file units, rotations joint-local -> world.
struct BvhPose {
  std::vector<Eigen::Vector3d> position;  // per joint
  std::vector<Eigen::Matrix3d> rotation;  // per joint
  std::vector<Eigen::Vector3d> end_site;  // per joint; meaningful where has_end_site
};

// Malformed input: the message names the source, the line (1-based) and the fix.
class BvhError : public std::runtime_error {
 public:
  BvhError(const std::string& source, int line, const std::string& problem);
  int line() const { return line_; }

 private:
  int line_;
};

// Parses BVH text. `source` names it in errors (a path, or "<string>"). Throws BvhError on an
// unknown keyword, a missing brace, a channel count that does not match the hierarchy, fewer or
// more frame lines than "Frames:", non-numbers, NaN or infinity, a non-positive frame time.
BvhMotion parseBvh(const std::string& text, const std::string& source = "<string>");

// Reads and parses a file; throws BvhError (line 0) if it cannot be read.
BvhMotion loadBvh(const std::string& path);

// Forward kinematics of frame `frame` (0-based): each joint's local transform is the offset plus
// its position channels, then its rotation channels applied in file order (R = R1 * R2 * R3,
// e.g. "Zrotation Yrotation Xrotation" -> Rz * Ry * Rx). Throws std::out_of_range on a bad frame.
BvhPose poseBvhFrame(const BvhMotion& motion, int frame);

}  // namespace body_scan_driver::sim
