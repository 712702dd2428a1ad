#include <body_scan_calib/calibration_capture.h>
#include <body_scan_calib/calibration_rig.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

namespace body_scan_calib {

int removeOldCaptures(const std::string& folder) {
  int removed = 0;
  std::error_code error;
  for (const std::filesystem::directory_entry& entry :
       std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    const bool pose = name.size() == 7 && name.rfind("pose_", 0) == 0 &&
                      std::isdigit(static_cast<unsigned char>(name[5])) &&
                      std::isdigit(static_cast<unsigned char>(name[6]));
    if (entry.is_directory() && (pose || name == body_scan_calib::kSphereFolderName)) {
      std::filesystem::remove_all(entry.path());
      ++removed;
    }
  }
  return removed;
}

std::vector<std::vector<size_t>> groupConsecutiveScanIds(const std::vector<uint32_t>& scan_ids) {
  std::vector<std::vector<size_t>> groups;
  for (size_t i = 0; i < scan_ids.size(); ++i) {
    if (groups.empty() || scan_ids[i] != scan_ids[i - 1] + 1) groups.emplace_back();
    groups.back().push_back(i);
  }
  return groups;
}

}  // namespace body_scan_calib
