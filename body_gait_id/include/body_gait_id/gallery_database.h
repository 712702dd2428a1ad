// The gallery of enrolled people (thesis 5.7-5.8): one SQLite file holding subjects, their
// scans, their fitted training poses with the gait features, and the normalization statistics
// of eqs 5.14-5.15 fitted to the whole gallery (stored with it, so identification uses the
// statistics of the gallery it searches).
//
// File: WAL journal, every write in one transaction (an enrolment is the whole subject or
// nothing, even when the process is killed mid-way), foreign keys with cascading deletes, and a
// schema_version table; a newer or unknown schema is refused. Another writer holding the lock is
// waited for (busy timeout), then reported. Arrays (p, q, r, shape, features, statistics) are
// BLOBs of little-endian float64.
#pragma once

#include <body_gait_id/gait_features.h>
#include <body_gait_id/matcher.h>
#include <body_gait_model/kinematic_model.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

struct sqlite3;

namespace body_gait_id {

// Every database failure: the message names the file, the problem and the fix.
class GalleryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SubjectInfo {
  std::string name;
  std::string gender;  // free text (e.g. "female", "male")
  int age = 0;         // years, 0 = unknown
};

struct Subject {
  std::int64_t id = 0;
  SubjectInfo info;
  std::string enrolled;  // UTC time of the enrolment (ISO 8601)
  int pose_count = 0;
  std::vector<std::string> scans;  // paths of the stored clouds or bags
};

// A training pose as stored: which subject, sequence (0 = eta1, 1 = eta2) and gait-cycle frame
// (1-based), and the fitted body model (p, q, r and shape).
struct PoseRecord {
  std::int64_t subject_id = 0;
  int sequence = 0;
  int frame = 0;
  body_gait_model::BodyModel model;
};

// The gallery file the node and the CLI use when none is given: $ROS_HOME/gait_gallery.db
// ($HOME/.ros when ROS_HOME is unset, the working directory when HOME is unset too).
std::string defaultGalleryPath();

// "3d", "frontal", "side" and back; parseView throws std::invalid_argument naming the choices.
const char* viewName(View view);
View parseView(const std::string& name);
// "dynamic", "dynamic_static" and back.
const char* featureSetName(FeatureSet set);
FeatureSet parseFeatureSet(const std::string& name);

// One connection to the file: use an object from one thread at a time (the node's callbacks
// run in one spinner thread). Several processes may open the same file: readers run alongside
// a writer (WAL), writers take turns (busy timeout).
class GalleryDatabase {
 public:
  // 2: the normalization table keeps running sums. 3: it keeps the body-shape measures'
  // statistics and sums too (dynamic_static_shape). Version 1 and 2 files are upgraded in
  // place when opened: every sum is computed once from their stored poses.
  static constexpr int kSchemaVersion = 3;

  // Opens the gallery at path, creating the file and its schema if it does not exist. Throws
  // GalleryError for a file that is not an SQLite database, a newer or unknown schema, or a
  // directory that cannot be written.
  explicit GalleryDatabase(const std::string& path,
                           std::chrono::milliseconds busy_timeout = std::chrono::seconds(2));
  ~GalleryDatabase();
  GalleryDatabase(const GalleryDatabase&) = delete;
  GalleryDatabase& operator=(const GalleryDatabase&) = delete;

  // Enrols one person with their scans and training poses (features computed here) and adds
  // them to the stored normalization (running sums: the cost does not grow with the gallery):
  // all in one transaction. Returns the new subject id (ids are never
  // reused). Throws GalleryError (nothing written) when there are no poses, the name is empty,
  // or the database is locked or read-only.
  std::int64_t enroll(const SubjectInfo& info, const std::vector<std::string>& scans,
                      const std::vector<PoseRecord>& poses);
  // Removes a subject with their scans and poses and takes them out of the normalization. Returns
  // false if no subject has that id.
  bool remove(std::int64_t subject_id);

  std::vector<Subject> subjects() const;
  // Every stored pose, or one subject's (subject_id != 0; ids start at 1).
  std::vector<PoseRecord> poseRecords(std::int64_t subject_id = 0) const;
  // The gallery's training poses with the features of a view (3D from the stored features, 2D
  // views computed from the stored models).
  std::vector<GalleryPose> poses(View view = View::k3D) const;
  // The stored statistics of eqs 5.14-5.15 for a view. Throws GalleryError if the gallery is
  // empty.
  FeatureNormalization normalization(View view = View::k3D) const;
  // A matcher over the stored gallery with the stored statistics; with `noise`, each
  // component weighted by noiseWeights (between / within-subject SD). Throws
  // std::invalid_argument when the noise does not fit the view or set (2D views have none).
  Matcher matcher(FeatureSet set, View view = View::k3D, const FeatureNoise* noise = nullptr) const;

  const std::string& path() const { return path_; }

  // Test hook: called inside enroll's transaction after each pose row is written (index of the
  // pose), so a test can kill the process mid-enrolment.
  void setEnrollHookForTesting(std::function<void(int)> hook) { enroll_hook_ = std::move(hook); }

 private:
  void createOrCheckSchema();
  // Upgrades a version 1 or 2 file to kSchemaVersion in one transaction.
  void upgradeFrom(int version_found);
  int tableCount(bool& has_version) const;
  // Adds (weight 1) or takes away (weight -1) poses from the stored statistics of every view.
  void updateNormalization(const std::vector<PoseRecord>& poses, double weight);
  void exec(const char* sql, const char* what);
  [[noreturn]] void fail(int code, const std::string& what) const;

  std::string path_;
  std::chrono::milliseconds busy_timeout_;
  sqlite3* db_ = nullptr;
  std::function<void(int)> enroll_hook_;
};

}  // namespace body_gait_id
