// gait_id_node: the ROS face of the gait gallery (thesis 5.7-5.8); its topics, services and
// parameters are in body_gait_id/README.md. Thin: the work is body_gait_id's core
// (GalleryDatabase, trainingPoses, Matcher).
//
// A database that cannot be opened (corrupt, locked, newer schema) is reported once at start
// and in every service reply; the node keeps running and tries the file again on the next
// call, so fixing or replacing the file needs no restart.
#include <body_gait_id/enrollment.h>
#include <body_gait_id/feature_noise_file.h>
#include <body_gait_id/gallery_database.h>
#include <body_gait_id/walk_identification.h>
#include <body_gait_model/ros/body_model_msg.h>
#include <body_gait_model/walk_collector.h>
#include <body_scan_msgs/EnrollSubject.h>
#include <body_scan_msgs/Identify.h>
#include <body_scan_msgs/Identity.h>
#include <body_scan_msgs/ListSubjects.h>
#include <body_scan_msgs/RemoveSubject.h>
#include <ros/ros.h>

#include <map>
#include <memory>
#include <optional>

namespace body_gait_id {

// Equal-error threshold of 3D dynamic + static features (evaluate_gait_id --protocol cross-walk
// --subjects 20 --scanner sampler: eer_threshold 4.53, EER 11.8 %).
constexpr double kDefaultAcceptThreshold = 4.5;

class GaitIdNode {
 public:
  GaitIdNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    path_ = pnh.param<std::string>("database", defaultGalleryPath());
    busy_timeout_ =
        std::chrono::milliseconds(static_cast<int>(1000 * pnh.param<double>("busy_timeout", 2.0)));
    accept_threshold_ = pnh.param<double>("accept_threshold", kDefaultAcceptThreshold);
    walk_accept_threshold_ =
        pnh.param<double>("walk_accept_threshold", kDefaultWalkAcceptThreshold);
    ranks_ = std::max(1, pnh.param("ranks", 5));
    try {
      set_ = parseFeatureSet(pnh.param<std::string>("feature_set", "dynamic_static"));
      view_ = parseView(pnh.param<std::string>("view", "3d"));
    } catch (const std::invalid_argument& e) {
      ROS_ERROR("%s; using dynamic_static features in 3D", e.what());
    }
    const std::string walk_body = pnh.param<std::string>("walk_body", "mean");
    median_body_ = walk_body == "median";
    if (walk_body != "mean" && walk_body != "median")
      ROS_ERROR("~walk_body must be mean or median, got '%s'; using mean", walk_body.c_str());
    const std::string noise_file = pnh.param<std::string>("feature_noise", "");
    if (!noise_file.empty()) {
      try {
        noise_ = readFeatureNoise(noise_file);
      } catch (const std::exception& e) {
        ROS_ERROR("%s; identifying without noise weights", e.what());
      }
    }
    try {
      database();
      ROS_INFO(
          "gait gallery '%s': %zu subjects; %s features, %s view, accept score <= %.2f (scans), "
          "<= %.2f (walks)",
          path_.c_str(), database().subjects().size(), featureSetName(set_), viewName(view_),
          accept_threshold_, walk_accept_threshold_);
    } catch (const std::exception& e) {
      ROS_ERROR("%s", e.what());
    }
    enroll_ = pnh.advertiseService("enroll", &GaitIdNode::onEnroll, this);
    identify_ = pnh.advertiseService("identify", &GaitIdNode::onIdentify, this);
    remove_ = pnh.advertiseService("remove", &GaitIdNode::onRemove, this);
    list_ = pnh.advertiseService("list", &GaitIdNode::onList, this);
    identity_pub_ = nh.advertise<body_scan_msgs::Identity>("body_gait/identity", 4);
    model_sub_ = nh.subscribe("body_gait/model", 4, &GaitIdNode::onModel, this);
  }

 private:
  // The open gallery, opened (again) on demand. Throws GalleryError.
  GalleryDatabase& database() {
    if (!db_) db_ = std::make_unique<GalleryDatabase>(path_, busy_timeout_);
    return *db_;
  }
  // Forget the connection after a failure so the next call reopens the file.
  void reset(const std::exception& e) {
    ROS_ERROR_THROTTLE(5.0, "%s", e.what());
    db_.reset();
    matcher_.reset();
  }

  struct Answer {
    Match match;
    std::string name;
  };
  // The matcher of the current gallery, rebuilt after every enrolment or removal (the gallery
  // and its statistics changed).
  const Matcher& matcher() {
    if (!matcher_) {
      matcher_.emplace(database().matcher(set_, view_, noise_ ? &*noise_ : nullptr));
      names_.clear();
      for (const Subject& s : database().subjects()) names_[s.id] = s.info.name;
    }
    return *matcher_;
  }
  Answer identify(const body_scan_msgs::BodyModel& model) {
    const Match match = matcher().identify(gaitFeatures(body_gait_model::fromMsg(model), view_));
    return {match, names_[match.subject_id]};
  }

  bool onEnroll(body_scan_msgs::EnrollSubject::Request& req,
                body_scan_msgs::EnrollSubject::Response& res) {
    try {
      std::vector<body_gait_model::BodyModel> models;
      for (const auto& pose : req.poses) models.push_back(body_gait_model::fromMsg(pose));
      const body_gait_model::RepresentativePoses s = representativePoses(models);
      const std::vector<PoseRecord> poses = trainingPoses(median_body_ ? withMedianBody(s) : s);
      res.subject_id = database().enroll({req.name, req.gender, req.age}, req.scan_paths, poses);
      res.pose_count = static_cast<int>(poses.size());
      res.success = true;
      matcher_.reset();
      // Names are personal data: above DEBUG the logs carry subject ids only.
      ROS_INFO("enrolled subject %ld (%d poses)", static_cast<long>(res.subject_id),
               res.pose_count);
      ROS_DEBUG("subject %ld is '%s'", static_cast<long>(res.subject_id), req.name.c_str());
    } catch (const GalleryError& e) {
      res.message = e.what();
      reset(e);
    } catch (const std::exception& e) {  // bad request: the gallery is fine
      res.message = std::string("enrolment refused: ") + e.what();
      ROS_ERROR("%s", res.message.c_str());
    }
    return true;
  }

  // The answer's fields, shared by the Identify reply and the Identity message.
  template <typename Out>
  void fillIdentity(const Answer& answer, Out& out) const {
    out.subject_id = answer.match.subject_id;
    out.name = answer.name;
    out.sequence = answer.match.sequence;
    out.frame = answer.match.frame;
    out.score = answer.match.score;
    out.accepted = answer.match.score <= accept_threshold_;
  }

  bool onIdentify(body_scan_msgs::Identify::Request& req, body_scan_msgs::Identify::Response& res) {
    try {
      fillIdentity(identify(req.model), res);
      res.success = true;
    } catch (const GalleryError& e) {
      res.message = e.what();
      reset(e);
    } catch (const std::exception& e) {
      res.message = std::string("identification refused: ") + e.what();
      ROS_ERROR("%s", res.message.c_str());
    }
    return true;
  }

  bool onRemove(body_scan_msgs::RemoveSubject::Request& req,
                body_scan_msgs::RemoveSubject::Response& res) {
    try {
      res.success = database().remove(req.subject_id);
      matcher_.reset();
      if (!res.success)
        res.message = "no subject " + std::to_string(req.subject_id) + " in gallery '" + path_ +
                      "': see ~list for the enrolled ids";
    } catch (const GalleryError& e) {
      res.message = e.what();
      reset(e);
    } catch (const std::exception& e) {
      res.message = e.what();
      ROS_ERROR("%s", res.message.c_str());
    }
    return true;
  }

  bool onList(body_scan_msgs::ListSubjects::Request&, body_scan_msgs::ListSubjects::Response& res) {
    try {
      for (const Subject& s : database().subjects()) {
        res.subject_ids.push_back(s.id);
        res.names.push_back(s.info.name);
        res.genders.push_back(s.info.gender);
        res.ages.push_back(s.info.age);
        res.pose_counts.push_back(s.pose_count);
      }
      res.success = true;
    } catch (const GalleryError& e) {
      res.message = e.what();
      reset(e);
    } catch (const std::exception& e) {
      res.message = e.what();
      ROS_ERROR("%s", res.message.c_str());
    }
    return true;
  }

  void onModel(const body_scan_msgs::BodyModel::ConstPtr& msg) {
    try {
      body_scan_msgs::Identity identity;
      identity.header = msg->header;
      identity.kind = body_scan_msgs::Identity::SCAN;
      identity.walk_id = msg->walk_id;
      identity.scan_id = msg->scan_id;
      identity.pose_index = msg->pose_index;
      fillIdentity(identify(*msg), identity);
      identity.threshold = accept_threshold_;
      const std::vector<Match> ranked =
          matcher().rankSubjects(gaitFeatures(body_gait_model::fromMsg(*msg), view_));
      for (std::size_t i = 0; i < ranked.size() && i < static_cast<std::size_t>(ranks_); ++i)
        addRank(identity, ranked[i].subject_id, ranked[i].score);
      identity_pub_.publish(identity);
      ROS_INFO("identified %s: subject %ld, sequence %d, frame %d, score %.3f (%s)",
               scanName(*msg).c_str(), static_cast<long>(identity.subject_id), identity.sequence,
               identity.frame, identity.score, identity.accepted ? "accepted" : "rejected");
    } catch (const GalleryError& e) {
      reset(e);
    } catch (const std::exception& e) {  // fromMsg names the bad field
      ROS_ERROR_THROTTLE(5.0, "model on body_gait/model not identified: %s", e.what());
    } catch (...) {
      ROS_ERROR_THROTTLE(5.0, "model on body_gait/model not identified: unknown error");
    }
    if (msg->walk_id != 0) collectWalk(msg);
  }

  static std::string scanName(const body_scan_msgs::BodyModel& model) {
    std::string name = "scan " + std::to_string(model.scan_id);
    if (model.walk_id != 0)
      name += " (walk " + std::to_string(model.walk_id) + " pose " +
              std::to_string(model.pose_index) + ")";
    return name;
  }

  void addRank(body_scan_msgs::Identity& identity, std::int64_t subject_id, double score) {
    identity.ranked_subject_ids.push_back(subject_id);
    identity.ranked_names.push_back(names_[subject_id]);
    identity.ranked_scores.push_back(score);
  }

  // A walk's models as they come; the walk is identified once its 4 poses are in.
  void collectWalk(const body_scan_msgs::BodyModel::ConstPtr& msg) {
    std::optional<body_gait_model::WalkCollector<body_scan_msgs::BodyModel::ConstPtr>::Walk> walk;
    try {
      walk = walks_.add(msg->walk_id, msg->pose_index, msg);
    } catch (const std::invalid_argument& e) {
      ROS_ERROR("%s: not collected into a walk", e.what());
      return;
    }
    for (std::uint32_t dropped : walks_.takeDropped())
      ROS_WARN("walk %u dropped before all %d poses arrived (a newer walk started)", dropped,
               body_gait_model::kWalkPoses);
    if (!walk) return;
    try {
      std::vector<body_gait_model::BodyModel> models;
      for (const auto& pose : *walk) models.push_back(body_gait_model::fromMsg(*pose));
      const body_gait_model::RepresentativePoses s = representativePoses(models);
      const std::vector<WalkMatch> ranked =
          rankWalk(matcher(), median_body_ ? withMedianBody(s) : s, view_);
      if (ranked.empty()) throw std::runtime_error("the gallery is empty: enrol people first");
      body_scan_msgs::Identity identity;
      identity.header = walk->back()->header;
      identity.kind = body_scan_msgs::Identity::WALK;
      identity.walk_id = msg->walk_id;
      identity.subject_id = ranked[0].subject_id;
      identity.name = names_[ranked[0].subject_id];
      identity.sequence = -1;
      identity.frame = 0;
      identity.score = ranked[0].score;
      identity.threshold = walk_accept_threshold_;
      identity.accepted = identity.score <= walk_accept_threshold_;
      for (std::size_t i = 0; i < ranked.size() && i < static_cast<std::size_t>(ranks_); ++i)
        addRank(identity, ranked[i].subject_id, ranked[i].score);
      identity_pub_.publish(identity);
      ROS_INFO("identified walk %u: subject %ld, score %.3f (%s)", identity.walk_id,
               static_cast<long>(identity.subject_id), identity.score,
               identity.accepted ? "accepted" : "rejected: unknown person");
    } catch (const GalleryError& e) {
      reset(e);
    } catch (const std::exception& e) {
      ROS_ERROR("walk %u not identified: %s", msg->walk_id, e.what());
    } catch (...) {  // nothing may escape into the node's spinner
      ROS_ERROR("walk %u not identified: unknown error", msg->walk_id);
    }
  }

  std::string path_;
  std::chrono::milliseconds busy_timeout_{2000};
  double accept_threshold_ = kDefaultAcceptThreshold;
  double walk_accept_threshold_ = kDefaultWalkAcceptThreshold;
  int ranks_ = 5;
  body_gait_model::WalkCollector<body_scan_msgs::BodyModel::ConstPtr> walks_;
  FeatureSet set_ = FeatureSet::kDynamicStatic;
  View view_ = View::k3D;
  std::unique_ptr<GalleryDatabase> db_;
  std::optional<Matcher> matcher_;
  std::optional<FeatureNoise> noise_;  // ~feature_noise: weights of the components
  bool median_body_ = false;           // ~walk_body median
  std::map<std::int64_t, std::string> names_;
  ros::ServiceServer enroll_, identify_, remove_, list_;
  ros::Publisher identity_pub_;
  ros::Subscriber model_sub_;
};

}  // namespace body_gait_id

int main(int argc, char** argv) {
  ros::init(argc, argv, "gait_id");
  ros::NodeHandle nh, pnh("~");
  body_gait_id::GaitIdNode node(nh, pnh);
  ros::spin();
  return 0;
}
