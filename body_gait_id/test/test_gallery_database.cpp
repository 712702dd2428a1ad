// The SQLite gallery: enrol / list / remove round trips, the stored normalization, clear errors
// for corrupt, foreign, newer and locked files, and atomic enrolment when the process is killed
// (fork + SIGKILL in the middle of a slow enrolment).
#include <body_gait_id/gallery_database.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

namespace body_gait_id {
namespace {

namespace fs = std::filesystem;

class GalleryDatabaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("test_gallery_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    path_ = (dir_ / "gallery.db").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  // 40 training poses of a person of the given stature with their own joint angles.
  static std::vector<PoseRecord> trainingPoses(double stature, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(-0.3, 0.3);
    std::vector<PoseRecord> poses;
    for (int n = 0; n < 40; ++n) {
      PoseRecord record;
      record.sequence = n / 20;
      record.frame = n % 20 + 1;
      record.model = body_gait_model::standingModel(stature);
      record.model.p << 0.1 * n, 0.9, 0, 0, 0.2, 0;
      for (int k = 0; k < 22; ++k) record.model.q[k] = angle(rng);
      poses.push_back(record);
    }
    return poses;
  }

  std::int64_t scalar(const std::string& sql) const {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* stmt = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr), SQLITE_OK) << sql;
    EXPECT_EQ(sqlite3_step(stmt), SQLITE_ROW) << sql;
    const std::int64_t value = sqlite3_column_int64(stmt, 0);
    sqlite3_finalize(stmt);
    sqlite3_close(db);
    return value;
  }
  void execRaw(const std::string& sql) const {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql;
    sqlite3_close(db);
  }
  std::string openError() const {
    try {
      GalleryDatabase db(path_);
    } catch (const GalleryError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
  std::string path_;
};

TEST_F(GalleryDatabaseTest, EnrolListReopenAndIdentify) {
  const auto alice = trainingPoses(1.62, 1), bob = trainingPoses(1.85, 2);
  std::int64_t alice_id = 0, bob_id = 0;
  {
    GalleryDatabase db(path_);
    EXPECT_TRUE(db.subjects().empty());
    EXPECT_THROW(db.normalization(), GalleryError);
    alice_id =
        db.enroll({"Alice", "female", 31}, {"/scans/alice_1.bag", "/scans/alice_2.bag"}, alice);
    bob_id = db.enroll({"Bob", "male", 45}, {}, bob);
    EXPECT_NE(alice_id, bob_id);
  }
  GalleryDatabase db(path_);  // reopened: everything is in the file
  const std::vector<Subject> subjects = db.subjects();
  ASSERT_EQ(subjects.size(), 2u);
  EXPECT_EQ(subjects[0].id, alice_id);
  EXPECT_EQ(subjects[0].info.name, "Alice");
  EXPECT_EQ(subjects[0].info.gender, "female");
  EXPECT_EQ(subjects[0].info.age, 31);
  EXPECT_EQ(subjects[0].pose_count, 40);
  EXPECT_EQ(subjects[0].scans,
            (std::vector<std::string>{"/scans/alice_1.bag", "/scans/alice_2.bag"}));
  EXPECT_EQ(subjects[1].info.name, "Bob");
  EXPECT_FALSE(subjects[1].enrolled.empty());

  const std::vector<PoseRecord> records = db.poseRecords();
  ASSERT_EQ(records.size(), 80u);
  EXPECT_EQ(records[41].subject_id, bob_id);
  EXPECT_EQ(records[41].sequence, bob[1].sequence);
  EXPECT_EQ(records[41].frame, bob[1].frame);
  EXPECT_EQ(records[41].model.p, bob[1].model.p);  // float64 BLOBs: bit-exact
  EXPECT_EQ(records[41].model.q, bob[1].model.q);
  EXPECT_EQ(records[41].model.r, bob[1].model.r);
  EXPECT_EQ(records[41].model.shape.distal_radius, bob[1].model.shape.distal_radius);
  EXPECT_EQ(records[41].model.shape.hip_rise, bob[1].model.shape.hip_rise);
  EXPECT_EQ(records[41].model.shape.hip_back, bob[1].model.shape.hip_back);

  // The stored statistics are eqs 5.14-5.15 over the whole gallery, per view.
  for (View view : {View::k3D, View::kFrontal, View::kSide}) {
    const std::vector<GalleryPose> poses = db.poses(view);
    ASSERT_EQ(poses.size(), 80u);
    std::vector<GaitFeatures> features;
    for (const PoseRecord& r : records) features.push_back(gaitFeatures(r.model, view));
    EXPECT_LT((poses[5].features.dynamic - features[5].dynamic).norm(), 1e-15);
    const FeatureNormalization expected = FeatureNormalization::fit(features);
    const FeatureNormalization stored = db.normalization(view);
    EXPECT_LT((stored.mean_dynamic - expected.mean_dynamic).norm(), 1e-12);
    EXPECT_LT((stored.sigma_static - expected.sigma_static).norm(), 1e-12);
    // Shape: features from the stored r and shape, statistics from the stored sums (3D only).
    EXPECT_EQ(poses[5].features.shape, features[5].shape);
    EXPECT_EQ(stored.sigma_shape.size(), view == View::k3D ? kShapeSize : 0);
    if (view == View::k3D) {
      EXPECT_LT((stored.sigma_shape - expected.sigma_shape).norm(), 1e-12);
    }
  }
  // A training pose identifies its subject and frame.
  const Matcher matcher = db.matcher(FeatureSet::kDynamicStatic);
  const Match m = matcher.identify(gaitFeatures(bob[27].model));
  EXPECT_EQ(m.subject_id, bob_id);
  EXPECT_EQ(m.sequence, bob[27].sequence);
  EXPECT_EQ(m.frame, bob[27].frame);
  EXPECT_LT(m.score, 1e-4);
  // With the body shape too (their statures differ, so their girths do).
  EXPECT_EQ(parseFeatureSet("dynamic_static_shape"), FeatureSet::kDynamicStaticShape);
  const Matcher shaped = db.matcher(FeatureSet::kDynamicStaticShape);
  const Match ms = shaped.identify(gaitFeatures(alice[3].model));
  EXPECT_EQ(ms.subject_id, alice_id);
  EXPECT_EQ(ms.frame, alice[3].frame);
  EXPECT_LT(ms.score, 1e-4);
}

TEST_F(GalleryDatabaseTest, FileIsInWalModeWithSchemaVersion) {
  { GalleryDatabase db(path_); }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &stmt, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)), "wal");
  sqlite3_finalize(stmt);
  sqlite3_close(db);
  EXPECT_EQ(scalar("SELECT version FROM schema_version"), GalleryDatabase::kSchemaVersion);
}

// Biometric data: a new gallery and its WAL files are readable by their owner only, whatever
// the umask.
TEST_F(GalleryDatabaseTest, NewGalleryIsOwnerOnly) {
  const mode_t old_umask = ::umask(0);
  {
    GalleryDatabase db(path_);
    db.enroll({"Alice", "female", 30}, {}, trainingPoses(1.6, 1));
    for (const std::string& file : {path_, path_ + "-wal", path_ + "-shm"}) {
      ASSERT_TRUE(fs::exists(file)) << file;
      EXPECT_EQ(fs::status(file).permissions() & fs::perms::all,
                fs::perms::owner_read | fs::perms::owner_write)
          << file;
    }
  }
  ::umask(old_umask);
}

TEST_F(GalleryDatabaseTest, RemoveCascadesAndRefitsTheStatistics) {
  GalleryDatabase db(path_);
  const std::int64_t a = db.enroll({"A", "", 0}, {"a.pcd"}, trainingPoses(1.6, 1));
  const std::int64_t b = db.enroll({"B", "", 0}, {"b.pcd"}, trainingPoses(1.9, 2));
  const double both = db.normalization().mean_static[0];
  EXPECT_TRUE(db.remove(a));
  EXPECT_FALSE(db.remove(a));
  ASSERT_EQ(db.subjects().size(), 1u);
  EXPECT_EQ(db.poses().size(), 40u);
  EXPECT_EQ(scalar("SELECT COUNT(*) FROM scans"), 1);
  const double only_b = db.normalization().mean_static[0];
  EXPECT_NEAR(only_b, body_gait_model::standingModel(1.9).r[0], 1e-12);
  EXPECT_GT(std::abs(only_b - both), 1e-3);
  // The shape sums lose A's poses too: B's own shape statistics remain.
  {
    std::vector<GaitFeatures> b_features;
    for (const GalleryPose& pose : db.poses()) b_features.push_back(pose.features);
    const FeatureNormalization expected = FeatureNormalization::fit(b_features);
    EXPECT_LT((db.normalization().mean_shape - expected.mean_shape).norm(), 1e-9);
    EXPECT_LT((db.normalization().sigma_shape - expected.sigma_shape).norm(), 1e-9);
  }
  const std::int64_t c = db.enroll({"C", "", 0}, {}, trainingPoses(1.7, 3));
  EXPECT_GT(c, b);  // ids are never reused
  EXPECT_TRUE(db.remove(b));
  EXPECT_TRUE(db.remove(c));
  EXPECT_THROW(db.normalization(), GalleryError);  // empty gallery: no statistics
}

TEST_F(GalleryDatabaseTest, BadEnrolmentsAreRefusedAndWriteNothing) {
  GalleryDatabase db(path_);
  EXPECT_THROW(db.enroll({"", "", 0}, {}, trainingPoses(1.7, 1)), GalleryError);
  EXPECT_THROW(db.enroll({"Nobody", "", 0}, {}, {}), GalleryError);
  std::vector<PoseRecord> poses = trainingPoses(1.7, 1);
  poses[12].model.q[3] = std::numeric_limits<double>::quiet_NaN();
  try {
    db.enroll({"Nan", "", 0}, {}, poses);
    ADD_FAILURE() << "a NaN pose must be refused";
  } catch (const GalleryError& e) {
    EXPECT_NE(std::string(e.what()).find("pose 13 has non-finite"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(db.subjects().empty());
}

TEST_F(GalleryDatabaseTest, CorruptFileGivesAClearError) {
  std::ofstream(path_) << std::string(8192, 'x');
  const std::string error = openError();
  EXPECT_NE(error.find("file is not a database"), std::string::npos) << error;
  EXPECT_NE(error.find(path_), std::string::npos) << error;
  EXPECT_NE(error.find("move it away"), std::string::npos) << error;
}

TEST_F(GalleryDatabaseTest, ForeignNewerAndUnknownSchemasAreRefused) {
  execRaw("CREATE TABLE something_else (x INTEGER)");
  EXPECT_NE(openError().find("not a gait gallery"), std::string::npos) << openError();
  fs::remove(path_);
  { GalleryDatabase db(path_); }
  execRaw("UPDATE schema_version SET version = 7");
  EXPECT_NE(openError().find("schema version 7, newer"), std::string::npos) << openError();
  execRaw("UPDATE schema_version SET version = 0");
  EXPECT_NE(openError().find("unknown schema version"), std::string::npos) << openError();
}

// A version 1 file (statistics without running sums) and a version 2 file (sums without the
// body-shape statistics) are upgraded when opened: same subjects, every sum recomputed from the
// stored poses (shape included), and the file takes new enrolments.
class GalleryUpgradeTest : public GalleryDatabaseTest, public ::testing::WithParamInterface<int> {};

TEST_P(GalleryUpgradeTest, OlderFileIsUpgraded) {
  {
    GalleryDatabase db(path_);
    db.enroll({"A", "", 0}, {}, trainingPoses(1.6, 1));
    db.enroll({"B", "", 0}, {}, trainingPoses(1.8, 2));
  }
  execRaw(
      "ALTER TABLE normalization DROP COLUMN mean_shape;"
      "ALTER TABLE normalization DROP COLUMN sigma_shape;"
      "ALTER TABLE normalization DROP COLUMN sum_shape;"
      "ALTER TABLE normalization DROP COLUMN sum_sq_shape;"
      "UPDATE schema_version SET version = 2");
  if (GetParam() == 1)
    execRaw(
        "ALTER TABLE normalization DROP COLUMN sum_dynamic;"
        "ALTER TABLE normalization DROP COLUMN sum_sq_dynamic;"
        "ALTER TABLE normalization DROP COLUMN sum_static;"
        "ALTER TABLE normalization DROP COLUMN sum_sq_static;"
        "UPDATE schema_version SET version = 1");
  GalleryDatabase db(path_);
  EXPECT_EQ(scalar("SELECT version FROM schema_version"), GalleryDatabase::kSchemaVersion);
  EXPECT_EQ(db.subjects().size(), 2u);
  db.enroll({"C", "", 0}, {}, trainingPoses(1.7, 3));
  std::vector<GaitFeatures> features;
  for (const GalleryPose& pose : db.poses()) features.push_back(pose.features);
  const FeatureNormalization expected = FeatureNormalization::fit(features);
  EXPECT_EQ(scalar("SELECT pose_count FROM normalization WHERE view = '3d'"), 120);
  const FeatureNormalization stored = db.normalization();
  EXPECT_LT((stored.mean_static - expected.mean_static).norm(), 1e-12);
  EXPECT_LT((stored.sigma_dynamic - expected.sigma_dynamic).norm(), 1e-12);
  ASSERT_EQ(stored.mean_shape.size(), kShapeSize);
  EXPECT_LT((stored.mean_shape - expected.mean_shape).norm(), 1e-12);
  EXPECT_LT((stored.sigma_shape - expected.sigma_shape).norm(), 1e-12);
  EXPECT_EQ(db.normalization(View::kSide).mean_shape.size(), 0);
}

INSTANTIATE_TEST_SUITE_P(FromVersion, GalleryUpgradeTest, ::testing::Values(1, 2));

// Poses stored before hip_back existed have one joint placement fewer in their shape: their hips
// read back on the lower torso's axis; a shape of another size is a clear error.
TEST_F(GalleryDatabaseTest, ShapesWithoutHipBackReadWithTheHipsOnTheAxis) {
  const std::vector<PoseRecord> poses = trainingPoses(1.7, 1);
  ASSERT_GT(poses[0].model.shape.hip_back, 0.01);
  {
    GalleryDatabase db(path_);
    db.enroll({"A", "", 0}, {}, poses);
  }
  const int placements_end = (2 * body_gait_model::kSegmentCount + 4) * int(sizeof(double));
  execRaw("UPDATE poses SET shape = substr(shape, 1, " + std::to_string(placements_end) + ")");
  {
    GalleryDatabase db(path_);
    const std::vector<PoseRecord> records = db.poseRecords();
    ASSERT_EQ(records.size(), poses.size());
    EXPECT_EQ(records[0].model.shape.hip_back, 0.0);
    EXPECT_EQ(records[0].model.shape.hip_rise, poses[0].model.shape.hip_rise);
    EXPECT_EQ(db.poses().size(), poses.size());
  }
  execRaw("UPDATE poses SET shape = substr(shape, 1, 16)");
  GalleryDatabase db(path_);
  try {
    db.poseRecords();
    ADD_FAILURE() << "a two-number shape was read";
  } catch (const GalleryError& e) {
    EXPECT_NE(std::string(e.what()).find("shape"), std::string::npos) << e.what();
  }
}

TEST_F(GalleryDatabaseTest, LockedDatabaseWaitsThenGivesAClearError) {
  GalleryDatabase db(path_, std::chrono::milliseconds(200));
  sqlite3* other = nullptr;  // another writer holding the write lock
  ASSERT_EQ(sqlite3_open(path_.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
  const auto start = std::chrono::steady_clock::now();
  try {
    db.enroll({"Carol", "", 0}, {}, trainingPoses(1.7, 1));
    ADD_FAILURE() << "enrolment under another writer's lock must fail";
  } catch (const GalleryError& e) {
    EXPECT_NE(std::string(e.what()).find("locked by another writer"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(path_), std::string::npos) << e.what();
  }
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(190));
  EXPECT_EQ(db.subjects().size(), 0u);  // reading works meanwhile (WAL)
  ASSERT_EQ(sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(other);
  EXPECT_NO_THROW(db.enroll({"Carol", "", 0}, {}, trainingPoses(1.7, 1)));
}

// Two processes enrolling into one file at once take turns (busy timeout): every subject and
// every pose arrives, and the running sums of the statistics count them all.
TEST_F(GalleryDatabaseTest, ConcurrentWritersTakeTurns) {
  { GalleryDatabase db(path_); }  // the schema exists before the writers start
  std::vector<pid_t> children;
  for (int writer = 0; writer < 2; ++writer) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      try {
        GalleryDatabase db(path_, std::chrono::seconds(20));
        for (int k = 0; k < 5; ++k)
          db.enroll({"w" + std::to_string(writer) + "_" + std::to_string(k), "", 0}, {},
                    trainingPoses(1.6 + 0.1 * writer + 0.01 * k, 10 * writer + k));
      } catch (...) {
        _exit(2);
      }
      _exit(0);
    }
    children.push_back(child);
  }
  for (pid_t child : children) {
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a writer failed";
  }
  GalleryDatabase db(path_);
  EXPECT_EQ(db.subjects().size(), 10u);
  std::vector<GaitFeatures> features;
  for (const GalleryPose& pose : db.poses()) features.push_back(pose.features);
  ASSERT_EQ(features.size(), 400u);
  EXPECT_EQ(scalar("SELECT pose_count FROM normalization WHERE view = '3d'"), 400);
  const FeatureNormalization expected = FeatureNormalization::fit(features);
  EXPECT_LT((db.normalization().mean_static - expected.mean_static).norm(), 1e-12);
  EXPECT_LT((db.normalization().sigma_dynamic - expected.sigma_dynamic).norm(), 1e-12);
}

// The child enrols A completely, then B slowly; the parent kills it with SIGKILL while B's
// transaction is half written. Reopened: A whole, B absent, statistics those of A alone.
TEST_F(GalleryDatabaseTest, KilledMidEnrolmentLosesNothingCommitted) {
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(ready[0]);
    try {
      GalleryDatabase db(path_);
      db.enroll({"A", "", 0}, {"a.bag"}, trainingPoses(1.6, 1));
      db.setEnrollHookForTesting([&](int pose) {
        if (pose == 20) {
          const char byte = 1;
          if (write(ready[1], &byte, 1) != 1) _exit(3);
          std::this_thread::sleep_for(std::chrono::seconds(30));  // killed here
        }
      });
      db.enroll({"B", "", 0}, {"b.bag"}, trainingPoses(1.9, 2));
    } catch (...) {
      _exit(2);
    }
    _exit(0);
  }
  close(ready[1]);
  char byte = 0;
  ASSERT_EQ(read(ready[0], &byte, 1), 1) << "the child did not reach the middle of B";
  close(ready[0]);
  ASSERT_EQ(kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));

  GalleryDatabase db(path_);
  const std::vector<Subject> subjects = db.subjects();
  ASSERT_EQ(subjects.size(), 1u);
  EXPECT_EQ(subjects[0].info.name, "A");
  EXPECT_EQ(subjects[0].pose_count, 40);
  EXPECT_EQ(db.poses().size(), 40u);
  EXPECT_EQ(scalar("SELECT COUNT(*) FROM scans"), 1);
  EXPECT_EQ(scalar("SELECT pose_count FROM normalization WHERE view = '3d'"), 40);
  EXPECT_EQ(scalar("SELECT COUNT(*) FROM pragma_integrity_check WHERE integrity_check = 'ok'"), 1);
  // And the gallery is writable again: the dead writer's lock is gone.
  EXPECT_NO_THROW(db.enroll({"B", "", 0}, {"b.bag"}, trainingPoses(1.9, 2)));
  EXPECT_EQ(db.subjects().size(), 2u);
}

}  // namespace
}  // namespace body_gait_id
