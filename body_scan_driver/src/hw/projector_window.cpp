#include <body_scan_driver/hw/projector_window.h>

#include <cstdlib>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

// X11 last: its macros (Success, Complex, Status) break Eigen and OpenCV headers.
#include <X11/Xlib.h>
#include <X11/Xutil.h>

namespace body_scan_driver::hw {
namespace {

Display* openDisplay(const std::string& name) {
  Display* display = XOpenDisplay(name.empty() ? nullptr : name.c_str());
  if (!display) {
    const char* env = std::getenv("DISPLAY");
    const std::string shown = !name.empty() ? name : (env ? std::string(env) : "$DISPLAY unset");
    throw std::runtime_error("cannot open X display '" + shown +
                             "': set the pair's projector_display to the X display the projector "
                             "is attached to (e.g. :0) and check DISPLAY/XAUTHORITY access");
  }
  return display;
}

int checkedScreen(Display* display, int screen) {
  if (screen < 0) return DefaultScreen(display);
  if (screen >= ScreenCount(display)) {
    const int count = ScreenCount(display);
    XCloseDisplay(display);
    throw std::runtime_error("X screen " + std::to_string(screen) +
                             " does not exist (the display has " + std::to_string(count) +
                             "): set projector_screen to 0.." + std::to_string(count - 1));
  }
  return screen;
}

// Pixel of a 24/32-bit TrueColor visual from its channel masks.
struct ChannelShift {
  int red, green, blue;
};
int shiftOf(unsigned long mask) {
  int shift = 0;
  while (mask && !(mask & 1)) {
    mask >>= 1;
    ++shift;
  }
  return shift;
}

}  // namespace

struct ProjectorWindow::X11 {
  std::string name;
  Display* display = nullptr;
  int screen = 0;
  Window window = 0;
  GC gc = nullptr;
  Visual* visual = nullptr;
  int depth = 0;
  int width = 0, height = 0;
  ChannelShift shift{};
  std::vector<uint32_t> pixels;  // 32 bits per pixel, as XPutImage's ZPixmap expects
  XImage* image = nullptr;
};

ProjectorWindow::ProjectorWindow(const std::string& display, int screen) : x_(new X11) {
  x_->name = display;
  x_->display = openDisplay(display);
  x_->screen = checkedScreen(x_->display, screen);
  Display* d = x_->display;
  x_->width = DisplayWidth(d, x_->screen);
  x_->height = DisplayHeight(d, x_->screen);
  XVisualInfo info;
  if (!XMatchVisualInfo(d, x_->screen, 24, TrueColor, &info)) {
    XCloseDisplay(d);
    throw std::runtime_error(
        "X screen has no 24-bit TrueColor visual: run the projector's "
        "screen at 24-bit colour depth");
  }
  x_->visual = info.visual;
  x_->depth = info.depth;
  x_->shift = {shiftOf(info.red_mask), shiftOf(info.green_mask), shiftOf(info.blue_mask)};

  XSetWindowAttributes attributes{};
  attributes.override_redirect = True;  // no window manager: no border, no title, no placement
  attributes.background_pixel = BlackPixel(d, x_->screen);
  attributes.border_pixel = 0;
  attributes.colormap = XCreateColormap(d, RootWindow(d, x_->screen), x_->visual, AllocNone);
  attributes.event_mask = ExposureMask | StructureNotifyMask;
  x_->window = XCreateWindow(
      d, RootWindow(d, x_->screen), 0, 0, x_->width, x_->height, 0, x_->depth, InputOutput,
      x_->visual, CWOverrideRedirect | CWBackPixel | CWBorderPixel | CWColormap | CWEventMask,
      &attributes);
  XStoreName(d, x_->window, "body_scan projector");
  // An empty cursor: the pointer must not appear in the patterns.
  char empty_bits[8] = {};
  const Pixmap empty = XCreateBitmapFromData(d, x_->window, empty_bits, 8, 8);
  XColor black{};
  const Cursor cursor = XCreatePixmapCursor(d, empty, empty, &black, &black, 0, 0);
  XDefineCursor(d, x_->window, cursor);
  XFreeCursor(d, cursor);
  XFreePixmap(d, empty);
  x_->gc = XCreateGC(d, x_->window, 0, nullptr);
  XMapRaised(d, x_->window);
  // Wait until the window is on screen, or the first pattern could be drawn into nothing.
  XEvent event;
  do XWindowEvent(d, x_->window, StructureNotifyMask, &event);
  while (event.type != MapNotify);
  x_->pixels.assign(static_cast<size_t>(x_->width) * x_->height, 0);
  x_->image =
      XCreateImage(d, x_->visual, x_->depth, ZPixmap, 0, reinterpret_cast<char*>(x_->pixels.data()),
                   x_->width, x_->height, 32, 0);
  XSync(d, False);
}

ProjectorWindow::~ProjectorWindow() {
  if (x_->image) {
    x_->image->data = nullptr;  // owned by pixels, not by Xlib
    XDestroyImage(x_->image);
  }
  if (x_->gc) XFreeGC(x_->display, x_->gc);
  if (x_->window) XDestroyWindow(x_->display, x_->window);
  XCloseDisplay(x_->display);
}

cv::Size ProjectorWindow::resolution() const { return {x_->width, x_->height}; }

std::string ProjectorWindow::displayName() const { return DisplayString(x_->display); }

void ProjectorWindow::show(const cv::Mat& image) {
  if (image.size() != resolution() || (image.type() != CV_8UC1 && image.type() != CV_8UC3))
    throw std::invalid_argument("projector image must be 8-bit grey or RGB of " +
                                std::to_string(x_->width) + "x" + std::to_string(x_->height));
  const ChannelShift s = x_->shift;
  for (int v = 0; v < image.rows; ++v) {
    uint32_t* out = x_->pixels.data() + static_cast<size_t>(v) * x_->width;
    if (image.type() == CV_8UC1) {
      const uint8_t* in = image.ptr<uint8_t>(v);
      for (int u = 0; u < image.cols; ++u)
        out[u] =
            (uint32_t{in[u]} << s.red) | (uint32_t{in[u]} << s.green) | (uint32_t{in[u]} << s.blue);
    } else {
      const cv::Vec3b* in = image.ptr<cv::Vec3b>(v);
      for (int u = 0; u < image.cols; ++u)
        out[u] = (uint32_t{in[u][0]} << s.red) | (uint32_t{in[u][1]} << s.green) |
                 (uint32_t{in[u][2]} << s.blue);
    }
  }
  XPutImage(x_->display, x_->window, x_->gc, x_->image, 0, 0, 0, 0, x_->width, x_->height);
  XSync(x_->display, False);  // drawn when this returns: frame counting starts from here
}

cv::Mat grabScreen(const std::string& display_name, int screen) {
  Display* display = openDisplay(display_name);
  screen = checkedScreen(display, screen);
  const int width = DisplayWidth(display, screen), height = DisplayHeight(display, screen);
  XImage* image =
      XGetImage(display, RootWindow(display, screen), 0, 0, width, height, AllPlanes, ZPixmap);
  if (!image) {
    XCloseDisplay(display);
    throw std::runtime_error("XGetImage failed on display '" + display_name + "'");
  }
  const int r = shiftOf(image->red_mask), g = shiftOf(image->green_mask),
            b = shiftOf(image->blue_mask);
  cv::Mat3b rgb(height, width);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const unsigned long pixel = XGetPixel(image, u, v);
      rgb(v, u) = cv::Vec3b(static_cast<uint8_t>(pixel >> r), static_cast<uint8_t>(pixel >> g),
                            static_cast<uint8_t>(pixel >> b));
    }
  XDestroyImage(image);
  XCloseDisplay(display);
  return rgb;
}

}  // namespace body_scan_driver::hw
