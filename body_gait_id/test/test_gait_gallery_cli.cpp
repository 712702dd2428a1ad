// gait_gallery CLI end to end on a temporary gallery: enrol two simulated people from YAML
// files of their 4 representative poses, list, identify (their own poses: frames 1, 6, 11, 16
// with score 0), export CSV, remove; usage and database errors exit non-zero with a message; a
// recorded walk session (a bag of BodyModel messages) enrolled and identified with --bag.
#include <body_gait_id/models_file.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/eval/skeleton_model.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <gtest/gtest.h>
#include <ros/package.h>
#include <rosbag/bag.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace body_gait_id {
namespace {

// The shipped noise weights of the sampler rig (config/), found through rospack.
std::string featureNoiseFile() {
  return ros::package::getPath("body_gait_id") + "/config/feature_noise_sampler.yaml";
}

namespace fs = std::filesystem;

struct CliRun {
  int status;
  std::string output;  // stdout and stderr
};

class GaitGalleryCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("test_gait_gallery_cli_" + std::to_string(getpid()));
    fs::create_directories(dir_);
    database_ = (dir_ / "gallery.db").string();
    const auto people = body_gait_model::eval::simulatedPeople(2, 3);
    for (int person = 0; person < 2; ++person) {
      std::vector<body_gait_model::BodyModel> models;
      for (int index = 1; index <= 4; ++index)
        models.push_back(body_gait_model::eval::modelFromSkeleton(
            body_gait_model::eval::walkingSubject(people[person], index, 0)));
      std::ofstream out(models_file(person));
      writeBodyModels(out, models);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string models_file(int person) const {
    return (dir_ / ("walk_" + std::to_string(person) + ".yaml")).string();
  }
  CliRun run(const std::string& arguments, const std::string& database = "") const {
    const std::string command = std::string(GAIT_GALLERY) + " --database " +
                                (database.empty() ? database_ : database) + " " + arguments +
                                " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    CliRun result{-1, ""};
    char buffer[4096];
    for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;)
      result.output.append(buffer, n);
    const int status = pclose(pipe);
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
  }
  fs::path dir_;
  std::string database_;
};

TEST_F(GaitGalleryCli, EnrolListIdentifyExportRemove) {
  CliRun r = run("enroll --name Ada --gender female --age 36 --models " + models_file(0) +
                 " --scan /scans/ada.bag");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("enrolled 'Ada' as subject 1 (40 poses)"), std::string::npos) << r.output;
  r = run("enroll --name Ben --models " + models_file(1));
  ASSERT_EQ(r.status, 0) << r.output;

  r = run("list");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("2 subjects"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Ada"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("/scans/ada.bag"), std::string::npos) << r.output;

  r = run("identify --models " + models_file(1));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* line : {"pose 1: subject 2 'Ben', sequence 0, frame 1, score 0.000",
                           "pose 2: subject 2 'Ben', sequence 1, frame 6, score 0.000",
                           "pose 3: subject 2 'Ben', sequence 0, frame 11, score 0.000",
                           "pose 4: subject 2 'Ben', sequence 1, frame 16, score 0.000"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;

  const std::string csv = (dir_ / "gallery.csv").string();
  r = run("export --format csv --output " + csv);
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(csv);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_EQ(lines, 1 + 80);
  // Names and biometrics: the export is its owner's only, like the gallery.
  EXPECT_EQ(fs::status(csv).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);

  EXPECT_EQ(run("remove 1").status, 0);
  r = run("remove 1");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("no subject 1"), std::string::npos) << r.output;
  r = run("list");
  EXPECT_NE(r.output.find("1 subjects"), std::string::npos) << r.output;
}

// The recognition options: median body at enrolment, shape features and noise weights at
// identification (own poses still exact); a bad noise file or walk body is an error with the fix.
TEST_F(GaitGalleryCli, ShapeMedianAndNoiseWeights) {
  CliRun r = run("enroll --name Ada --walk-body median --models " + models_file(0));
  ASSERT_EQ(r.status, 0) << r.output;
  r = run("enroll --name Ben --walk-body median --models " + models_file(1));
  ASSERT_EQ(r.status, 0) << r.output;
  r = run("identify --feature-set dynamic_static_shape --feature-noise " + featureNoiseFile() +
          " --models " + models_file(1));
  ASSERT_EQ(r.status, 0) << r.output;
  // The median body differs from each single fit only where the four fits differ (true models:
  // they do not), so the own poses match exactly.
  EXPECT_NE(r.output.find("pose 3: subject 2 'Ben', sequence 0, frame 11, score 0.000"),
            std::string::npos)
      << r.output;
  r = run("identify --feature-noise /nonexistent/noise.yaml --models " + models_file(1));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("feature noise file '/nonexistent/noise.yaml'"), std::string::npos)
      << r.output;
  r = run("identify --view side --feature-noise " + featureNoiseFile() + " --models " +
          models_file(1));
  EXPECT_EQ(r.status, 1);  // the noise is 3D
  EXPECT_NE(r.output.find("learn the noise on the same view"), std::string::npos) << r.output;
  r = run("enroll --name Cy --walk-body trimmed --models " + models_file(1));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--walk-body: trimmed not in {mean,median}"), std::string::npos)
      << r.output;
}

TEST_F(GaitGalleryCli, MistakesExitNonZeroWithTheFix) {
  // Usage errors exit 2 naming the option; --help lists the commands.
  CliRun r = run("");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("give a command: list, enroll, remove, export or identify"),
            std::string::npos)
      << r.output;
  r = run("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.output.find("Usage: gait_gallery [OPTIONS] [SUBCOMMAND]"), std::string::npos)
      << r.output;
  r = run("enroll --name Ada");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("give the models, --models FILE.yaml or --bag WALK.bag"),
            std::string::npos)
      << r.output;
  r = run("enroll --name Ada --age 3x --models " + models_file(0));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--age: must be a number, got '3x'"), std::string::npos) << r.output;
  r = run("remove Ada");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("Could not convert: ID = Ada"), std::string::npos) << r.output;
  r = run("frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("not expected: frobnicate"), std::string::npos) << r.output;
  const std::string corrupt = (dir_ / "corrupt.db").string();
  std::ofstream(corrupt) << std::string(4096, 'x');
  r = run("list", corrupt);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("file is not a database"), std::string::npos) << r.output;
  r = run("identify --models " + models_file(0));  // an empty gallery
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("enrol at least one subject"), std::string::npos) << r.output;
}

TEST_F(GaitGalleryCli, EnrolsAndIdentifiesARecordedWalkFromABag) {
  // A walk session as record.launch stores it: the fitter's models of walk 7, poses 1..4 (out of
  // order, pose 2 twice), and a single scan outside the walk.
  const std::string bag_path = (dir_ / "walk.bag").string();
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    const auto people = body_gait_model::eval::simulatedPeople(2, 3);
    const int order[] = {2, 1, 2, 4, 3};
    for (std::size_t i = 0; i < 5; ++i) {
      body_gait_model::BodyFit fit;
      fit.model = body_gait_model::eval::modelFromSkeleton(
          body_gait_model::eval::walkingSubject(people[1], order[i], 0));
      std_msgs::Header header;
      header.frame_id = "world";
      header.stamp = ros::Time(100 + i, 0);
      body_scan_msgs::BodyModel model = body_gait_model::toMsg(fit, header, 0.0);
      model.walk_id = 7;
      model.pose_index = order[i];
      model.scan_id = 20 + i;
      bag.write("/body_gait/model", header.stamp, model);
    }
    body_gait_model::BodyFit single;
    single.model = body_gait_model::eval::modelFromSkeleton(
        body_gait_model::eval::walkingSubject(people[0], 1, 0));
    std_msgs::Header header;
    header.frame_id = "world";
    header.stamp = ros::Time(200, 0);
    bag.write("/body_gait/model", header.stamp, body_gait_model::toMsg(single, header, 0.0));
  }
  ASSERT_EQ(run("enroll --name zero --models " + models_file(0)).status, 0);
  const CliRun enrol = run("enroll --name walker --bag " + bag_path);
  ASSERT_EQ(enrol.status, 0) << enrol.output;
  EXPECT_NE(enrol.output.find("walk 7"), std::string::npos) << enrol.output;
  EXPECT_NE(run("list").output.find(bag_path + " (walk 7)"), std::string::npos);
  // Its own walk: the walk is the walker, accepted, 'zero' far behind.
  const CliRun identify = run("identify --bag " + bag_path);
  ASSERT_EQ(identify.status, 0) << identify.output;
  // (Not 0: the probe is the walk's own cycle eta3, the gallery its training cycles eta1 and eta2,
  // which mirror two of the poses.)
  EXPECT_NE(identify.output.find("walk 7: subject 2 'walker', score 0."), std::string::npos)
      << identify.output;
  EXPECT_NE(identify.output.find(", accepted"), std::string::npos) << identify.output;
  EXPECT_NE(identify.output.find("rank 2: 'zero'"), std::string::npos) << identify.output;
  // Errors name the problem: another walk id, a bag without models, both inputs.
  const CliRun missing = run("identify --bag " + bag_path + " --walk 8");
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("no walk 8"), std::string::npos) << missing.output;
  { rosbag::Bag empty((dir_ / "empty.bag").string(), rosbag::bagmode::Write); }
  const CliRun no_models = run("enroll --name x --bag " + (dir_ / "empty.bag").string());
  EXPECT_NE(no_models.status, 0);
  EXPECT_NE(no_models.output.find("record.launch"), std::string::npos) << no_models.output;
  EXPECT_NE(run("identify --bag " + bag_path + " --models " + models_file(0)).status, 0);
}

}  // namespace
}  // namespace body_gait_id
