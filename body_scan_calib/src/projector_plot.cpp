#include <body_scan_calib/projector_plot.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

namespace body_scan_calib {
namespace {

constexpr int kWidth = 900, kPanelHeight = 260, kLeft = 90, kRight = 20, kTop = 30, kBottom = 40;

std::string format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value);
  return text;
}

void drawPanel(
    cv::Mat& image, int panel, const std::string& title, int stripes,
    const std::function<double(const body_scan_driver::StripePlaneProjector&, int)>& value,
    const body_scan_driver::StripePlaneProjector& estimated,
    const body_scan_driver::StripePlaneProjector* reference) {
  const int top = panel * kPanelHeight + kTop, bottom = (panel + 1) * kPanelHeight - kBottom;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const body_scan_driver::StripePlaneProjector* source : {&estimated, reference}) {
    if (!source) continue;
    for (int i = 0; i < source->stripeCount(); ++i) {
      const double y = value(*source, i);
      if (!std::isfinite(y)) continue;
      low = std::min(low, y);
      high = std::max(high, y);
    }
  }
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200);
  cv::putText(image, title, {kLeft, top - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.55, black, 1,
              cv::LINE_AA);
  cv::rectangle(image, {kLeft, top}, {kWidth - kRight, bottom}, black, 1);
  if (!std::isfinite(low)) return;
  if (high - low < 1e-9) {
    low -= 0.5;
    high += 0.5;
  }
  const double margin = 0.05 * (high - low);
  low -= margin;
  high += margin;
  auto to_x = [&](double stripe) {
    return kLeft + stripe / std::max(1, stripes - 1) * (kWidth - kRight - kLeft);
  };
  auto to_y = [&](double y) { return bottom - (y - low) / (high - low) * (bottom - top); };
  for (int tick = 0; tick <= 4; ++tick) {
    const double y = low + tick * (high - low) / 4;
    const int row = static_cast<int>(to_y(y));
    cv::line(image, {kLeft, row}, {kWidth - kRight, row}, grey, 1);
    cv::putText(image, format(y), {5, row + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1,
                cv::LINE_AA);
  }
  // About eight labels whatever the stripe count (a power of two: 32 for 256, 128 for 1024).
  int label_step = 1;
  while (stripes / label_step > 8) label_step *= 2;
  for (int stripe = 0; stripe < stripes; stripe += label_step) {
    const int column = static_cast<int>(to_x(stripe));
    cv::line(image, {column, bottom}, {column, bottom + 4}, black, 1);
    cv::putText(image, std::to_string(stripe), {column - 8, bottom + 18}, cv::FONT_HERSHEY_SIMPLEX,
                0.4, black, 1, cv::LINE_AA);
  }
  cv::putText(image, "stripe number", {kWidth / 2 - 50, bottom + 34}, cv::FONT_HERSHEY_SIMPLEX,
              0.45, black, 1, cv::LINE_AA);
  if (reference) {
    cv::Point previous(-1, -1);
    for (int i = 0; i < reference->stripeCount(); ++i) {
      const double y = value(*reference, i);
      if (!std::isfinite(y)) {
        previous = {-1, -1};
        continue;
      }
      const cv::Point point(static_cast<int>(to_x(i)), static_cast<int>(to_y(y)));
      if (previous.x >= 0) cv::line(image, previous, point, cv::Scalar(0, 0, 220), 1, cv::LINE_AA);
      previous = point;
    }
  }
  for (int i = 0; i < estimated.stripeCount(); ++i) {
    const double y = value(estimated, i);
    if (std::isfinite(y))
      cv::circle(image, {static_cast<int>(to_x(i)), static_cast<int>(to_y(y))}, 2,
                 cv::Scalar(200, 80, 0), cv::FILLED, cv::LINE_AA);
  }
}

}  // namespace

cv::Mat plotProjectorParameters(const body_scan_driver::StripePlaneProjector& estimated,
                                const body_scan_driver::StripePlaneProjector* reference) {
  cv::Mat image(3 * kPanelHeight + 30, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const int stripes = estimated.stripeCount();
  auto parameters = [](const body_scan_driver::StripePlaneProjector& projector, int i) {
    const Eigen::Vector4d& plane = projector.planes[i];
    return plane.allFinite() ? projector.explicitParameters(i)
                             : body_scan_driver::StripePlaneProjector::Explicit{NAN, NAN, NAN};
  };
  drawPanel(
      image, 0, "(a) baseline l_i [mm] (eq 3.6)", stripes,
      [&](const body_scan_driver::StripePlaneProjector& p, int i) {
        return 1e3 * parameters(p, i).baseline;
      },
      estimated, reference);
  drawPanel(
      image, 1, "(b) projection angle theta_i [deg] (eq 3.7)", stripes,
      [&](const body_scan_driver::StripePlaneProjector& p, int i) {
        return parameters(p, i).projection_angle * 180 / M_PI;
      },
      estimated, reference);
  drawPanel(
      image, 2, "(c) tilt angle phi_i [deg] (eq 3.8)", stripes,
      [&](const body_scan_driver::StripePlaneProjector& p, int i) {
        return parameters(p, i).tilt_angle * 180 / M_PI;
      },
      estimated, reference);
  const int legend = 3 * kPanelHeight + 18;
  cv::circle(image, {kLeft + 5, legend - 4}, 3, cv::Scalar(200, 80, 0), cv::FILLED);
  cv::putText(image, "estimated (plane per stripe)", {kLeft + 15, legend}, cv::FONT_HERSHEY_SIMPLEX,
              0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  if (reference) {
    cv::line(image, {kLeft + 300, legend - 4}, {kLeft + 320, legend - 4}, cv::Scalar(0, 0, 220), 1);
    cv::putText(image, "simulator truth", {kLeft + 330, legend}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  return image;
}

}  // namespace body_scan_calib
