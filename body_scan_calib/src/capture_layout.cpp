#include <body_scan_calib/capture_layout.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace body_scan_calib {
namespace fs = std::filesystem;
namespace {

bool startsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

bool isImageFile(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  for (const char* known : {".png", ".bmp", ".pgm", ".tif", ".tiff", ".jpg", ".jpeg"})
    if (extension == known) return true;
  return false;
}

int blockFrames(FrameBlock block, const CaptureBits& bits) {
  switch (block) {
    case FrameBlock::kStripeBits:
      return 2 * bits.stripe_bits;
    case FrameBlock::kCrossBits:
      return 2 * bits.cross_bits;
    default:
      return 1;
  }
}

}  // namespace

const std::vector<CaptureLayout>& captureLayouts() {
  static const std::vector<CaptureLayout> layouts = {
      {"project",
       "pose_",
       "frame_",
       {FrameBlock::kLit, FrameBlock::kDark, FrameBlock::kStripeBits},
       "pose_NN/frame_MM.png: lit, dark, then pattern/inverse per stripe bit (--bits)"},
      {"opencv",
       "",
       "",
       {FrameBlock::kStripeBits, FrameBlock::kCrossBits, FrameBlock::kLit, FrameBlock::kDark},
       "OpenCV structured_light::GrayCodePattern: one folder per pose, images sorted by name: "
       "column bits then row bits as pattern/inverse pairs (MSB first), white, black; bits from "
       "--projector-width/--projector-height"},
  };
  return layouts;
}

const CaptureLayout& captureLayout(const std::string& name) {
  std::string known;
  for (const CaptureLayout& layout : captureLayouts()) {
    if (layout.name == name) return layout;
    known += (known.empty() ? "" : ", ") + layout.name;
  }
  throw std::invalid_argument("unknown capture layout '" + name + "'; known: " + known);
}

int bitsForPixels(int pixels) {
  int bits = 0;
  while ((1 << bits) < pixels) ++bits;
  return bits;
}

CapturedPatternSet loadCapturedPatternSet(const std::string& folder, const CaptureLayout& layout,
                                          const CaptureBits& bits) {
  const bool has_cross = std::find(layout.frame_order.begin(), layout.frame_order.end(),
                                   FrameBlock::kCrossBits) != layout.frame_order.end();
  CaptureBits used = bits;
  if (!has_cross) used.cross_bits = 0;
  for (int b : {used.stripe_bits, used.cross_bits})
    if (b < 0 || b > body_scan_driver::kMaxBits || used.stripe_bits < body_scan_driver::kMinBits)
      throw std::invalid_argument("Gray code bits must be 1.." +
                                  std::to_string(body_scan_driver::kMaxBits) + ", got " +
                                  std::to_string(b));
  std::vector<fs::path> files;
  if (!fs::is_directory(folder))
    throw std::runtime_error("capture folder " + folder + " does not exist or is not a folder");
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && isImageFile(entry.path()) &&
        startsWith(entry.path().filename().string(), layout.frame_prefix))
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  int expected = 0;
  for (FrameBlock block : layout.frame_order) expected += blockFrames(block, used);
  if (static_cast<int>(files.size()) != expected)
    throw std::runtime_error(
        folder + " holds " + std::to_string(files.size()) + " images" +
        (layout.frame_prefix.empty() ? "" : " named " + layout.frame_prefix + "*") + ", the '" +
        layout.name + "' layout with " + std::to_string(used.stripe_bits) + " stripe bits" +
        (has_cross ? " and " + std::to_string(used.cross_bits) + " cross bits" : "") + " needs " +
        std::to_string(expected) + " (" + layout.description +
        "); check --layout and --bits or --projector-width/--projector-height");

  std::vector<cv::Mat> images;
  for (const fs::path& file : files) {
    cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw std::runtime_error("cannot read " + file.string() + " as an image");
    if (!images.empty() && image.size() != images.front().size())
      throw std::runtime_error(file.string() + " differs in size from " + files.front().string() +
                               ": every frame of a pose must have one size");
    images.push_back(image);
  }
  CapturedPatternSet set;
  set.folder = folder;
  cv::Mat lit, dark;
  std::vector<cv::Mat> stripe_bits, cross_bits;
  size_t next = 0;
  for (FrameBlock block : layout.frame_order) {
    const int count = blockFrames(block, used);
    for (int i = 0; i < count; ++i, ++next) {
      if (block == FrameBlock::kLit) lit = images[next];
      if (block == FrameBlock::kDark) dark = images[next];
      if (block == FrameBlock::kStripeBits) stripe_bits.push_back(images[next]);
      if (block == FrameBlock::kCrossBits) cross_bits.push_back(images[next]);
    }
  }
  set.frames = {lit, dark};
  set.frames.insert(set.frames.end(), stripe_bits.begin(), stripe_bits.end());
  if (!cross_bits.empty()) {
    set.cross_frames = {lit, dark};
    set.cross_frames.insert(set.cross_frames.end(), cross_bits.begin(), cross_bits.end());
  }
  return set;
}

std::vector<CapturedPatternSet> loadCapturedPoses(const std::string& folder,
                                                  const CaptureLayout& layout,
                                                  const CaptureBits& bits) {
  if (!fs::is_directory(folder))
    throw std::runtime_error("capture folder " + folder + " does not exist or is not a folder");
  std::vector<fs::path> poses;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    if (entry.is_directory() &&
        startsWith(entry.path().filename().string(), layout.pose_folder_prefix))
      poses.push_back(entry.path());
  std::sort(poses.begin(), poses.end());
  if (poses.empty())
    throw std::runtime_error("no pose folders in " + folder + " for the '" + layout.name +
                             "' layout (" + layout.description + ")" +
                             (layout.pose_folder_prefix.empty()
                                  ? ""
                                  : ": expected " + layout.pose_folder_prefix + "NN"));
  std::vector<CapturedPatternSet> sets;
  for (const fs::path& pose : poses)
    sets.push_back(loadCapturedPatternSet(pose.string(), layout, bits));
  return sets;
}

}  // namespace body_scan_calib
