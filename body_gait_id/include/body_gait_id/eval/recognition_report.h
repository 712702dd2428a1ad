// The evaluation's outputs: a YAML report (written atomically) and a CMC / ROC PNG plot with
// one curve per feature set (OpenCV core + imgproc + imgcodecs only).
#pragma once

#include <body_gait_id/eval/recognition_metrics.h>

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace body_gait_id::eval {

// The thesis's figures for the same row (Tables 5.3 / 5.4), printed side by side.
struct ThesisFigures {
  double identification_rate_percent = 0;
  double average_pose_error_frames = 0;
};

// One row of results: a feature set (and view) evaluated on one protocol.
struct NamedMetrics {
  std::string name;  // e.g. "3D dynamic+static"
  RecognitionMetrics metrics;
  std::optional<ThesisFigures> thesis;
  std::string note;  // what a reader must know about the row (e.g. people left out); "" none
};

struct RecognitionReport {
  std::vector<std::pair<std::string, std::string>> settings;  // protocol, subjects, scanner...
  std::vector<NamedMetrics> results;
};

// At most this many ROC points go to the YAML (evenly spaced, the first and last kept):
// the full curve of 50 subjects has ~10^5 points.
constexpr int kMaxReportedRocPoints = 101;

std::string recognitionReportYaml(const RecognitionReport& report);
// Throws body_scan_driver::FileWriteError naming the file and the fix.
void writeRecognitionReport(const std::string& path, const RecognitionReport& report);

// A printed table (name, rank-1 with CI, pose error, EER, thesis figures) for the terminal.
std::string recognitionTable(const std::vector<NamedMetrics>& results);

// --- plot
struct PlotCurve {
  std::string label;
  std::vector<cv::Point2d> points;  // data coordinates, drawn as a polyline
};
struct PlotPanel {
  std::string title, x_label, y_label;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  std::vector<double> x_ticks, y_ticks;  // empty: 5 even ticks (decades on a log axis)
  std::vector<PlotCurve> curves;
  bool log_x = false;  // log10 x axis (x_min > 0); smaller x are drawn at x_min
};

// Panels side by side on a white image, each with a frame, ticks, labels and a legend.
cv::Mat plotPanels(const std::vector<PlotPanel>& panels);
// The pixel where (x, y) of panel `panel` is drawn by plotPanels (tests, annotations).
cv::Point plotPixel(const std::vector<PlotPanel>& panels, int panel, double x, double y);
// Colour (BGR) of the index-th curve of a panel.
cv::Scalar curveColour(int index);

// CMC (rank 1..K against identification rate) and verification ROC (false accept rate, log
// axis from 10^-3, against genuine accept rate), one curve per result.
std::vector<PlotPanel> cmcAndRocPanels(const std::vector<NamedMetrics>& results);
// Writes a PNG atomically; throws body_scan_driver::FileWriteError naming the file and the fix.
void writePng(const std::string& path, const cv::Mat& image);

}  // namespace body_gait_id::eval
