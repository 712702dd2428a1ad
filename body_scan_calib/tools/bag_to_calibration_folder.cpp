// Converts calibration captures recorded in a bag into the image folder calibrate_pair reads
// (FOLDER/pose_NN/frame_MM.png, optional FOLDER/spheres): each run of consecutive scan ids is
// one board placement, its pattern sets averaged per pattern.
#include <body_scan_calib/calibration_bag.h>

#include <iostream>

namespace {

constexpr const char* kUsage = R"(usage: bag_to_calibration_folder BAG FOLDER [options]
  BAG     body_scan_msgs/PatternSet messages of one pair; each run of consecutive scan ids is
          one board placement (repeated exposures, averaged), e.g. scan ids 1000..1015 for the
          first pose, 2000..2015 for the second (capture_calibration_views records that way)
  FOLDER  written as FOLDER/pose_NN/frame_MM.png, the layout of calibrate_pair --images
options:
  --topic TOPIC      read only this topic (default: every PatternSet topic)
  --pair-id ID       keep only this pair's sets (needed when the bag holds several pairs)
  --spheres-last     the last placement is the five evaluation spheres -> FOLDER/spheres
)";

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  body_scan_calib::BagConversionOptions options;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string argument = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(argument + " needs a value");
        return argv[++i];
      };
      if (argument == "--topic")
        options.topic = value();
      else if (argument == "--pair-id")
        options.pair_id = value();
      else if (argument == "--spheres-last")
        options.spheres_last = true;
      else if (argument == "-h" || argument == "--help") {
        std::cout << kUsage;
        return 0;
      } else if (!argument.empty() && argument[0] == '-')
        throw std::invalid_argument("unknown option " + argument);
      else
        positional.push_back(argument);
    }
    if (positional.size() != 2) throw std::invalid_argument("give BAG and FOLDER");
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    const body_scan_calib::BagConversionResult result = body_scan_calib::bagToCalibrationFolder(
        positional[0], positional[1], options,
        [](const std::string& line) { std::cout << "  " << line << std::endl; });
    std::cout << result.pattern_sets << " pattern sets -> " << result.folders.size()
              << " folders in " << positional[1] << "; calibrate with:\n  rosrun body_scan_calib "
              << "calibrate_pair --images " << positional[1] << " --bits " << result.bits
              << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
