// The YAML report reads back with the measured figures; the PNG plot has its curves where the
// data put them.
#include <body_gait_id/eval/recognition_report.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

namespace body_gait_id::eval {
namespace {

namespace fs = std::filesystem;

fs::path scratchFolder(const std::string& name) {
  const fs::path folder =
      fs::temp_directory_path() / ("test_recognition_report_" + std::to_string(::getpid())) / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

NamedMetrics toyResult() {
  const std::vector<ProbeResult> probes = {
      {1, 1, true, {{1, 2, 0.1}, {2, 1, 0.5}}},
      {2, 4, true, {{1, 4, 0.3}, {2, 4, 0.4}}},  // wrong at rank 1
      {3, 1, false, {{2, 1, 0.2}, {1, 1, 0.7}}},
  };
  return {"3D dynamic", evaluateRecognition(probes), ThesisFigures{98.96, 0.41}, "a note"};
}

bool near(const cv::Vec3b& pixel, const cv::Scalar& colour, int tolerance) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(pixel[c] - static_cast<int>(colour[c])) > tolerance) return false;
  return true;
}

TEST(RecognitionReport, YamlReadsBackTheFigures) {
  const fs::path folder = scratchFolder("yaml");
  RecognitionReport report{{{"protocol", "thesis"}, {"subjects", "2"}}, {toyResult()}};
  const std::string path = (folder / "sub" / "report.yaml").string();
  writeRecognitionReport(path, report);
  // Atomic: only the report is left in the folder (no temporary file).
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder / "sub")) files += entry.is_regular_file();
  EXPECT_EQ(files, 1);

  const YAML::Node root = YAML::LoadFile(path);
  EXPECT_EQ(root["settings"]["protocol"].as<std::string>(), "thesis");
  const YAML::Node result = root["results"][0];
  EXPECT_EQ(result["name"].as<std::string>(), "3D dynamic");
  EXPECT_EQ(result["note"].as<std::string>(), "a note");
  EXPECT_DOUBLE_EQ(result["identification_rate"]["rate"].as<double>(), 0.5);
  EXPECT_EQ(result["identification_rate"]["n"].as<int>(), 2);
  EXPECT_EQ(result["identification_rate"]["ci95"].size(), 2u);
  EXPECT_DOUBLE_EQ(result["average_pose_error_frames"].as<double>(), 0.5);  // (1 + 0) / 2
  EXPECT_DOUBLE_EQ(result["thesis"]["identification_rate_percent"].as<double>(), 98.96);
  ASSERT_EQ(result["cmc"].size(), 2u);
  EXPECT_DOUBLE_EQ(result["cmc"][1]["rate"].as<double>(), 1.0);
  EXPECT_EQ(result["verification"]["genuine_scores"].as<int>(), 2);
  EXPECT_EQ(result["verification"]["roc"].size(), 6u);  // 2 genuine + 4 impostor scores
  EXPECT_DOUBLE_EQ(result["open_set"]["fpir"]["n"].as<double>(), 1);
}

TEST(RecognitionReport, LongRocIsThinnedKeepingBothEnds) {
  NamedMetrics result = toyResult();
  result.metrics.roc.clear();
  for (int i = 0; i < 1000; ++i) result.metrics.roc.push_back({i * 1.0, i / 999.0, 1 - i / 999.0});
  const YAML::Node root = YAML::Load(recognitionReportYaml({{}, {result}}));
  const YAML::Node roc = root["results"][0]["verification"]["roc"];
  ASSERT_EQ(roc.size(), static_cast<std::size_t>(kMaxReportedRocPoints));
  EXPECT_DOUBLE_EQ(roc[0][0].as<double>(), 0.0);
  EXPECT_DOUBLE_EQ(roc[kMaxReportedRocPoints - 1][0].as<double>(), 999.0);
  EXPECT_EQ(root["results"][0]["verification"]["roc_points"].as<int>(), 1000);
}

TEST(RecognitionReport, WritingIntoAFileGivesAClearError) {
  const fs::path folder = scratchFolder("blocked");
  const std::string file = (folder / "not_a_folder").string();
  writeRecognitionReport(file, {});
  EXPECT_THROW(writeRecognitionReport(file + "/report.yaml", {}), std::runtime_error);
}

TEST(RecognitionPlot, CurvesAreDrawnWhereTheDataPutsThem) {
  std::vector<PlotPanel> panels = {
      {"CMC", "rank", "rate", 1, 5, 0, 1, {1, 2, 3, 4, 5}, {}, {{"flat", {{1, 0.6}, {5, 0.6}}}}},
      {"ROC",
       "FAR",
       "GAR",
       0,
       1,
       0,
       1,
       {},
       {},
       {{"a", {{0, 0}, {1, 1}}}, {"b", {{0, 0.9}, {1, 0.9}}}}},
  };
  const fs::path path = scratchFolder("png") / "plot.png";
  writePng(path.string(), plotPanels(panels));
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << path;
  EXPECT_EQ(image.cols, 2 * 520);
  EXPECT_GT(image.rows, 420);  // the panels and one legend row below them
  // Legend below the second panel: its first entry's line sample in the first curve's colour.
  EXPECT_TRUE(near(image.at<cv::Vec3b>(420 + 12 - 4, 520 + 20 + 10), curveColour(0), 30));
  EXPECT_TRUE(near(image.at<cv::Vec3b>(420 + 12 - 4, 520 + 20 + 260 + 10), curveColour(1), 30));
  // On the curves, away from ticks and points: the curve's colour.
  EXPECT_TRUE(near(image.at<cv::Vec3b>(plotPixel(panels, 0, 2.5, 0.6)), curveColour(0), 30));
  EXPECT_TRUE(near(image.at<cv::Vec3b>(plotPixel(panels, 1, 0.4, 0.4)), curveColour(0), 30));
  EXPECT_TRUE(near(image.at<cv::Vec3b>(plotPixel(panels, 1, 0.4, 0.9)), curveColour(1), 30));
  // Off the curves, grid and legend: white.
  EXPECT_TRUE(near(image.at<cv::Vec3b>(plotPixel(panels, 0, 2.5, 0.35)), {255, 255, 255}, 0));
  EXPECT_TRUE(near(image.at<cv::Vec3b>(plotPixel(panels, 1, 0.1, 0.6)), {255, 255, 255}, 0));
  // The frame of the second panel is black at its corner.
  EXPECT_TRUE(near(image.at<cv::Vec3b>(plotPixel(panels, 1, 0, 1)), {0, 0, 0}, 0));
}

TEST(RecognitionPlot, LogAxisPutsDecadesEvenlyApart) {
  std::vector<PlotPanel> panels(1);
  panels[0].x_min = 1e-3;
  panels[0].log_x = true;
  const int x_milli = plotPixel(panels, 0, 1e-3, 0).x, x_centi = plotPixel(panels, 0, 1e-2, 0).x;
  const int x_deci = plotPixel(panels, 0, 0.1, 0).x, x_one = plotPixel(panels, 0, 1, 0).x;
  EXPECT_NEAR(x_centi - x_milli, x_deci - x_centi, 1);
  EXPECT_NEAR(x_one - x_deci, x_deci - x_centi, 1);
  EXPECT_EQ(plotPixel(panels, 0, 0.0, 0).x, x_milli);  // FAR 0 is drawn at the axis' start
  const cv::Mat image = plotPanels(panels);
  // The decade ticks' grid lines (grey) are drawn at those columns, mid-height.
  const int row = plotPixel(panels, 0, 1e-2, 0.375).y;
  EXPECT_TRUE(near(image.at<cv::Vec3b>(row, x_centi), {215, 215, 215}, 0));
  EXPECT_TRUE(near(image.at<cv::Vec3b>(row, x_deci), {215, 215, 215}, 0));
}

TEST(RecognitionPlot, CmcAndRocPanelsOfResults) {
  const std::vector<PlotPanel> panels = cmcAndRocPanels({toyResult(), toyResult()});
  ASSERT_EQ(panels.size(), 2u);
  ASSERT_EQ(panels[0].curves.size(), 2u);
  ASSERT_EQ(panels[0].curves[0].points.size(), 2u);  // ranks 1 and 2
  EXPECT_DOUBLE_EQ(panels[0].curves[0].points[0].y, 0.5);
  EXPECT_DOUBLE_EQ(panels[0].y_min, 0.4);  // below the lowest rate shown
  // ROC from (0, 0) to (1, 1) through every threshold.
  EXPECT_EQ(panels[1].curves[0].points.size(), 7u);
  EXPECT_DOUBLE_EQ(panels[1].curves[0].points.back().x, 1.0);
  EXPECT_DOUBLE_EQ(panels[1].curves[0].points.back().y, 1.0);
}

}  // namespace
}  // namespace body_gait_id::eval
