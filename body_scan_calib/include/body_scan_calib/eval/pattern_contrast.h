// How much the finest Gray-code bit still separates from its inverse on a checkerboard: the
// distribution of |pattern - inverse| (grey levels) over the board's dark and light squares. It
// measures how hard a capture set is to decode (dark print, blooming, the projector's pixel
// footprint and the optics' blur all shrink it) and compares the simulator's board renders with
// real captures (evaluation library body_scan_calib_eval; product code never links it).
#pragma once

#include <body_scan_calib/camera_calibration.h>
#include <body_scan_driver/gray_code.h>

#include <array>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace body_scan_calib::eval {

// Histogram bin edges (grey levels): [0, 2), [2, 4), [4, 8), ... [128, 256].
constexpr std::array<int, 9> kContrastBinEdges{0, 2, 4, 8, 16, 32, 64, 128, 256};

struct ContrastDistribution {
  size_t pixels = 0;
  double p5 = 0, p25 = 0, p50 = 0, p75 = 0, p95 = 0;             // grey levels
  std::array<double, kContrastBinEdges.size() - 1> histogram{};  // share of the pixels per bin
};
ContrastDistribution contrastDistribution(std::vector<float> values);

struct BoardContrast {
  ContrastDistribution dark, light;  // the board's dark and light squares
  // Median grey levels of the squares in the all-lit and the all-dark frame.
  double dark_lit_level = 0, light_lit_level = 0, dark_unlit_level = 0, light_unlit_level = 0;
  int poses = 0;  // poses whose board was found
  // The dark squares' level in the all-lit minus the all-dark frame against the distance to the
  // nearest light pixel (index: pixels, rounded; up to kMaxEdgeDistancePx), as a share of the
  // light squares' level: blooming makes it fall off over its width from a light square's edge.
  // Light and dark pixels: Otsu's threshold of the lit frame inside the inner corners' hull.
  std::vector<double> dark_share_by_edge_distance;
};
constexpr int kMaxEdgeDistancePx = 30;

// Pixels measured: inside the squares bounded by the board's inner corners (found in the lit
// frame), more than `edge_margin_px` from a square's edge, on image rows that were recorded
// (a row whose finest-bit frames are 0 everywhere is a trimmed one, left out). Which squares are
// dark: the lower median lit level of the two square parities. frames: PatternLayout(bits,
// true) order (lit, dark, pattern/inverse pairs). Poses whose board is not found are skipped;
// throws std::runtime_error if none is found.
BoardContrast finestBitContrastOnBoard(const std::vector<std::vector<cv::Mat>>& pose_frames,
                                       const body_scan_driver::PatternLayout& layout,
                                       const Checkerboard& board, double edge_margin_px = 2.0);

// Temporal sensor noise against signal level, from the frames themselves: a pixel is in the same
// projector state (lit or dark) in the all-lit (all-dark) frame and in one frame of each of the
// `coarse_bits` most significant bits' pattern/inverse pairs, where that pair differs by more
// than max(4, half the lit - dark range) throughout its 9x9 neighbourhood. The two frames'
// difference minus its 5x5 mean (the smooth, pattern-dependent light: stray light, blooming, the
// projector's frame-to-frame brightness) leaves the noise: sigma = sd / sqrt(2 (1 - 1/25)), per
// band of the pixel's level (kNoiseLevelEdges), differences beyond 4 sd trimmed. Saturated pixels
// (>= 250) and rows without the coarse bits (trimmed) are left out.
constexpr std::array<int, 8> kNoiseLevelEdges{0, 4, 8, 16, 32, 64, 128, 250};
struct NoiseAtLevel {
  size_t samples = 0;
  double level = 0, sigma = 0;  // grey levels: the samples' mean level and the noise there
};
std::array<NoiseAtLevel, kNoiseLevelEdges.size() - 1> sensorNoiseByLevel(
    const std::vector<std::vector<cv::Mat>>& pose_frames,
    const body_scan_driver::PatternLayout& layout, int coarse_bits = 4);

// Two sensorNoiseByLevel results side by side, one row per level band with samples in either.
std::string noiseTable(const std::string& name_a,
                       const std::array<NoiseAtLevel, kNoiseLevelEdges.size() - 1>& a,
                       const std::string& name_b,
                       const std::array<NoiseAtLevel, kNoiseLevelEdges.size() - 1>& b);

// Side by side, one row per statistic: "name: dark a | b   light a | b".
std::string contrastTable(const std::string& name_a, const BoardContrast& a,
                          const std::string& name_b, const BoardContrast& b);

}  // namespace body_scan_calib::eval
