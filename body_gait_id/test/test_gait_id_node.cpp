// gait_id_node end to end: 6 simulated people enrolled through ~enroll, 24 probes (another walk
// of each) identified through ~identify and the /body_gait/model topic; the node is stopped and
// a new one started on the same gallery file gives the same answers; a corrupt gallery file is
// reported in the log and in every service reply while the node keeps running; a walk's 4 models
// on the topic give 4 scan answers and one walk answer (an enrolled person's accepted, a
// stranger's rejected).
#include <body_gait_id/walk_identification.h>
#include <body_gait_model/eval/gait_subjects.h>
#include <body_gait_model/eval/skeleton_model.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_scan_driver/test_time_scale.h>
#include <body_scan_msgs/EnrollSubject.h>
#include <body_scan_msgs/Identify.h>
#include <body_scan_msgs/Identity.h>
#include <body_scan_msgs/ListSubjects.h>
#include <body_scan_msgs/RemoveSubject.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using body_scan_driver::scaledSeconds;

namespace body_gait_id {
namespace {

// The shipped noise weights of the sampler rig (config/), found through rospack.
std::string featureNoiseFile() {
  return ros::package::getPath("body_gait_id") + "/config/feature_noise_sampler.yaml";
}

namespace fs = std::filesystem;
constexpr int kPeople = 6;

body_scan_msgs::BodyModel modelMsg(const body_scan_driver::sim::HumanBodySpec& spec) {
  body_gait_model::BodyFit fit;
  fit.model = body_gait_model::eval::modelFromSkeleton(spec);
  std_msgs::Header header;
  header.frame_id = "world";
  return body_gait_model::toMsg(fit, header, 0.0);
}

// A gait_id_node process on a gallery file, its output in a log file.
class NodeProcess {
 public:
  // params: more private parameters, "_name:=value".
  NodeProcess(const std::string& name, const std::string& database, const std::string& log,
              const std::vector<std::string>& params = {})
      : name_(name), log_(log) {
    // The test's own accept threshold (the node's default is calibrated for fitted models).
    std::vector<std::string> args{GAIT_ID_NODE, "__name:=" + name, "_database:=" + database,
                                  "_accept_threshold:=3.0"};
    args.insert(args.end(), params.begin(), params.end());
    // Everything the child needs is made before fork: this process runs ROS threads, and a
    // child that allocates can deadlock on a malloc lock another thread held at the fork.
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(fd, 1);
      dup2(fd, 2);
      execv(GAIT_ID_NODE, argv.data());
      _exit(127);
    }
  }
  ~NodeProcess() {
    stop();
    if (::testing::Test::HasFailure())  // the node's side of a failure, in the test's result
      ADD_FAILURE() << "---- " << name_ << " output (last lines) ----\n" << logTail(8);
  }
  bool waitForServices() const {
    return ros::service::waitForService("/" + name_ + "/list", ros::Duration(scaledSeconds(20)));
  }
  bool alive() const { return pid_ > 0 && kill(pid_, 0) == 0; }
  void stop() {
    clients_.clear();
    if (pid_ <= 0) return;
    kill(pid_, SIGINT);
    int status = 0;
    for (int i = 0; i < 100 && waitpid(pid_, &status, WNOHANG) == 0; ++i) usleep(50000);
    if (waitpid(pid_, &status, WNOHANG) == 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }
  std::string log() const {
    std::ifstream in(log_);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  std::string logTail(std::size_t lines) const {
    const std::string text = log();
    std::size_t start = text.size();
    for (std::size_t seen = 0; start > 0 && seen <= lines;)
      if (text[--start] == '\n') ++seen;
    return text.substr(start);
  }
  // One persistent connection per service: a non-persistent roscpp call can fail when the
  // server's close of the connection is seen before its response is read (ros_comm #1976).
  template <typename Service>
  Service call(const std::string& service, Service srv = {}) const {
    auto client = clients_.find(service);
    if (client == clients_.end())
      client = clients_
                   .emplace(service, ros::NodeHandle().serviceClient<Service>(
                                         "/" + name_ + "/" + service, /*persistent=*/true))
                   .first;
    EXPECT_TRUE(client->second.call(srv)) << service;
    return srv;
  }

 private:
  std::string name_, log_;
  pid_t pid_ = -1;
  mutable std::map<std::string, ros::ServiceClient> clients_;
};

struct Answer {
  std::int64_t subject_id;
  int sequence, frame;
  double score;
};

class GaitIdNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("test_gait_id_node_" + std::to_string(getpid()));
    fs::remove_all(dir_);  // a gallery left by an earlier process of the same pid
    fs::create_directories(dir_);
    people_ = body_gait_model::eval::simulatedPeople(kPeople, 6);
  }
  void TearDown() override { fs::remove_all(dir_); }

  body_scan_msgs::EnrollSubject enrolment(int person) const {
    body_scan_msgs::EnrollSubject srv;
    srv.request.name = people_[person].name;
    srv.request.gender = people_[person].gender;
    srv.request.age = people_[person].age;
    for (int index = 1; index <= 4; ++index)
      srv.request.poses.push_back(
          modelMsg(body_gait_model::eval::walkingSubject(people_[person], index, 0)));
    srv.request.scan_paths = {"/scans/" + people_[person].name + "_walk0.bag"};
    return srv;
  }
  // Probes: the 4 representative poses of another walk (trial 1) of every person.
  std::vector<body_scan_msgs::BodyModel> probes() const {
    std::vector<body_scan_msgs::BodyModel> out;
    for (int person = 0; person < kPeople; ++person)
      for (int index = 1; index <= 4; ++index)
        out.push_back(modelMsg(body_gait_model::eval::walkingSubject(people_[person], index, 1)));
    return out;
  }
  static std::vector<Answer> identifyAll(const NodeProcess& node,
                                         const std::vector<body_scan_msgs::BodyModel>& probes) {
    std::vector<Answer> answers;
    for (const auto& probe : probes) {
      body_scan_msgs::Identify srv;
      srv.request.model = probe;
      srv = node.call("identify", srv);
      EXPECT_TRUE(srv.response.success) << srv.response.message;
      answers.push_back(
          {srv.response.subject_id, srv.response.sequence, srv.response.frame, srv.response.score});
    }
    return answers;
  }

  fs::path dir_;
  std::vector<body_gait_model::eval::SimulatedPerson> people_;
};

TEST_F(GaitIdNodeTest, EnrolRestartIdentifySameAnswers) {
  const std::string database = (dir_ / "gallery.db").string();
  const std::vector<body_scan_msgs::BodyModel> probe_models = probes();
  std::vector<std::int64_t> ids;
  std::vector<Answer> before;
  {
    NodeProcess node("gait_id_first", database, (dir_ / "first.log").string());
    ASSERT_TRUE(node.waitForServices()) << node.log();
    for (int person = 0; person < kPeople; ++person) {
      const auto srv = node.call("enroll", enrolment(person));
      ASSERT_TRUE(srv.response.success) << srv.response.message;
      EXPECT_EQ(srv.response.pose_count, 40);
      ids.push_back(srv.response.subject_id);
    }
    // The enrolment walk's own representative poses are training frames 1, 6, 11, 16 (s1 and
    // s3 in eta1, s2 and s4 in eta2): exact matches with their subject, sequence and frame.
    for (int person = 0; person < kPeople; ++person) {
      const std::vector<Answer> own = identifyAll(node, enrolment(person).request.poses);
      for (int index = 0; index < 4; ++index) {
        EXPECT_EQ(own[index].subject_id, ids[person]) << "person " << person << " s" << index + 1;
        EXPECT_EQ(own[index].sequence, index % 2) << "person " << person << " s" << index + 1;
        EXPECT_EQ(own[index].frame, 1 + 5 * index) << "person " << person << " s" << index + 1;
        EXPECT_LT(own[index].score, 1e-3) << "person " << person << " s" << index + 1;
      }
    }
    // Another walk of each person (trial-to-trial variation of ~1 deg, true models): recorded
    // for the restart check; recognition well above chance (1 in 6) but not asserted perfect,
    // which is the evaluation's business (measured: 18 of 24 with these 6 people).
    before = identifyAll(node, probe_models);
    int correct = 0;
    for (std::size_t i = 0; i < before.size(); ++i) correct += before[i].subject_id == ids[i / 4];
    std::printf("another walk, dynamic + static: %d of %d probes identified\n", correct,
                4 * kPeople);
    EXPECT_GE(correct, 2 * kPeople);

    // The topic gives the service's answer.
    ros::NodeHandle nh;
    std::vector<body_scan_msgs::Identity> identities;
    ros::Subscriber sub = nh.subscribe<body_scan_msgs::Identity>(
        "/body_gait/identity", 4,
        [&](const body_scan_msgs::Identity::ConstPtr& msg) { identities.push_back(*msg); });
    ros::Publisher pub = nh.advertise<body_scan_msgs::BodyModel>("/body_gait/model", 1);
    body_scan_msgs::BodyModel probe = probe_models[9];
    probe.header.stamp = ros::Time(1234, 5);
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(15));
    ros::WallTime next_publish;
    while (identities.empty() && ros::WallTime::now() < deadline) {
      if (ros::WallTime::now() >= next_publish && pub.getNumSubscribers() > 0) {
        pub.publish(probe);
        next_publish = ros::WallTime::now() + ros::WallDuration(2);
      }
      ros::spinOnce();
      ros::WallDuration(0.02).sleep();
    }
    ASSERT_FALSE(identities.empty()) << "no identity on /body_gait/identity";
    EXPECT_EQ(identities[0].header.stamp, probe.header.stamp);
    EXPECT_EQ(identities[0].subject_id, before[9].subject_id);
    EXPECT_EQ(identities[0].frame, before[9].frame);
    const auto person = std::find(ids.begin(), ids.end(), identities[0].subject_id) - ids.begin();
    ASSERT_LT(person, kPeople);
    EXPECT_EQ(identities[0].name, people_[person].name);
    EXPECT_DOUBLE_EQ(identities[0].score, before[9].score);
    EXPECT_EQ(identities[0].accepted, before[9].score <= 3.0);

    // A refused enrolment names the bad field (and not the person) in the reply.
    body_scan_msgs::EnrollSubject refused = enrolment(0);
    refused.request.poses[2].q[3] = std::nan("");
    const std::string message = node.call("enroll", refused).response.message;
    EXPECT_NE(message.find("BodyModel.q[3] is not finite"), std::string::npos) << message;
  }  // the first node stops here

  // Biometric hygiene: names stay out of the node's log above DEBUG (its whole output at the
  // default level, after enrolments, identifications and a refusal), and the gallery file it
  // created is its owner's only.
  {
    std::ifstream in(dir_ / "first.log");
    std::stringstream log;
    log << in.rdbuf();
    ASSERT_NE(log.str().find("enrolled subject"), std::string::npos) << log.str();
    for (const auto& person : people_)
      EXPECT_EQ(log.str().find(person.name), std::string::npos) << person.name << " logged";
    EXPECT_EQ(fs::status(database).permissions() & fs::perms::all,
              fs::perms::owner_read | fs::perms::owner_write);
  }

  NodeProcess node("gait_id_second", database, (dir_ / "second.log").string());
  ASSERT_TRUE(node.waitForServices()) << node.log();
  const auto list = node.call<body_scan_msgs::ListSubjects>("list");
  ASSERT_TRUE(list.response.success) << list.response.message;
  EXPECT_EQ(list.response.subject_ids, ids);
  EXPECT_EQ(list.response.names[3], people_[3].name);
  EXPECT_EQ(list.response.pose_counts, std::vector<int>(kPeople, 40));
  const std::vector<Answer> after = identifyAll(node, probe_models);
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].subject_id, before[i].subject_id) << "probe " << i;
    EXPECT_EQ(after[i].sequence, before[i].sequence) << "probe " << i;
    EXPECT_EQ(after[i].frame, before[i].frame) << "probe " << i;
    EXPECT_DOUBLE_EQ(after[i].score, before[i].score) << "probe " << i;
  }

  // A malformed model (empty arrays) and 3 poses instead of 4 are refused; the gallery is fine.
  body_scan_msgs::Identify malformed;
  const auto refused = node.call("identify", malformed);
  EXPECT_FALSE(refused.response.success);
  EXPECT_NE(refused.response.message.find("BodyModel.p has 0"), std::string::npos)
      << refused.response.message;
  body_scan_msgs::EnrollSubject three = enrolment(0);
  three.request.poses.pop_back();
  const auto short_enrolment = node.call("enroll", three);
  EXPECT_FALSE(short_enrolment.response.success);
  EXPECT_NE(short_enrolment.response.message.find("exactly 4"), std::string::npos)
      << short_enrolment.response.message;

  // Removal through the service; an unknown id is refused with a hint.
  body_scan_msgs::RemoveSubject remove;
  remove.request.subject_id = ids[0];
  EXPECT_TRUE(node.call("remove", remove).response.success);
  const auto again = node.call("remove", remove);
  EXPECT_FALSE(again.response.success);
  EXPECT_NE(again.response.message.find("~list"), std::string::npos) << again.response.message;
  EXPECT_EQ(node.call<body_scan_msgs::ListSubjects>("list").response.subject_ids.size(),
            std::size_t(kPeople - 1));
}

// The best cross-walk variant through the node's parameters: body-shape features, median
// body at enrolment, components weighted by the shipped noise file. Same gallery people and
// probes as above; the plain node on the same file is the peer. A bad noise file is reported
// and the node identifies unweighted.
int correctAnswers(const std::vector<Answer>& answers, const std::vector<std::int64_t>& ids) {
  int correct = 0;
  for (std::size_t i = 0; i < answers.size(); ++i) correct += answers[i].subject_id == ids[i / 4];
  return correct;
}

TEST_F(GaitIdNodeTest, ShapeFeaturesAndNoiseWeightsThroughParameters) {
  const std::string database = (dir_ / "shaped.db").string();
  const std::vector<body_scan_msgs::BodyModel> probe_models = probes();
  std::vector<std::int64_t> ids;
  int shaped_correct = 0;
  {
    NodeProcess node("gait_id_shaped", database, (dir_ / "shaped.log").string(),
                     {"_feature_set:=dynamic_static_shape", "_walk_body:=median",
                      "_feature_noise:=" + featureNoiseFile()});
    ASSERT_TRUE(node.waitForServices()) << node.log();
    for (int person = 0; person < kPeople; ++person) {
      const auto srv = node.call("enroll", enrolment(person));
      ASSERT_TRUE(srv.response.success) << srv.response.message;
      ids.push_back(srv.response.subject_id);
    }
    shaped_correct = correctAnswers(identifyAll(node, probe_models), ids);
    EXPECT_EQ(node.log().find("ERROR"), std::string::npos) << node.log();
  }
  NodeProcess plain("gait_id_plain", database, (dir_ / "plain.log").string(),
                    {"_feature_noise:=/nonexistent/noise.yaml"});
  ASSERT_TRUE(plain.waitForServices()) << plain.log();
  const int plain_correct = correctAnswers(identifyAll(plain, probe_models), ids);
  EXPECT_NE(plain.log().find("/nonexistent/noise.yaml"), std::string::npos) << plain.log();
  std::printf("another walk: shape + median + noise weights %d of %d, plain %d\n", shaped_correct,
              4 * kPeople, plain_correct);
  EXPECT_GT(shaped_correct, plain_correct);
  EXPECT_GE(shaped_correct, 4 * kPeople - 1);
}

TEST_F(GaitIdNodeTest, AWalksFourModelsAreIdentifiedAsOneWalk) {
  const std::string database = (dir_ / "walks.db").string();
  // The recognition.launch features (shape, median body, noise weights) and the default walk
  // threshold; people 0-2 enrolled, person 4 a stranger.
  NodeProcess node("gait_id_walks", database, (dir_ / "walks.log").string(),
                   {"_feature_set:=dynamic_static_shape", "_walk_body:=median",
                    "_feature_noise:=" + featureNoiseFile()});
  ASSERT_TRUE(node.waitForServices()) << node.log();
  std::vector<std::int64_t> ids;
  for (int person = 0; person < 3; ++person) {
    const auto srv = node.call("enroll", enrolment(person));
    ASSERT_TRUE(srv.response.success) << srv.response.message;
    ids.push_back(srv.response.subject_id);
  }
  ros::NodeHandle nh;
  std::vector<body_scan_msgs::Identity> identities;
  ros::Subscriber sub = nh.subscribe<body_scan_msgs::Identity>(
      "/body_gait/identity", 20,
      [&](const body_scan_msgs::Identity::ConstPtr& msg) { identities.push_back(*msg); });
  ros::Publisher pub = nh.advertise<body_scan_msgs::BodyModel>("/body_gait/model", 8);
  for (const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(scaledSeconds(10));
       ros::WallTime::now() < end && (pub.getNumSubscribers() == 0 || sub.getNumPublishers() == 0);
       ros::WallDuration(0.02).sleep()) {
  }
  const auto walkAnswer = [&](int person, std::uint32_t walk_id) {
    for (int index = 1; index <= 4; ++index) {
      body_scan_msgs::BodyModel model =
          modelMsg(body_gait_model::eval::walkingSubject(people_[person], index, 1));
      model.header.stamp = ros::Time(100 * walk_id + index, 0);
      model.walk_id = walk_id;
      model.pose_index = index;
      model.scan_id = 10 * walk_id + index;
      pub.publish(model);
    }
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(scaledSeconds(15));
    while (ros::WallTime::now() < deadline) {
      ros::spinOnce();
      for (const auto& identity : identities)
        if (identity.kind == body_scan_msgs::Identity::WALK && identity.walk_id == walk_id)
          return std::optional<body_scan_msgs::Identity>(identity);
      ros::WallDuration(0.02).sleep();
    }
    return std::optional<body_scan_msgs::Identity>();
  };
  const auto known = walkAnswer(1, 21);
  ASSERT_TRUE(known) << "no walk identity for walk 21";
  EXPECT_EQ(known->subject_id, ids[1]);
  EXPECT_EQ(known->name, people_[1].name);
  EXPECT_TRUE(known->accepted) << "score " << known->score;
  EXPECT_DOUBLE_EQ(known->threshold, kDefaultWalkAcceptThreshold);
  ASSERT_EQ(known->ranked_subject_ids.size(), 3u);  // rank-5 list of a 3-person gallery
  EXPECT_EQ(known->ranked_subject_ids[0], ids[1]);
  EXPECT_DOUBLE_EQ(known->ranked_scores[0], known->score);
  EXPECT_TRUE(std::is_sorted(known->ranked_scores.begin(), known->ranked_scores.end()));
  // Each of the walk's models was also answered as a single scan, with its walk and pose.
  std::vector<int> scan_poses;
  for (const auto& identity : identities)
    if (identity.kind == body_scan_msgs::Identity::SCAN && identity.walk_id == 21) {
      scan_poses.push_back(identity.pose_index);
      EXPECT_EQ(identity.scan_id, 210u + identity.pose_index);
      EXPECT_EQ(identity.ranked_subject_ids.size(), 3u);
    }
  EXPECT_EQ(scan_poses, (std::vector<int>{1, 2, 3, 4}));

  const auto stranger = walkAnswer(4, 22);
  ASSERT_TRUE(stranger) << "no walk identity for walk 22";
  EXPECT_FALSE(stranger->accepted) << "a stranger's walk was accepted as " << stranger->name
                                   << " with score " << stranger->score;
  std::printf(
      "[ figure ] walk of an enrolled person: score %.2f (accepted); a stranger's walk: "
      "nearest %s, score %.2f (rejected at %.1f)\n",
      known->score, stranger->name.c_str(), stranger->score, stranger->threshold);
}

TEST_F(GaitIdNodeTest, CorruptGalleryIsReportedAndTheNodeKeepsRunning) {
  const std::string database = (dir_ / "corrupt.db").string();
  std::ofstream(database) << std::string(4096, 'x');
  NodeProcess node("gait_id_corrupt", database, (dir_ / "corrupt.log").string());
  ASSERT_TRUE(node.waitForServices()) << node.log();
  body_scan_msgs::Identify identify;
  identify.request.model = probes()[0];
  for (int attempt = 0; attempt < 2; ++attempt) {
    const auto reply = node.call("identify", identify);
    EXPECT_FALSE(reply.response.success);
    EXPECT_NE(reply.response.message.find("file is not a database"), std::string::npos)
        << reply.response.message;
    EXPECT_NE(reply.response.message.find(database), std::string::npos) << reply.response.message;
  }
  const auto enrol = node.call("enroll", enrolment(0));
  EXPECT_FALSE(enrol.response.success);
  EXPECT_NE(enrol.response.message.find("file is not a database"), std::string::npos);
  EXPECT_FALSE(node.call<body_scan_msgs::ListSubjects>("list").response.success);
  EXPECT_TRUE(node.alive());
  EXPECT_NE(node.log().find("file is not a database"), std::string::npos) << node.log();
}

// The gallery's file system full, then read-only, during enrolment: the enrolment fails with an
// error naming the file and the fix, the node keeps running, and the gallery holds exactly the
// subjects enrolled before (also for a new node on the file). A small tmpfs when the test may
// mount one (root), else a read-only directory (the read-only half only).
TEST_F(GaitIdNodeTest, FullOrReadOnlyDiskFailsEnrolmentAndKeepsTheGallery) {
  const fs::path volume = dir_ / "volume";
  fs::create_directories(volume);
  const bool tmpfs = mount("tmpfs", volume.c_str(), "tmpfs", 0, "size=4m,mode=0700") == 0;
  if (!tmpfs && geteuid() == 0) GTEST_SKIP() << "root but cannot mount a tmpfs here";
  struct Unmount {
    fs::path path;
    bool mounted;
    ~Unmount() {
      if (mounted) umount2(path.c_str(), MNT_DETACH);
      fs::permissions(path, fs::perms::owner_all, fs::perm_options::add);
    }
  } unmount{volume, tmpfs};
  const std::string database = (volume / "gallery.db").string();
  auto names = [](const NodeProcess& node) {
    const auto list = node.call<body_scan_msgs::ListSubjects>("list");
    EXPECT_TRUE(list.response.success) << list.response.message;
    return list.response.names;
  };
  auto expectCannotWrite = [&](const body_scan_msgs::EnrollSubject& enrol) {
    EXPECT_FALSE(enrol.response.success);
    EXPECT_NE(enrol.response.message.find("cannot write gallery database '" + database + "'"),
              std::string::npos)
        << enrol.response.message;
    std::printf("[ figure ] enrolment refused: %s\n", enrol.response.message.c_str());
  };
  std::vector<std::string> enrolled;
  {
    NodeProcess node("gait_id_disk", database, (dir_ / "disk.log").string());
    ASSERT_TRUE(node.waitForServices()) << node.log();
    ASSERT_TRUE(node.call("enroll", enrolment(0)).response.success);
    enrolled.push_back(people_[0].name);
    if (tmpfs) {  // fill the file system, enrol, free the space, enrol again
      {
        std::ofstream filler(volume / "filler", std::ios::binary);
        const std::string block(4096, 'f');
        while (filler.write(block.data(), block.size()) && filler.flush()) {
        }
      }
      expectCannotWrite(node.call("enroll", enrolment(1)));
      EXPECT_EQ(names(node), enrolled);
      fs::remove(volume / "filler");
      ASSERT_TRUE(node.call("enroll", enrolment(1)).response.success);
      enrolled.push_back(people_[1].name);
      EXPECT_TRUE(node.alive());
    }
  }
  // Read-only: the volume remounted so (a file system with open writers cannot be), or, not
  // root, the directory and its files made read-only; a node started on it cannot enrol.
  if (tmpfs) {
    ASSERT_EQ(mount(nullptr, volume.c_str(), nullptr, MS_REMOUNT | MS_RDONLY, "size=4m"), 0)
        << std::strerror(errno);
  } else {
    for (const auto& entry : fs::directory_iterator(volume))
      fs::permissions(entry.path(), fs::perms::owner_read);
    fs::permissions(volume, fs::perms::owner_read | fs::perms::owner_exec);
  }
  {
    NodeProcess node("gait_id_readonly", database, (dir_ / "readonly.log").string());
    ASSERT_TRUE(node.waitForServices()) << node.log();
    expectCannotWrite(node.call("enroll", enrolment(2)));
    EXPECT_TRUE(node.alive());
  }
  if (tmpfs) {
    ASSERT_EQ(mount(nullptr, volume.c_str(), nullptr, MS_REMOUNT, "size=4m"), 0);
  } else {
    fs::permissions(volume, fs::perms::owner_all);
    for (const auto& entry : fs::directory_iterator(volume))
      fs::permissions(entry.path(), fs::perms::owner_read | fs::perms::owner_write);
  }
  NodeProcess reopened("gait_id_reopened", database, (dir_ / "reopened.log").string());
  ASSERT_TRUE(reopened.waitForServices()) << reopened.log();
  EXPECT_EQ(names(reopened), enrolled);
}

}  // namespace
}  // namespace body_gait_id

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_gait_id_node");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
