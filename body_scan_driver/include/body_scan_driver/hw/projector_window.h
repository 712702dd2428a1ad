// The projector of a DIY pair is a display: a borderless full-screen X11 window on a
// configured display and screen shows each pattern frame. The window is
// override-redirect (no window manager decorations or placement) and hides the cursor.
// X11 headers stay in the .cpp.
#pragma once

#include <body_scan_driver/hw/pattern_sequencer.h>

#include <memory>
#include <string>

namespace body_scan_driver::hw {

class ProjectorWindow : public PatternProjector {
 public:
  // display: an X display name such as ":0" (empty: $DISPLAY); screen: -1 for the display's
  // default screen. Throws std::runtime_error naming the display and the fix if it cannot open.
  ProjectorWindow(const std::string& display, int screen);
  ~ProjectorWindow() override;
  ProjectorWindow(const ProjectorWindow&) = delete;
  ProjectorWindow& operator=(const ProjectorWindow&) = delete;

  cv::Size resolution() const override;
  // CV_8UC1 or CV_8UC3 (RGB) of resolution(); returns after the X server has drawn it (XSync).
  void show(const cv::Mat& image) override;
  std::string displayName() const;

 private:
  struct X11;
  std::unique_ptr<X11> x_;
};

// Grabs the root window of `display`/`screen` as CV_8UC3 RGB (XGetImage): what a projector
// attached as that screen is showing. Used by the tests and measure_projector_latency.
cv::Mat grabScreen(const std::string& display, int screen);

}  // namespace body_scan_driver::hw
