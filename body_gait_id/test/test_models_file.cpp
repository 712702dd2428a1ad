// YAML body models (CLI enrolment input) and the gallery export (YAML, CSV).
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_id/models_file.h>
#include <gtest/gtest.h>
#include <ros/package.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace body_gait_id {
namespace {

// The shipped noise weights of the sampler rig (config/), found through rospack.
std::string featureNoiseFile() {
  return ros::package::getPath("body_gait_id") + "/config/feature_noise_sampler.yaml";
}

namespace fs = std::filesystem;

class ModelsFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("test_models_file_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  static body_gait_model::BodyModel pose(double stature, double swing) {
    body_gait_model::BodyModel m = body_gait_model::standingModel(stature);
    m.p << 0.1, 0.2, 0.95, 0.01, 1.0 / 3.0, -0.02;
    m.setJointAngles(body_gait_model::kRightUpperLeg, swing, 0.05);
    m.setJointAngles(body_gait_model::kLeftUpperLeg, -swing, -0.05);
    return m;
  }
  fs::path dir_;
};

TEST_F(ModelsFileTest, WrittenModelsReadBackExactly) {
  std::vector<body_gait_model::BodyModel> models = {pose(1.7, 0.3), pose(1.7, 0.1), pose(1.7, -0.3),
                                                    pose(1.7, -0.1)};
  models[2].shape.hip_rise = 0.0712345678901234;
  std::ostringstream text;
  writeBodyModels(text, models);
  const std::vector<body_gait_model::BodyModel> read = readBodyModels(write("m.yaml", text.str()));
  ASSERT_EQ(read.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(read[i].p, models[i].p);
    EXPECT_EQ(read[i].q, models[i].q);
    EXPECT_EQ(read[i].r, models[i].r);
    EXPECT_EQ(read[i].shape.proximal_radius, models[i].shape.proximal_radius);
    EXPECT_EQ(read[i].shape.hip_rise, models[i].shape.hip_rise);
  }
}

// `rostopic echo` output: one BodyModel message per document, with fields we ignore.
TEST_F(ModelsFileTest, ReadsBodyModelMessagesAsRostopicEchoPrintsThem) {
  std::string text;
  for (double swing : {0.3, -0.2}) {
    std::ostringstream one;
    writeBodyModels(one, {pose(1.8, swing)});
    std::string pose_text = one.str();
    // writeBodyModels nests the pose under "poses:\n  - "; rostopic echo prints it flat.
    YAML::Node node = YAML::Load(pose_text)["poses"][0];
    node["header"]["frame_id"] = "world";
    node["segment_names"].push_back("upper_torso");
    node["rms_distance"] = 0.012;
    YAML::Emitter out;
    out.SetDoublePrecision(17);
    out << node;
    text += std::string(out.c_str()) + "\n---\n";
  }
  const std::vector<body_gait_model::BodyModel> read = readBodyModels(write("echo.yaml", text));
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].q, pose(1.8, -0.2).q);
  EXPECT_EQ(read[0].r, pose(1.8, 0.3).r);
}

TEST_F(ModelsFileTest, BadFilesNameTheProblem) {
  const auto error = [](const std::string& path) {
    try {
      readBodyModels(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error((dir_ / "missing.yaml").string()).find("cannot be read"), std::string::npos);
  EXPECT_NE(error(write("a.yaml", "models: []\n")).find("no 'poses:' list and no BodyModel"),
            std::string::npos);
  const std::string short_q = error(write("b.yaml",
                                          "poses:\n  - {p: [0,0,0,0,0,0], q: [1, 2], "
                                          "r: [1,1,1,1,1,1,1,1,1,1,1,1]}\n"));
  EXPECT_NE(short_q.find("pose 1: 'q' must be a list of 22 numbers"), std::string::npos) << short_q;
  EXPECT_NE(error(write("c.yaml", "poses: [\n")).find("not valid YAML"), std::string::npos);
}

TEST_F(ModelsFileTest, ExportHoldsEverySubjectAndPose) {
  GalleryDatabase db((dir_ / "g.db").string());
  std::vector<PoseRecord> poses;
  for (int n = 0; n < 3; ++n) poses.push_back({0, 0, n + 1, pose(1.6 + 0.01 * n, 0.1 * n)});
  db.enroll({"Smith, \"Jo\"", "female", 30}, {"/a.bag"}, poses);
  db.enroll({"Lee", "male", 40}, {}, poses);

  std::ostringstream yaml;
  exportGalleryYaml(db, yaml);
  const YAML::Node root = YAML::Load(yaml.str());
  ASSERT_EQ(root["subjects"].size(), 2u);
  EXPECT_EQ(root["subjects"][0]["name"].as<std::string>(), "Smith, \"Jo\"");
  EXPECT_EQ(root["subjects"][0]["scans"][0].as<std::string>(), "/a.bag");
  ASSERT_EQ(root["subjects"][1]["poses"].size(), 3u);
  EXPECT_EQ(root["subjects"][1]["poses"][2]["frame"].as<int>(), 3);
  EXPECT_EQ(root["subjects"][1]["poses"][2]["q"][16].as<double>(), poses[2].model.q[16]);
  EXPECT_EQ(root["normalization_3d"]["sigma_dynamic"].size(), 22u);

  std::ostringstream csv;
  exportGalleryCsv(db, csv);
  std::istringstream lines(csv.str());
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 7u);  // header + 6 poses
  EXPECT_EQ(std::count(rows[0].begin(), rows[0].end(), ','), 4 + 22 + 12 - 1);
  EXPECT_EQ(rows[1].rfind("1,\"Smith, \"\"Jo\"\"\",0,1,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[6].rfind("2,Lee,0,3,", 0), 0u) << rows[6];
}

// The feature noise file (evaluate_gait_id --write-noise -> gait_id_node ~feature_noise).
TEST_F(ModelsFileTest, FeatureNoiseRoundTripAndErrors) {
  FeatureNoise noise{Eigen::VectorXd::LinSpaced(22, 0.01, 0.3),
                     Eigen::VectorXd::LinSpaced(12, 0.002, 0.015),
                     Eigen::VectorXd::LinSpaced(kShapeSize, 0.0001, 0.008)};
  const std::string path = (dir_ / "noise.yaml").string();
  std::ofstream(path) << featureNoiseYaml(noise, "test");
  const FeatureNoise read = readFeatureNoise(path);
  EXPECT_LT((read.dynamic - noise.dynamic).cwiseQuotient(noise.dynamic).cwiseAbs().maxCoeff(),
            1e-5);
  EXPECT_LT((read.statics - noise.statics).cwiseQuotient(noise.statics).cwiseAbs().maxCoeff(),
            1e-5);
  EXPECT_LT((read.shape - noise.shape).cwiseQuotient(noise.shape).cwiseAbs().maxCoeff(), 1e-5);
  const auto error = [&path](const std::string& text) {
    std::ofstream(path) << text;
    try {
      readFeatureNoise(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string short_list = error("dynamic: [1, 2]\nstatics: []\nshape: []\n");
  EXPECT_NE(short_list.find("'dynamic' must be a list of 22"), std::string::npos) << short_list;
  EXPECT_NE(short_list.find("--write-noise"), std::string::npos) << short_list;
  std::string negative = featureNoiseYaml(noise, "test");
  negative.replace(negative.find("statics: [") + 10, 1, "-");
  EXPECT_NE(error(negative).find("'statics'[0] is not a non-negative number"), std::string::npos)
      << error(negative);
  EXPECT_NE(error("{").find(path), std::string::npos);
  // The shipped file is valid.
  EXPECT_NO_THROW(readFeatureNoise(featureNoiseFile()));
}

}  // namespace
}  // namespace body_gait_id
