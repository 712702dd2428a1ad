#include <body_scan_calib/eval/pattern_contrast.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace body_scan_calib::eval {
namespace {

double median(std::vector<float> values) {
  if (values.empty()) return 0;
  auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// One pose's board pixels by square parity ((col + row) % 2 of the square): |pattern -
// inverse| and the lit level.
struct ParitySamples {
  std::vector<float> contrast[2], lit[2], unlit[2];
};

ParitySamples sampleBoard(const std::vector<cv::Mat>& frames,
                          const body_scan_driver::PatternLayout& layout,
                          const std::vector<Eigen::Vector2d>& corners, const Checkerboard& board,
                          double edge_margin_px) {
  const int finest = layout.bits() - 1;
  const cv::Mat& lit = frames[body_scan_driver::PatternLayout::litFrame()];
  const cv::Mat& unlit = frames[body_scan_driver::PatternLayout::darkFrame()];
  const cv::Mat& pattern = frames[layout.patternFrame(finest)];
  const cv::Mat& inverse = frames[layout.inverseFrame(finest)];
  cv::Mat brighter, row_max;
  cv::max(pattern, inverse, brighter);
  cv::reduce(brighter, row_max, 1, cv::REDUCE_MAX);
  ParitySamples samples;
  const int cols = board.inner_cols;
  for (int r = 0; r + 1 < board.inner_rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const Eigen::Vector2d quad[4] = {corners[r * cols + c], corners[r * cols + c + 1],
                                       corners[(r + 1) * cols + c + 1],
                                       corners[(r + 1) * cols + c]};
      std::vector<cv::Point2f> image_quad, unit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      double side = 0, u_min = 1e9, u_max = -1e9, v_min = 1e9, v_max = -1e9;
      for (int i = 0; i < 4; ++i) {
        image_quad.emplace_back(static_cast<float>(quad[i].x()), static_cast<float>(quad[i].y()));
        side += 0.25 * (quad[(i + 1) % 4] - quad[i]).norm();
        u_min = std::min(u_min, quad[i].x()), u_max = std::max(u_max, quad[i].x());
        v_min = std::min(v_min, quad[i].y()), v_max = std::max(v_max, quad[i].y());
      }
      const cv::Matx33d to_square(cv::getPerspectiveTransform(image_quad, unit));
      const double margin = edge_margin_px / side;
      const int parity = (r + c) % 2;
      for (int v = std::max(0, static_cast<int>(std::floor(v_min)));
           v <= std::min(lit.rows - 1, static_cast<int>(std::ceil(v_max))); ++v) {
        if (row_max.at<uint8_t>(v) == 0) continue;  // a trimmed row
        for (int u = std::max(0, static_cast<int>(std::floor(u_min)));
             u <= std::min(lit.cols - 1, static_cast<int>(std::ceil(u_max))); ++u) {
          const cv::Vec3d p = to_square * cv::Vec3d(u, v, 1);
          const double x = p[0] / p[2], y = p[1] / p[2];
          if (x < margin || x > 1 - margin || y < margin || y > 1 - margin) continue;
          samples.contrast[parity].push_back(static_cast<float>(
              std::abs(int{pattern.at<uint8_t>(v, u)} - int{inverse.at<uint8_t>(v, u)})));
          samples.lit[parity].push_back(lit.at<uint8_t>(v, u));
          samples.unlit[parity].push_back(unlit.at<uint8_t>(v, u));
        }
      }
    }
  return samples;
}

// Sums for BoardContrast::dark_share_by_edge_distance over one pose.
struct EdgeProfileSums {
  std::vector<double> dark_sum = std::vector<double>(kMaxEdgeDistancePx + 1, 0.0);
  std::vector<size_t> dark_count = std::vector<size_t>(kMaxEdgeDistancePx + 1, 0);
  double light_sum = 0;
  size_t light_count = 0;
};

void addEdgeProfile(const cv::Mat& lit, const cv::Mat& unlit,
                    const std::vector<Eigen::Vector2d>& corners, EdgeProfileSums& sums) {
  std::vector<cv::Point2f> points, hull;
  for (const Eigen::Vector2d& c : corners)
    points.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
  cv::convexHull(points, hull);
  std::vector<cv::Point> polygon;
  for (const cv::Point2f& p : hull) polygon.emplace_back(cvRound(p.x), cvRound(p.y));
  cv::Mat inside = cv::Mat::zeros(lit.size(), CV_8U);
  cv::fillConvexPoly(inside, polygon, 255);
  std::vector<uint8_t> values;
  for (int v = 0; v < lit.rows; ++v)
    for (int u = 0; u < lit.cols; ++u)
      if (inside.at<uint8_t>(v, u)) values.push_back(lit.at<uint8_t>(v, u));
  if (values.empty()) return;
  cv::Mat scratch(values, true);
  const double threshold =
      cv::threshold(scratch, scratch, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  const cv::Mat dark = lit <= threshold;
  cv::Mat light_core, distance, recorded_rows;
  cv::erode((lit > threshold) & inside, light_core, cv::Mat::ones(7, 7, CV_8U));
  cv::distanceTransform(dark, distance, cv::DIST_L2, cv::DIST_MASK_5);
  cv::reduce(unlit, recorded_rows, 1, cv::REDUCE_MAX);
  for (int v = 0; v < lit.rows; ++v) {
    if (recorded_rows.at<uint8_t>(v) == 0) continue;  // a trimmed row
    for (int u = 0; u < lit.cols; ++u) {
      if (!inside.at<uint8_t>(v, u)) continue;
      const double level = int{lit.at<uint8_t>(v, u)} - int{unlit.at<uint8_t>(v, u)};
      if (light_core.at<uint8_t>(v, u)) sums.light_sum += level, ++sums.light_count;
      if (!dark.at<uint8_t>(v, u)) continue;
      const int d = static_cast<int>(std::lround(distance.at<float>(v, u)));
      if (d > kMaxEdgeDistancePx) continue;
      sums.dark_sum[d] += level;
      ++sums.dark_count[d];
    }
  }
}

}  // namespace

ContrastDistribution contrastDistribution(std::vector<float> values) {
  ContrastDistribution d;
  d.pixels = values.size();
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  auto at = [&](double q) {
    return values[static_cast<size_t>(std::lround(q * (values.size() - 1)))];
  };
  d.p5 = at(0.05), d.p25 = at(0.25), d.p50 = at(0.5), d.p75 = at(0.75), d.p95 = at(0.95);
  for (float value : values)
    for (size_t bin = 0; bin + 1 < kContrastBinEdges.size(); ++bin)
      if (value < kContrastBinEdges[bin + 1] || bin + 2 == kContrastBinEdges.size()) {
        d.histogram[bin] += 1.0 / values.size();
        break;
      }
  return d;
}

BoardContrast finestBitContrastOnBoard(const std::vector<std::vector<cv::Mat>>& pose_frames,
                                       const body_scan_driver::PatternLayout& layout,
                                       const Checkerboard& board, double edge_margin_px) {
  if (!layout.inverseFrames())
    throw std::invalid_argument("finestBitContrastOnBoard needs inverse frames");
  std::vector<float> contrast[2], lit[2], unlit[2];  // dark, light
  EdgeProfileSums edge_sums;
  BoardContrast result;
  for (const std::vector<cv::Mat>& frames : pose_frames) {
    if (static_cast<int>(frames.size()) != layout.frameCount())
      throw std::invalid_argument("finestBitContrastOnBoard: " + std::to_string(frames.size()) +
                                  " frames for a layout of " + std::to_string(layout.frameCount()));
    std::vector<Eigen::Vector2d> corners;
    if (!detectCheckerboardCorners(frames[body_scan_driver::PatternLayout::litFrame()], board,
                                   corners))
      continue;
    ++result.poses;
    addEdgeProfile(frames[body_scan_driver::PatternLayout::litFrame()],
                   frames[body_scan_driver::PatternLayout::darkFrame()], corners, edge_sums);
    ParitySamples samples = sampleBoard(frames, layout, corners, board, edge_margin_px);
    const int dark = median(samples.lit[0]) <= median(samples.lit[1]) ? 0 : 1;
    for (int colour = 0; colour < 2; ++colour) {
      const int parity = colour == 0 ? dark : 1 - dark;
      contrast[colour].insert(contrast[colour].end(), samples.contrast[parity].begin(),
                              samples.contrast[parity].end());
      lit[colour].insert(lit[colour].end(), samples.lit[parity].begin(), samples.lit[parity].end());
      unlit[colour].insert(unlit[colour].end(), samples.unlit[parity].begin(),
                           samples.unlit[parity].end());
    }
  }
  if (result.poses == 0)
    throw std::runtime_error("finestBitContrastOnBoard: the " + std::to_string(board.inner_cols) +
                             "x" + std::to_string(board.inner_rows) +
                             " inner corners were found in no pose's lit frame (check the board "
                             "size)");
  result.dark = contrastDistribution(contrast[0]);
  result.light = contrastDistribution(contrast[1]);
  result.dark_lit_level = median(lit[0]);
  result.light_lit_level = median(lit[1]);
  result.dark_unlit_level = median(unlit[0]);
  result.light_unlit_level = median(unlit[1]);
  const double light_level = edge_sums.light_sum / std::max<size_t>(1, edge_sums.light_count);
  for (int d = 0; d <= kMaxEdgeDistancePx; ++d)
    result.dark_share_by_edge_distance.push_back(edge_sums.dark_count[d] > 0 && light_level > 0
                                                     ? edge_sums.dark_sum[d] /
                                                           edge_sums.dark_count[d] / light_level
                                                     : std::nan(""));
  return result;
}

std::string contrastTable(const std::string& name_a, const BoardContrast& a,
                          const std::string& name_b, const BoardContrast& b) {
  std::string text;
  char line[256];
  std::snprintf(line, sizeof line, "%-22s %12s %12s   %12s %12s\n", "|pattern - inverse|",
                ("dark " + name_a).c_str(), ("dark " + name_b).c_str(), ("light " + name_a).c_str(),
                ("light " + name_b).c_str());
  text += line;
  auto row = [&](const char* name, double da, double db, double la, double lb) {
    std::snprintf(line, sizeof line, "%-22s %12.4g %12.4g   %12.4g %12.4g\n", name, da, db, la, lb);
    text += line;
  };
  row("pixels", a.dark.pixels, b.dark.pixels, a.light.pixels, b.light.pixels);
  row("lit frame median", a.dark_lit_level, b.dark_lit_level, a.light_lit_level, b.light_lit_level);
  row("dark frame median", a.dark_unlit_level, b.dark_unlit_level, a.light_unlit_level,
      b.light_unlit_level);
  row("p5", a.dark.p5, b.dark.p5, a.light.p5, b.light.p5);
  row("p25", a.dark.p25, b.dark.p25, a.light.p25, b.light.p25);
  row("p50", a.dark.p50, b.dark.p50, a.light.p50, b.light.p50);
  row("p75", a.dark.p75, b.dark.p75, a.light.p75, b.light.p75);
  row("p95", a.dark.p95, b.dark.p95, a.light.p95, b.light.p95);
  for (size_t bin = 0; bin + 1 < kContrastBinEdges.size(); ++bin) {
    char name[32];
    std::snprintf(name, sizeof name, "share [%d, %d)", kContrastBinEdges[bin],
                  kContrastBinEdges[bin + 1]);
    row(name, a.dark.histogram[bin], b.dark.histogram[bin], a.light.histogram[bin],
        b.light.histogram[bin]);
  }
  // Blooming: the dark squares' lit level near a light square, in % of the light squares'.
  for (int d : {1, 2, 3, 5, 10, 15, 20, 30}) {
    auto share = [&](const BoardContrast& c) {
      return d < static_cast<int>(c.dark_share_by_edge_distance.size())
                 ? 100 * c.dark_share_by_edge_distance[d]
                 : std::nan("");
    };
    char name[32];
    std::snprintf(name, sizeof name, "lit %% of light, %d px", d);
    std::snprintf(line, sizeof line, "%-22s %12.4g %12.4g\n", name, share(a), share(b));
    text += line;
  }
  return text;
}

std::array<NoiseAtLevel, kNoiseLevelEdges.size() - 1> sensorNoiseByLevel(
    const std::vector<std::vector<cv::Mat>>& pose_frames,
    const body_scan_driver::PatternLayout& layout, int coarse_bits) {
  if (!layout.inverseFrames())
    throw std::invalid_argument("sensorNoiseByLevel needs inverse frames");
  constexpr int kWindow = 5, kStateWindow = 9;
  constexpr size_t kBands = kNoiseLevelEdges.size() - 1;
  std::array<std::vector<float>, kBands> differences, levels;
  for (const std::vector<cv::Mat>& frames : pose_frames) {
    if (static_cast<int>(frames.size()) != layout.frameCount())
      throw std::invalid_argument("sensorNoiseByLevel: " + std::to_string(frames.size()) +
                                  " frames for a layout of " + std::to_string(layout.frameCount()));
    cv::Mat lit, unlit;
    frames[body_scan_driver::PatternLayout::litFrame()].convertTo(lit, CV_32F);
    frames[body_scan_driver::PatternLayout::darkFrame()].convertTo(unlit, CV_32F);
    const cv::Mat threshold = cv::max(0.5 * (lit - unlit), 4.0);
    const cv::Mat state_kernel = cv::Mat::ones(kStateWindow, kStateWindow, CV_8U);
    for (int bit = 0; bit < std::min(coarse_bits, layout.bits()); ++bit) {
      cv::Mat pattern, inverse;
      frames[layout.patternFrame(bit)].convertTo(pattern, CV_32F);
      frames[layout.inverseFrame(bit)].convertTo(inverse, CV_32F);
      const cv::Mat difference = pattern - inverse;
      cv::Mat pattern_lit = difference > threshold, inverse_lit = difference < -threshold;
      cv::erode(pattern_lit, pattern_lit, state_kernel);
      cv::erode(inverse_lit, inverse_lit, state_kernel);
      cv::Mat decided = pattern_lit | inverse_lit;
      cv::erode(decided, decided, cv::Mat::ones(kWindow, kWindow, CV_8U));
      cv::Mat lit_frame = inverse.clone(), dark_frame = pattern.clone();
      pattern.copyTo(lit_frame, pattern_lit);
      inverse.copyTo(dark_frame, pattern_lit);
      for (const auto& [all, one] : {std::pair{&lit, &lit_frame}, {&unlit, &dark_frame}}) {
        const cv::Mat change = *all - *one;
        cv::Mat local_mean;
        cv::blur(change, local_mean, cv::Size(kWindow, kWindow), cv::Point(-1, -1),
                 cv::BORDER_REPLICATE);
        for (int v = 0; v < change.rows; ++v)
          for (int u = 0; u < change.cols; ++u) {
            if (!decided.at<uint8_t>(v, u)) continue;
            const float a = all->at<float>(v, u), b = one->at<float>(v, u);
            if (a >= kNoiseLevelEdges.back() || b >= kNoiseLevelEdges.back()) continue;
            const float level = 0.5f * (a + b);
            size_t band = 0;
            while (band + 1 < kBands && level >= kNoiseLevelEdges[band + 1]) ++band;
            differences[band].push_back(change.at<float>(v, u) - local_mean.at<float>(v, u));
            levels[band].push_back(level);
          }
      }
    }
  }
  std::array<NoiseAtLevel, kBands> result;
  auto standardDeviation = [](const std::vector<float>& x) {
    if (x.empty()) return 0.0;
    double sum = 0, squares = 0;
    for (float value : x) sum += value, squares += double{value} * value;
    const double mean = sum / x.size();
    return std::sqrt(std::max(0.0, squares / x.size() - mean * mean));
  };
  for (size_t band = 0; band < kBands; ++band) {
    if (differences[band].empty()) continue;
    const double all = standardDeviation(differences[band]);
    std::vector<float> kept;
    for (float value : differences[band])
      if (std::abs(value) <= 4 * all) kept.push_back(value);
    double level_sum = 0;
    for (float level : levels[band]) level_sum += level;
    result[band].samples = kept.size();
    result[band].level = level_sum / levels[band].size();
    result[band].sigma =
        standardDeviation(kept) / std::sqrt(2.0 * (1.0 - 1.0 / (kWindow * kWindow)));
  }
  return result;
}

std::string noiseTable(const std::string& name_a,
                       const std::array<NoiseAtLevel, kNoiseLevelEdges.size() - 1>& a,
                       const std::string& name_b,
                       const std::array<NoiseAtLevel, kNoiseLevelEdges.size() - 1>& b) {
  std::string text;
  char line[256];
  std::snprintf(line, sizeof line, "%-16s %10s %8s %8s   %10s %8s %8s\n", "noise by level",
                ("pixels " + name_a).c_str(), "level", "sigma", ("pixels " + name_b).c_str(),
                "level", "sigma");
  text += line;
  for (size_t band = 0; band < a.size(); ++band) {
    if (a[band].samples == 0 && b[band].samples == 0) continue;
    char name[32];
    std::snprintf(name, sizeof name, "[%d, %d)", kNoiseLevelEdges[band],
                  kNoiseLevelEdges[band + 1]);
    std::snprintf(line, sizeof line, "%-16s %10zu %8.1f %8.2f   %10zu %8.1f %8.2f\n", name,
                  a[band].samples, a[band].level, a[band].sigma, b[band].samples, b[band].level,
                  b[band].sigma);
    text += line;
  }
  return text;
}

}  // namespace body_scan_calib::eval
