#include <body_scan_calib/capture_folder.h>
#include <body_scan_driver/atomic_file.h>

#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace body_scan_calib {
namespace fs = std::filesystem;
namespace {

std::string frameName(size_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%02zu.png", index);
  return name;
}

}  // namespace

std::string poseFolderName(int pose) {
  char name[32];
  std::snprintf(name, sizeof(name), "pose_%02d", pose);
  return name;
}

void writePngAtomically(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> png;
  if (image.empty() || !cv::imencode(".png", image, png))
    throw std::runtime_error("cannot encode " + path +
                             " as PNG: it must be a non-empty 8-bit image");
  body_scan_driver::writeFileAtomically(path, std::string(png.begin(), png.end()));
}

void savePatternFrames(const std::string& folder, const std::vector<cv::Mat>& frames) {
  for (size_t f = 0; f < frames.size(); ++f)
    writePngAtomically((fs::path(folder) / frameName(f)).string(), frames[f]);
}

std::vector<cv::Mat> loadPatternFrames(const std::string& folder,
                                       const body_scan_driver::PatternLayout& layout) {
  std::vector<cv::Mat> frames;
  for (int f = 0; f < layout.frameCount(); ++f) {
    const fs::path file = fs::path(folder) / frameName(f);
    cv::Mat frame = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (frame.empty())
      throw std::runtime_error("cannot read " + file.string() + ": a pattern set of " +
                               std::to_string(layout.bits()) + " bits with inverse frames has " +
                               std::to_string(layout.frameCount()) +
                               " frames frame_00.png..; check the folder or --bits");
    frames.push_back(frame);
  }
  return frames;
}

std::vector<std::vector<cv::Mat>> loadPoseCaptures(const std::string& folder,
                                                   const body_scan_driver::PatternLayout& layout) {
  std::vector<std::vector<cv::Mat>> poses;
  for (int pose = 0;; ++pose) {
    const fs::path path = fs::path(folder) / poseFolderName(pose);
    if (!fs::is_directory(path)) break;
    poses.push_back(loadPatternFrames(path.string(), layout));
  }
  if (poses.empty())
    throw std::runtime_error("no " + (fs::path(folder) / poseFolderName(0)).string() +
                             ": the folder needs pose_00, pose_01, ... with the pattern frames "
                             "frame_00.png.. of each board pose");
  return poses;
}

}  // namespace body_scan_calib
