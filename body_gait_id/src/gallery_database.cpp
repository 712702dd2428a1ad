// SQLite gallery database (plain C API); see gallery_database.h for the file's guarantees.
#include <body_gait_id/gallery_database.h>
#include <fcntl.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>

namespace body_gait_id {
namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE schema_version (version INTEGER NOT NULL);
CREATE TABLE subjects (
  id INTEGER PRIMARY KEY AUTOINCREMENT,  -- never reused after a removal
  name TEXT NOT NULL,
  gender TEXT NOT NULL DEFAULT '',
  age INTEGER NOT NULL DEFAULT 0,
  enrolled TEXT NOT NULL);
CREATE TABLE scans (
  id INTEGER PRIMARY KEY,
  subject INTEGER NOT NULL REFERENCES subjects(id) ON DELETE CASCADE,
  path TEXT NOT NULL);
CREATE TABLE poses (
  id INTEGER PRIMARY KEY,
  subject INTEGER NOT NULL REFERENCES subjects(id) ON DELETE CASCADE,
  sequence INTEGER NOT NULL,  -- 0 = eta1, 1 = eta2 (thesis 5.8.3)
  frame INTEGER NOT NULL,     -- gait-cycle frame, 1-based
  p BLOB NOT NULL, q BLOB NOT NULL, r BLOB NOT NULL,  -- eqs 5.1-5.3, float64
  shape BLOB NOT NULL,        -- radii (12 proximal, 12 distal), shoulder/hip offsets (4)
  dynamic BLOB NOT NULL, statics BLOB NOT NULL);  -- 3D gait features (5.7)
CREATE INDEX poses_subject ON poses(subject);
CREATE INDEX scans_subject ON scans(subject);
CREATE TABLE normalization (  -- eqs 5.14-5.15 over the whole gallery, per view
  view TEXT PRIMARY KEY,
  pose_count INTEGER NOT NULL,
  mean_dynamic BLOB NOT NULL, sigma_dynamic BLOB NOT NULL,
  mean_static BLOB NOT NULL, sigma_static BLOB NOT NULL,
  -- running sums (FeatureMoments): an enrolment or removal updates them from its own poses
  sum_dynamic BLOB NOT NULL, sum_sq_dynamic BLOB NOT NULL,
  sum_static BLOB NOT NULL, sum_sq_static BLOB NOT NULL,
  mean_shape BLOB NOT NULL, sigma_shape BLOB NOT NULL,  -- bodyShapeFeatures, 3D only (2D: empty)
  sum_shape BLOB NOT NULL, sum_sq_shape BLOB NOT NULL);
)sql";

// The radii, then the joint placements in kJointPlacements order. Galleries written before
// hip_back existed store one placement fewer: their hips sit on the lower torso's axis.
constexpr int kPlacementCount = std::size(body_gait_model::kJointPlacements);
constexpr int kShapeBlobSize = 2 * body_gait_model::kSegmentCount + kPlacementCount;

constexpr View kViews[] = {View::k3D, View::kFrontal, View::kSide};

Eigen::VectorXd shapeVector(const body_gait_model::BodyShape& shape) {
  Eigen::VectorXd v(kShapeBlobSize);
  for (int i = 0; i < body_gait_model::kSegmentCount; ++i) {
    v[i] = shape.proximal_radius[i];
    v[body_gait_model::kSegmentCount + i] = shape.distal_radius[i];
  }
  for (int i = 0; i < kPlacementCount; ++i)
    v[2 * body_gait_model::kSegmentCount + i] = shape.*body_gait_model::kJointPlacements[i].field;
  return v;
}

// fail: the database's clear error for a blob of neither size.
template <typename Fail>
body_gait_model::BodyShape shapeFromVector(const Eigen::VectorXd& v, const Fail& fail) {
  if (v.size() != kShapeBlobSize && v.size() != kShapeBlobSize - 1)
    fail(SQLITE_CORRUPT, "reading a pose's shape: " + std::to_string(v.size()) +
                             " numbers, expected " + std::to_string(kShapeBlobSize));
  body_gait_model::BodyShape shape;
  for (int i = 0; i < body_gait_model::kSegmentCount; ++i) {
    shape.proximal_radius[i] = v[i];
    shape.distal_radius[i] = v[body_gait_model::kSegmentCount + i];
  }
  shape.hip_back = 0;
  for (int i = 0; i < v.size() - 2 * body_gait_model::kSegmentCount; ++i)
    shape.*body_gait_model::kJointPlacements[i].field = v[2 * body_gait_model::kSegmentCount + i];
  return shape;
}

// One prepared statement; errors go through the database's fail() for the clear messages.
class Statement {
 public:
  using Fail = std::function<void(int, const std::string&)>;  // throws GalleryError

  Statement(sqlite3* db, const char* sql, Fail fail) : sql_(sql), fail_(std::move(fail)) {
    const int rc = sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr);
    if (rc != SQLITE_OK) fail_(rc, std::string("preparing '") + sql + "'");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void bind(int i, std::int64_t v) { check(sqlite3_bind_int64(stmt_, i, v)); }
  void bind(int i, int v) { check(sqlite3_bind_int(stmt_, i, v)); }
  void bind(int i, const std::string& v) {
    check(sqlite3_bind_text(stmt_, i, v.c_str(), int(v.size()), SQLITE_TRANSIENT));
  }
  void bind(int i, const Eigen::VectorXd& v) {
    if (v.size() == 0) {  // an empty array (a 2D view's shape): a blob of 0 bytes, not NULL
      check(sqlite3_bind_zeroblob(stmt_, i, 0));
      return;
    }
    check(sqlite3_bind_blob(stmt_, i, v.data(), int(v.size() * sizeof(double)), SQLITE_TRANSIENT));
  }
  // True while there is a row.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail_(rc, std::string("running '") + sql_ + "'");
    return false;
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  std::int64_t integer(int column) const { return sqlite3_column_int64(stmt_, column); }
  std::string text(int column) const {
    const unsigned char* t = sqlite3_column_text(stmt_, column);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  // A float64 array of the expected size (a corrupt row is reported, not read past).
  Eigen::VectorXd vector(int column, Eigen::Index expected) const {
    const int bytes = sqlite3_column_bytes(stmt_, column);
    if (expected >= 0 && bytes != int(expected * sizeof(double)))
      fail_(SQLITE_CORRUPT, "reading column " + std::string(sqlite3_column_name(stmt_, column)) +
                                ": " + std::to_string(bytes) + " bytes, expected " +
                                std::to_string(expected * sizeof(double)));
    Eigen::VectorXd v(bytes / sizeof(double));
    if (bytes > 0) std::memcpy(v.data(), sqlite3_column_blob(stmt_, column), v.size() * 8);
    return v;
  }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail_(rc, std::string("binding '") + sql_ + "'");
  }
  const char* sql_;
  sqlite3_stmt* stmt_ = nullptr;
  std::function<void(int, const std::string&)> fail_;
};

// BEGIN IMMEDIATE ... COMMIT, rolled back if anything throws before commit().
class Transaction {
 public:
  Transaction(sqlite3* db, Statement::Fail fail) : db_(db), fail_(std::move(fail)) {
    const int rc = sqlite3_exec(db_, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr);
    if (rc != SQLITE_OK) fail_(rc, "starting a write transaction");
  }
  void commit() {
    const int rc = sqlite3_exec(db_, "COMMIT", nullptr, nullptr, nullptr);
    if (rc != SQLITE_OK) fail_(rc, "committing");
    committed_ = true;
  }
  ~Transaction() {
    if (!committed_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }

 private:
  sqlite3* db_;
  Statement::Fail fail_;
  bool committed_ = false;
};

}  // namespace

std::string defaultGalleryPath() {
  if (const char* ros_home = std::getenv("ROS_HOME"); ros_home && *ros_home)
    return std::string(ros_home) + "/gait_gallery.db";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.ros/gait_gallery.db";
  return "gait_gallery.db";
}

const char* viewName(View view) {
  switch (view) {
    case View::kFrontal:
      return "frontal";
    case View::kSide:
      return "side";
    case View::k3D:
      break;
  }
  return "3d";
}

View parseView(const std::string& name) {
  for (View view : kViews)
    if (name == viewName(view)) return view;
  throw std::invalid_argument("unknown view '" + name + "': use 3d, frontal or side");
}

const char* featureSetName(FeatureSet set) {
  switch (set) {
    case FeatureSet::kDynamic:
      return "dynamic";
    case FeatureSet::kDynamicStaticShape:
      return "dynamic_static_shape";
    case FeatureSet::kStatic:
      return "static";
    case FeatureSet::kShape:
      return "shape";
    case FeatureSet::kStaticShape:
      return "static_shape";
    case FeatureSet::kDynamicShape:
      return "dynamic_shape";
    case FeatureSet::kDynamicStatic:
      break;
  }
  return "dynamic_static";
}

FeatureSet parseFeatureSet(const std::string& name) {
  for (FeatureSet set : {FeatureSet::kDynamic, FeatureSet::kDynamicStatic,
                         FeatureSet::kDynamicStaticShape, FeatureSet::kStatic, FeatureSet::kShape,
                         FeatureSet::kStaticShape, FeatureSet::kDynamicShape})
    if (name == featureSetName(set)) return set;
  throw std::invalid_argument(
      "unknown feature set '" + name +
      "': use dynamic, dynamic_static or dynamic_static_shape (or static, shape, static_shape, "
      "dynamic_shape)");
}

void GalleryDatabase::fail(int code, const std::string& what) const {
  const std::string file = "gallery database '" + path_ + "'";
  const std::string detail = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(code);
  switch (code & 0xff) {
    case SQLITE_NOTADB:
      throw GalleryError(file + ": file is not a database (corrupt, or another kind of file): " +
                         "restore it from a backup, or move it away to start a new gallery " +
                         "(a missing file is created), or point ~database / --database at "
                         "another file");
    case SQLITE_CORRUPT:
      throw GalleryError(file + " is corrupt (" + detail + ", " + what +
                         "): restore it from a backup, or move it away and enrol again");
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      throw GalleryError(file + " is locked by another writer (waited " +
                         std::to_string(busy_timeout_.count()) + " ms, " + what +
                         "): stop the other process using it (another gait_id_node or "
                         "gait_gallery) or use another file");
    case SQLITE_READONLY:
    case SQLITE_CANTOPEN:
    case SQLITE_PERM:
    case SQLITE_IOERR:
    case SQLITE_FULL:
      throw GalleryError("cannot write " + file + " (" + detail + ", " + what +
                         "): check that its directory exists, is writable and has space, or "
                         "choose another path");
    default:
      throw GalleryError(file + ": " + what + " failed: " + detail);
  }
}

GalleryDatabase::GalleryDatabase(const std::string& path, std::chrono::milliseconds busy_timeout)
    : path_(path), busy_timeout_(busy_timeout) {
  if (path.empty())
    throw GalleryError("gallery database: empty path; give a file name (e.g. gait_gallery.db)");
  // Biometric data: a new gallery is readable by its owner only. SQLite would create it (and
  // its -wal and -shm files, which copy the database's mode) with 0644; an empty file is a
  // valid empty database, so it is made here first with 0600.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd >= 0) ::close(fd);
  const int rc =
      sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  try {
    if (rc != SQLITE_OK) fail(rc, "opening");
    sqlite3_busy_timeout(db_, int(busy_timeout_.count()));
    sqlite3_extended_result_codes(db_, 1);
    // WAL: readers do not block the writer; synchronous FULL: a committed enrolment survives a
    // power cut too, not only a killed process.
    exec("PRAGMA journal_mode=WAL", "switching to WAL");
    exec("PRAGMA synchronous=FULL", "setting synchronous");
    exec("PRAGMA foreign_keys=ON", "enabling foreign keys");
    createOrCheckSchema();
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

GalleryDatabase::~GalleryDatabase() { sqlite3_close(db_); }

void GalleryDatabase::exec(const char* sql, const char* what) {
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, sql, nullptr, nullptr, &message);
  sqlite3_free(message);
  if (rc != SQLITE_OK) fail(rc, what);
}

int GalleryDatabase::tableCount(bool& has_version) const {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  Statement list(db_, "SELECT name FROM sqlite_master WHERE type = 'table'", thrower);
  int tables = 0;
  has_version = false;
  while (list.step()) {
    ++tables;
    has_version = has_version || list.text(0) == "schema_version";
  }
  return tables;
}

void GalleryDatabase::createOrCheckSchema() {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  bool has_version = false;
  if (tableCount(has_version) == 0) {
    // A new file: create the schema under the write lock, checking again under it in case
    // another process created it meanwhile. An existing gallery opens without the write lock,
    // so a node can start while another process enrols.
    Transaction transaction(db_, thrower);
    if (tableCount(has_version) == 0) {
      exec(kSchema, "creating the schema");
      Statement insert(db_, "INSERT INTO schema_version (version) VALUES (?)", thrower);
      insert.bind(1, kSchemaVersion);
      insert.step();
      has_version = true;
    }
    transaction.commit();
  }
  if (!has_version)
    throw GalleryError("gallery database '" + path_ +
                       "' is an SQLite file but not a gait gallery (no schema_version table): "
                       "point ~database / --database at a gallery file or a new file name");
  std::int64_t found = -1;
  {
    Statement version(db_, "SELECT version FROM schema_version", thrower);
    found = version.step() ? version.integer(0) : -1;
  }
  if (found == 1 || found == 2) {
    upgradeFrom(static_cast<int>(found));
    found = kSchemaVersion;
  }
  if (found > kSchemaVersion)
    throw GalleryError("gallery database '" + path_ + "' has schema version " +
                       std::to_string(found) + ", newer than this body_gait_id's " +
                       std::to_string(kSchemaVersion) + ": update body_gait_id to read it");
  if (found != kSchemaVersion)
    throw GalleryError("gallery database '" + path_ + "' has an unknown schema version (" +
                       std::to_string(found) + "; expected " + std::to_string(kSchemaVersion) +
                       "): restore it from a backup or start a new gallery file");
}

void GalleryDatabase::upgradeFrom(int version_found) {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  Transaction transaction(db_, thrower);
  {
    Statement version(db_, "SELECT version FROM schema_version", thrower);
    if (version.step() && version.integer(0) != version_found)
      return;  // another process upgraded it
  }
  if (version_found == 1)
    exec(
        "ALTER TABLE normalization ADD COLUMN sum_dynamic BLOB NOT NULL DEFAULT x'';"
        "ALTER TABLE normalization ADD COLUMN sum_sq_dynamic BLOB NOT NULL DEFAULT x'';"
        "ALTER TABLE normalization ADD COLUMN sum_static BLOB NOT NULL DEFAULT x'';"
        "ALTER TABLE normalization ADD COLUMN sum_sq_static BLOB NOT NULL DEFAULT x'';",
        "upgrading the schema from version 1");
  exec(
      "ALTER TABLE normalization ADD COLUMN mean_shape BLOB NOT NULL DEFAULT x'';"
      "ALTER TABLE normalization ADD COLUMN sigma_shape BLOB NOT NULL DEFAULT x'';"
      "ALTER TABLE normalization ADD COLUMN sum_shape BLOB NOT NULL DEFAULT x'';"
      "ALTER TABLE normalization ADD COLUMN sum_sq_shape BLOB NOT NULL DEFAULT x'';"
      "DELETE FROM normalization;",
      "upgrading the schema to store the body-shape statistics");
  // Every sum once from the stored poses (their models carry r and the shape).
  updateNormalization(poseRecords(), +1.0);
  Statement version(db_, "UPDATE schema_version SET version = ?", thrower);
  version.bind(1, kSchemaVersion);
  version.step();
  transaction.commit();
}

std::int64_t GalleryDatabase::enroll(const SubjectInfo& info, const std::vector<std::string>& scans,
                                     const std::vector<PoseRecord>& poses) {
  if (info.name.empty())
    throw GalleryError("gallery database '" + path_ + "': enrolment without a name: give one");
  if (poses.empty())
    throw GalleryError(
        "gallery database '" + path_ +
        "': enrolment without training poses: give the 4 fitted representative poses");
  // A NaN would poison the running sums of every later identification.
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const body_gait_model::BodyModel& m = poses[i].model;
    if (!m.p.allFinite() || !m.q.allFinite() || !m.r.allFinite())
      throw GalleryError("gallery database '" + path_ + "': enrolment refused: pose " +
                         std::to_string(i + 1) +
                         " has non-finite values (NaN or inf); fit that scan again");
  }
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  Transaction transaction(db_, thrower);
  Statement subject(db_,
                    "INSERT INTO subjects (name, gender, age, enrolled) "
                    "VALUES (?, ?, ?, strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))",
                    thrower);
  subject.bind(1, info.name);
  subject.bind(2, info.gender);
  subject.bind(3, info.age);
  subject.step();
  const std::int64_t id = sqlite3_last_insert_rowid(db_);

  Statement scan(db_, "INSERT INTO scans (subject, path) VALUES (?, ?)", thrower);
  for (const std::string& path : scans) {
    scan.reset();
    scan.bind(1, id);
    scan.bind(2, path);
    scan.step();
  }
  Statement pose(db_,
                 "INSERT INTO poses (subject, sequence, frame, p, q, r, shape, dynamic, statics) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                 thrower);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const PoseRecord& record = poses[i];
    const GaitFeatures features = gaitFeatures(record.model, View::k3D);
    pose.reset();
    pose.bind(1, id);
    pose.bind(2, record.sequence);
    pose.bind(3, record.frame);
    pose.bind(4, Eigen::VectorXd(record.model.p));
    pose.bind(5, Eigen::VectorXd(record.model.q));
    pose.bind(6, Eigen::VectorXd(record.model.r));
    pose.bind(7, shapeVector(record.model.shape));
    pose.bind(8, features.dynamic);
    pose.bind(9, features.statics);
    pose.step();
    if (enroll_hook_) enroll_hook_(static_cast<int>(i));
  }
  updateNormalization(poses, +1.0);
  transaction.commit();
  return id;
}

bool GalleryDatabase::remove(std::int64_t subject_id) {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  Transaction transaction(db_, thrower);
  std::vector<PoseRecord> leaving = poseRecords(subject_id);
  Statement erase(db_, "DELETE FROM subjects WHERE id = ?", thrower);
  erase.bind(1, subject_id);
  erase.step();
  if (sqlite3_changes(db_) == 0) return false;  // rolled back: nothing changed
  updateNormalization(leaving, -1.0);
  transaction.commit();
  return true;
}

void GalleryDatabase::updateNormalization(const std::vector<PoseRecord>& poses, double weight) {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  for (View view : kViews) {
    const std::string name = viewName(view);
    FeatureMoments moments;
    {
      Statement read(db_,
                     "SELECT pose_count, sum_dynamic, sum_sq_dynamic, sum_static, sum_sq_static, "
                     "sum_shape, sum_sq_shape FROM normalization WHERE view = ?",
                     thrower);
      read.bind(1, name);
      if (read.step()) {
        const Eigen::Index nd = dynamicSize(view);
        moments.count = static_cast<double>(read.integer(0));
        moments.sum_dynamic = read.vector(1, nd);
        moments.sum_sq_dynamic = read.vector(2, nd);
        moments.sum_static = read.vector(3, kStaticSize);
        moments.sum_sq_static = read.vector(4, kStaticSize);
        const Eigen::Index nb = view == View::k3D ? kShapeSize : 0;
        moments.sum_shape = read.vector(5, nb);
        moments.sum_sq_shape = read.vector(6, nb);
      }
    }
    for (const PoseRecord& record : poses) moments.add(gaitFeatures(record.model, view), weight);
    if (moments.count < 0.5) {  // the last subject left: no statistics
      Statement erase(db_, "DELETE FROM normalization WHERE view = ?", thrower);
      erase.bind(1, name);
      erase.step();
      continue;
    }
    const FeatureNormalization n = moments.normalization();
    Statement store(db_,
                    "INSERT OR REPLACE INTO normalization (view, pose_count, mean_dynamic, "
                    "sigma_dynamic, mean_static, sigma_static, sum_dynamic, sum_sq_dynamic, "
                    "sum_static, sum_sq_static, mean_shape, sigma_shape, sum_shape, sum_sq_shape) "
                    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    thrower);
    store.bind(1, name);
    store.bind(2, static_cast<std::int64_t>(std::llround(moments.count)));
    store.bind(3, n.mean_dynamic);
    store.bind(4, n.sigma_dynamic);
    store.bind(5, n.mean_static);
    store.bind(6, n.sigma_static);
    store.bind(7, moments.sum_dynamic);
    store.bind(8, moments.sum_sq_dynamic);
    store.bind(9, moments.sum_static);
    store.bind(10, moments.sum_sq_static);
    store.bind(11, n.mean_shape);
    store.bind(12, n.sigma_shape);
    store.bind(13, moments.sum_shape);
    store.bind(14, moments.sum_sq_shape);
    store.step();
  }
}

std::vector<Subject> GalleryDatabase::subjects() const {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  std::vector<Subject> out;
  std::map<std::int64_t, std::size_t> index;
  {
    Statement list(db_,
                   "SELECT s.id, s.name, s.gender, s.age, s.enrolled, "
                   "(SELECT COUNT(*) FROM poses p WHERE p.subject = s.id) "
                   "FROM subjects s ORDER BY s.id",
                   thrower);
    while (list.step()) {
      Subject s;
      s.id = list.integer(0);
      s.info = {list.text(1), list.text(2), static_cast<int>(list.integer(3))};
      s.enrolled = list.text(4);
      s.pose_count = static_cast<int>(list.integer(5));
      index[s.id] = out.size();
      out.push_back(std::move(s));
    }
  }
  Statement scans(db_, "SELECT subject, path FROM scans ORDER BY id", thrower);
  while (scans.step()) {
    const auto it = index.find(scans.integer(0));
    if (it != index.end()) out[it->second].scans.push_back(scans.text(1));
  }
  return out;
}

std::vector<PoseRecord> GalleryDatabase::poseRecords(std::int64_t subject_id) const {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  Statement list(db_,
                 "SELECT subject, sequence, frame, p, q, r, shape FROM poses "
                 "WHERE ? = 0 OR subject = ? ORDER BY id",
                 thrower);
  list.bind(1, subject_id);
  list.bind(2, subject_id);
  std::vector<PoseRecord> out;
  while (list.step()) {
    PoseRecord record;
    record.subject_id = list.integer(0);
    record.sequence = static_cast<int>(list.integer(1));
    record.frame = static_cast<int>(list.integer(2));
    record.model.p = list.vector(3, 6);
    record.model.q = list.vector(4, 22);
    record.model.r = list.vector(5, 12);
    record.model.shape = shapeFromVector(list.vector(6, -1), thrower);
    out.push_back(std::move(record));
  }
  return out;
}

std::vector<GalleryPose> GalleryDatabase::poses(View view) const {
  std::vector<GalleryPose> out;
  if (view != View::k3D) {
    for (const PoseRecord& record : poseRecords())
      out.push_back(
          {record.subject_id, record.sequence, record.frame, gaitFeatures(record.model, view)});
    return out;
  }
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  // The shape measures are computed from the stored r and shape (not stored per pose).
  Statement list(db_,
                 "SELECT subject, sequence, frame, dynamic, statics, r, shape FROM poses "
                 "ORDER BY id",
                 thrower);
  while (list.step()) {
    body_gait_model::BodyModel model;
    model.r = list.vector(5, kStaticSize);
    model.shape = shapeFromVector(list.vector(6, -1), thrower);
    out.push_back({list.integer(0),
                   static_cast<int>(list.integer(1)),
                   static_cast<int>(list.integer(2)),
                   {list.vector(3, dynamicSize(View::k3D)), list.vector(4, kStaticSize),
                    bodyShapeFeatures(model)}});
  }
  return out;
}

FeatureNormalization GalleryDatabase::normalization(View view) const {
  const auto thrower = [this](int code, const std::string& what) { fail(code, what); };
  Statement read(db_,
                 "SELECT mean_dynamic, sigma_dynamic, mean_static, sigma_static, mean_shape, "
                 "sigma_shape FROM normalization WHERE view = ?",
                 thrower);
  read.bind(1, std::string(viewName(view)));
  if (!read.step())
    throw GalleryError("gallery database '" + path_ +
                       "' has no normalization statistics: the gallery is empty; enrol at least "
                       "one subject first");
  const Eigen::Index nd = dynamicSize(view);
  FeatureNormalization n;
  n.mean_dynamic = read.vector(0, nd);
  n.sigma_dynamic = read.vector(1, nd);
  n.mean_static = read.vector(2, kStaticSize);
  n.sigma_static = read.vector(3, kStaticSize);
  const Eigen::Index nb = view == View::k3D ? kShapeSize : 0;  // 2D views: no shape
  n.mean_shape = read.vector(4, nb);
  n.sigma_shape = read.vector(5, nb);
  return n;
}

Matcher GalleryDatabase::matcher(FeatureSet set, View view, const FeatureNoise* noise) const {
  std::vector<GalleryPose> gallery = poses(view);
  if (gallery.empty())
    throw GalleryError("gallery database '" + path_ +
                       "' has no enrolled subjects: enrol at least one subject first");
  FeatureNormalization n = normalization(view);
  if (noise) n.weights = noiseWeights(n, *noise, set);
  return Matcher(std::move(gallery), set, std::move(n));
}

}  // namespace body_gait_id
