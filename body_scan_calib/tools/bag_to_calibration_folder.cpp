// Converts calibration captures recorded in a bag into the image folder calibrate_pair reads
// (FOLDER/pose_NN/frame_MM.png, optional FOLDER/spheres): each run of consecutive scan ids is
// one board placement, its pattern sets averaged per pattern.
#include <body_scan_calib/calibration_bag.h>
#include <body_scan_driver/tools/command_line.h>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app(
      "Converts calibration captures recorded in a bag into the image folder calibrate_pair "
      "reads (FOLDER/pose_NN/frame_MM.png, optional FOLDER/spheres): each run of consecutive "
      "scan ids is one board placement, its pattern sets averaged per pattern.",
      "bag_to_calibration_folder");
  std::string bag, folder;
  body_scan_calib::BagConversionOptions options;
  app.add_option("BAG", bag,
                 "body_scan_msgs/PatternSet messages of one pair; each run of consecutive scan "
                 "ids is one board placement (repeated exposures, averaged), e.g. scan ids "
                 "1000..1015 for the first pose, 2000..2015 for the second "
                 "(capture_calibration_views records that way)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("FOLDER", folder,
                 "written as FOLDER/pose_NN/frame_MM.png, the layout of calibrate_pair --images")
      ->required();
  app.add_option("--topic", options.topic,
                 "read only this topic (default: every PatternSet topic)");
  app.add_option("--pair-id", options.pair_id,
                 "keep only this pair's sets (needed when the bag holds several pairs)");
  app.add_flag("--spheres-last", options.spheres_last,
               "the last placement is the five evaluation spheres -> FOLDER/spheres");
  if (const auto status = body_scan_driver::tools::parseCommandLine(app, argc, argv))
    return *status;
  try {
    const body_scan_calib::BagConversionResult result = body_scan_calib::bagToCalibrationFolder(
        bag, folder, options,
        [](const std::string& line) { std::cout << "  " << line << std::endl; });
    std::cout << result.pattern_sets << " pattern sets -> " << result.folders.size()
              << " folders in " << folder << "; calibrate with:\n  rosrun body_scan_calib "
              << "calibrate_pair --images " << folder << " --bits " << result.bits << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
