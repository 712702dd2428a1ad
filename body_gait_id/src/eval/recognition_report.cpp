#include <body_gait_id/eval/recognition_report.h>
#include <body_scan_driver/atomic_file.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace body_gait_id::eval {
namespace {

void emitProportion(YAML::Emitter& out, const std::string& key, const Proportion& p) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "rate" << YAML::Value << p.rate;
  out << YAML::Key << "count" << YAML::Value << p.count;
  out << YAML::Key << "n" << YAML::Value << p.n;
  out << YAML::Key << "ci95" << YAML::Value << YAML::Flow << YAML::BeginSeq << p.ci_low << p.ci_high
      << YAML::EndSeq;
  out << YAML::EndMap;
}

void emitMetrics(YAML::Emitter& out, const NamedMetrics& named) {
  const RecognitionMetrics& m = named.metrics;
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << named.name;
  out << YAML::Key << "enrolled_probes" << YAML::Value << m.enrolled_probes;
  out << YAML::Key << "non_enrolled_probes" << YAML::Value << m.non_enrolled_probes;
  emitProportion(out, "identification_rate", m.identification);
  out << YAML::Key << "average_pose_error_frames" << YAML::Value << m.average_pose_error;
  out << YAML::Key << "average_cyclic_pose_error_frames" << YAML::Value
      << m.average_cyclic_pose_error;
  if (!named.note.empty()) out << YAML::Key << "note" << YAML::Value << named.note;
  if (named.thesis) {
    out << YAML::Key << "thesis" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "identification_rate_percent" << YAML::Value
        << named.thesis->identification_rate_percent;
    out << YAML::Key << "average_pose_error_frames" << YAML::Value
        << named.thesis->average_pose_error_frames;
    out << YAML::EndMap;
  }
  out << YAML::Key << "cmc" << YAML::Value << YAML::BeginSeq;
  for (std::size_t k = 0; k < m.cmc.size(); ++k) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "rank" << YAML::Value << k + 1;
    out << YAML::Key << "rate" << YAML::Value << m.cmc[k].rate;
    out << YAML::Key << "ci95" << YAML::Value << YAML::Flow << YAML::BeginSeq << m.cmc[k].ci_low
        << m.cmc[k].ci_high << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "verification" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "genuine_scores" << YAML::Value << m.genuine_scores;
  out << YAML::Key << "impostor_scores" << YAML::Value << m.impostor_scores;
  out << YAML::Key << "equal_error_rate" << YAML::Value << m.equal_error_rate;
  out << YAML::Key << "eer_threshold" << YAML::Value << m.eer_threshold;
  out << YAML::Key << "roc_points" << YAML::Value << static_cast<int>(m.roc.size());
  out << YAML::Key << "roc" << YAML::Value << YAML::Comment("[threshold, FAR, FRR]")
      << YAML::BeginSeq;
  const std::size_t points = m.roc.size();
  const std::size_t shown = std::min<std::size_t>(points, kMaxReportedRocPoints);
  for (std::size_t i = 0; i < shown; ++i) {
    const std::size_t index = shown == 1 ? 0 : i * (points - 1) / (shown - 1);
    const RocPoint& p = m.roc[index];
    out << YAML::Flow << YAML::BeginSeq << p.threshold << p.false_accept_rate << p.false_reject_rate
        << YAML::EndSeq;
  }
  out << YAML::EndSeq << YAML::EndMap;
  for (const auto& [key, open_set] :
       {std::pair{"open_set", &m.open_set}, std::pair{"open_set_strict", &m.open_set_strict}}) {
    if (!*open_set) continue;
    const OpenSetResult& o = **open_set;
    out << YAML::Key << key << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "target_fnir" << YAML::Value << o.target_fnir;
    out << YAML::Key << "target_reached" << YAML::Value << o.target_reached;
    out << YAML::Key << "threshold" << YAML::Value << o.threshold;
    emitProportion(out, "fnir", o.fnir);
    emitProportion(out, "fpir", o.fpir);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

std::string percent(double rate) {
  char text[16];
  std::snprintf(text, sizeof(text), "%6.2f", 100 * rate);
  return text;
}

}  // namespace

std::string recognitionReportYaml(const RecognitionReport& report) {
  YAML::Emitter out;
  out.SetDoublePrecision(6);
  out << YAML::Comment("gait recognition evaluation (body_gait_id, thesis 5.8.3-5.8.4)");
  out << YAML::BeginMap;
  out << YAML::Key << "settings" << YAML::Value << YAML::BeginMap;
  for (const auto& [key, value] : report.settings) out << YAML::Key << key << YAML::Value << value;
  out << YAML::EndMap;
  out << YAML::Key << "results" << YAML::Value << YAML::BeginSeq;
  for (const NamedMetrics& named : report.results) emitMetrics(out, named);
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void writeRecognitionReport(const std::string& path, const RecognitionReport& report) {
  body_scan_driver::writeFileAtomically(path, recognitionReportYaml(report));
}

std::string recognitionTable(const std::vector<NamedMetrics>& results) {
  std::string table =
      "features                                    rank-1 %  (95% CI)          pose err  cyclic   "
      "EER %   "
      "thesis: rank-1 %  pose err\n";
  for (const NamedMetrics& r : results) {
    const RecognitionMetrics& m = r.metrics;
    char line[256];
    std::snprintf(line, sizeof(line), "%-42s  %s  [%s, %s]  %8.2f  %6.2f  %6.2f", r.name.c_str(),
                  percent(m.identification.rate).c_str(), percent(m.identification.ci_low).c_str(),
                  percent(m.identification.ci_high).c_str(), m.average_pose_error,
                  m.average_cyclic_pose_error, 100 * m.equal_error_rate);
    table += line;
    if (r.thesis) {
      std::snprintf(line, sizeof(line), "   %14.2f  %8.2f", r.thesis->identification_rate_percent,
                    r.thesis->average_pose_error_frames);
      table += line;
    }
    if (!r.note.empty()) table += "  (" + r.note + ")";
    table += "\n";
  }
  return table;
}

// --- plot
namespace {

constexpr int kPanelWidth = 520, kPanelHeight = 420;
constexpr int kLeft = 70, kRight = 20, kTop = 40, kBottom = 60;  // margins inside a panel
constexpr int kLegendRow = 18;                                   // below the panels

std::string tickLabel(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

std::vector<double> ticksOf(const std::vector<double>& given, double low, double high,
                            bool log_axis = false) {
  if (!given.empty()) return given;
  std::vector<double> ticks;
  if (log_axis) {
    for (double t = std::pow(10.0, std::ceil(std::log10(low) - 1e-9)); t <= high * (1 + 1e-9);
         t *= 10)
      ticks.push_back(t);
    return ticks;
  }
  for (int i = 0; i <= 4; ++i) ticks.push_back(low + i * (high - low) / 4);
  return ticks;
}

}  // namespace

cv::Scalar curveColour(int index) {
  // BGR, told apart in print and by most colour-blind readers (Okabe-Ito order) plus greys.
  static const cv::Scalar kColours[] = {
      {178, 114, 0},  {0, 94, 213}, {115, 158, 0},   {167, 121, 204}, {0, 159, 230}, {233, 180, 86},
      {66, 228, 240}, {0, 0, 0},    {120, 120, 120}, {40, 40, 160},   {160, 160, 0}, {90, 0, 160}};
  return kColours[index % 12];
}

cv::Point plotPixel(const std::vector<PlotPanel>& panels, int panel, double x, double y) {
  const PlotPanel& p = panels.at(panel);
  const double left = panel * kPanelWidth + kLeft, right = (panel + 1) * kPanelWidth - kRight;
  const double top = kTop, bottom = kPanelHeight - kBottom;
  const double u = p.log_x ? (std::log10(std::max(x, p.x_min)) - std::log10(p.x_min)) /
                                 (std::log10(p.x_max) - std::log10(p.x_min))
                           : (x - p.x_min) / (p.x_max - p.x_min);
  const double v = (y - p.y_min) / (p.y_max - p.y_min);
  return {static_cast<int>(std::lround(left + u * (right - left))),
          static_cast<int>(std::lround(bottom - v * (bottom - top)))};
}

cv::Mat plotPanels(const std::vector<PlotPanel>& panels) {
  const cv::Scalar black(0, 0, 0), grey(215, 215, 215);
  // Legends go below the panels, two entries per row, so they never hide a curve.
  std::size_t most_curves = 0;
  for (const PlotPanel& p : panels) most_curves = std::max(most_curves, p.curves.size());
  const int legend_rows = static_cast<int>(most_curves + 1) / 2;
  cv::Mat image(kPanelHeight + kLegendRow * legend_rows + (legend_rows > 0 ? 8 : 0),
                std::max<int>(1, panels.size()) * kPanelWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  auto text = [&](const std::string& s, cv::Point at, double scale) {
    cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, black, 1, cv::LINE_AA);
  };
  for (int i = 0; i < static_cast<int>(panels.size()); ++i) {
    const PlotPanel& p = panels[i];
    const cv::Point top_left = plotPixel(panels, i, p.x_min, p.y_max);
    const cv::Point bottom_right = plotPixel(panels, i, p.x_max, p.y_min);
    text(p.title, {top_left.x + 140, kTop - 18}, 0.55);
    for (double t : ticksOf(p.x_ticks, p.x_min, p.x_max, p.log_x)) {
      const int column = plotPixel(panels, i, t, p.y_min).x;
      cv::line(image, {column, top_left.y}, {column, bottom_right.y}, grey, 1);
      cv::line(image, {column, bottom_right.y}, {column, bottom_right.y + 5}, black, 1);
      text(tickLabel(t), {column - 10, bottom_right.y + 20}, 0.4);
    }
    for (double t : ticksOf(p.y_ticks, p.y_min, p.y_max)) {
      const int row = plotPixel(panels, i, p.x_min, t).y;
      cv::line(image, {top_left.x, row}, {bottom_right.x, row}, grey, 1);
      cv::line(image, {top_left.x - 5, row}, {top_left.x, row}, black, 1);
      text(tickLabel(t), {top_left.x - 45, row + 4}, 0.4);
    }
    cv::rectangle(image, top_left, bottom_right, black, 1);
    text(p.x_label, {(top_left.x + bottom_right.x) / 2 - 60, bottom_right.y + 42}, 0.45);
    // The y label sits above the axis (OpenCV draws no rotated text).
    text(p.y_label, {top_left.x - 60, kTop - 18}, 0.42);
    for (int c = 0; c < static_cast<int>(p.curves.size()); ++c) {
      const PlotCurve& curve = p.curves[c];
      std::vector<cv::Point> polyline;
      for (const cv::Point2d& point : curve.points)
        polyline.push_back(plotPixel(panels, i, point.x, point.y));
      const cv::Scalar colour = curveColour(c);
      if (polyline.size() > 1) cv::polylines(image, polyline, false, colour, 2, cv::LINE_AA);
      if (polyline.size() <= 30)  // markers where the points are few enough to tell apart
        for (const cv::Point& point : polyline) cv::circle(image, point, 3, colour, cv::FILLED);
      const int row = kPanelHeight + kLegendRow * (c / 2) + 12;
      const int column = i * kPanelWidth + 20 + (c % 2) * (kPanelWidth / 2);
      cv::line(image, {column, row - 4}, {column + 20, row - 4}, colour, 2);
      text(curve.label, {column + 26, row}, 0.4);
    }
  }
  return image;
}

std::vector<PlotPanel> cmcAndRocPanels(const std::vector<NamedMetrics>& results) {
  PlotPanel cmc{"CMC", "rank", "identification rate", 1, 5, 0, 1, {}, {}, {}};
  PlotPanel roc{"verification ROC",
                "false accept rate",
                "genuine accept rate",
                1e-3,
                1,
                0,
                1,
                {},
                {},
                {},
                true};
  int max_rank = 1;
  for (const NamedMetrics& r : results) {
    const RecognitionMetrics& m = r.metrics;
    max_rank = std::max<int>(max_rank, m.cmc.size());
    PlotCurve cmc_curve{r.name, {}};
    for (std::size_t k = 0; k < m.cmc.size(); ++k)
      cmc_curve.points.emplace_back(k + 1.0, m.cmc[k].rate);
    cmc.curves.push_back(cmc_curve);
    PlotCurve roc_curve{r.name, {{0.0, 0.0}}};
    for (const RocPoint& p : m.roc)
      roc_curve.points.emplace_back(p.false_accept_rate, 1 - p.false_reject_rate);
    roc.curves.push_back(roc_curve);
  }
  cmc.x_max = std::max(2, max_rank);
  for (int k = 1; k <= cmc.x_max; ++k) cmc.x_ticks.push_back(k);
  // Rates near 1 are what matters: the CMC's y axis starts below the lowest rate shown.
  double lowest = 1;
  for (const PlotCurve& c : cmc.curves)
    for (const cv::Point2d& p : c.points) lowest = std::min(lowest, p.y);
  cmc.y_min = std::max(0.0, std::floor(lowest * 10 - 1) / 10);
  return {cmc, roc};
}

void writePng(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> png;
  if (image.empty() || !cv::imencode(".png", image, png))
    throw body_scan_driver::FileWriteError("cannot encode " + path +
                                           " as PNG: it must be a non-empty 8-bit image");
  body_scan_driver::writeFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace body_gait_id::eval
