// Capture layouts: how a folder of recorded Gray-code pattern sets is organised on disk. Each
// layout is one entry of a table (captureLayouts()): which subfolders are board poses, which
// files of a pose folder are frames (sorted by name), and the order of the frame blocks. One
// reader serves every entry, so another layout is another entry.
//
//   name     pose folders        frames (sorted)  order
//   project  pose_*              frame_*          lit, dark, stripe bits
//   opencv   every subfolder     every image      column bits, row bits, lit, dark
//
// "bits" blocks are pattern/inverse pairs, most significant bit first (OpenCV's
// structured_light::GrayCodePattern order). The stripe code is the one the pair model uses
// (one plane per stripe); the cross code (the projector's other axis, if recorded) only
// checks the decoding.
#pragma once

#include <body_scan_driver/gray_code.h>

#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib {

enum class FrameBlock { kLit, kDark, kStripeBits, kCrossBits };

struct CaptureLayout {
  std::string name;
  std::string pose_folder_prefix;  // subfolders whose names start with this ("" = all)
  std::string frame_prefix;        // image files whose names start with this ("" = all)
  std::vector<FrameBlock> frame_order;
  std::string description;  // for --help
};

const std::vector<CaptureLayout>& captureLayouts();
// Throws std::invalid_argument listing the known names.
const CaptureLayout& captureLayout(const std::string& name);

// Gray-code bits of the projector's two axes as a layout records them.
struct CaptureBits {
  int stripe_bits = 8;
  int cross_bits = 0;  // 0: no cross code recorded
};
// Bits to tell `pixels` projector pixels apart (ceil(log2)), as OpenCV's GrayCodePattern.
int bitsForPixels(int pixels);

// One board pose's pattern set.
struct CapturedPatternSet {
  std::string folder;
  std::vector<cv::Mat> frames;        // PatternLayout(stripe_bits, true) order
  std::vector<cv::Mat> cross_frames;  // PatternLayout(cross_bits, true) order; empty if none
};

// Reads one pose folder. Throws std::runtime_error naming the folder, the image count found
// and expected, and the options to check (--layout, --bits, --projector-width/height).
CapturedPatternSet loadCapturedPatternSet(const std::string& folder, const CaptureLayout& layout,
                                          const CaptureBits& bits);
// Every pose folder of `folder` in name order. Throws std::runtime_error if there is none.
std::vector<CapturedPatternSet> loadCapturedPoses(const std::string& folder,
                                                  const CaptureLayout& layout,
                                                  const CaptureBits& bits);

}  // namespace body_scan_calib
