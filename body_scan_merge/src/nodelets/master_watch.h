// MasterWatch: a restarted ROS master knows nothing of the running nodes; roscpp does not
// register them again. Connections already made keep working, but no new client finds a service
// and no new subscriber finds a publisher. The watch polls the master once a second; when another
// master answers (its pid changed) it registers this process's publications and services with
// it. Not its subscriptions: the new master would then send this process publisher lists without
// the publishers of processes that do not register again (e.g. nodelet loaders' bonds), and
// roscpp drops the connections missing from a list. One watch per process, shared by the
// nodelets that hold it.
#pragma once

#include <ros/callback_queue.h>
#include <ros/connection_manager.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/publication.h>
#include <ros/ros.h>
#include <ros/topic_manager.h>
#include <ros/xmlrpc_manager.h>

#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace body_scan_merge {

class MasterWatch {
 public:
  // The process's watch, started by the first holder, stopped with the last.
  static std::shared_ptr<MasterWatch> acquire() {
    static std::mutex mutex;
    static std::weak_ptr<MasterWatch> shared;
    std::lock_guard<std::mutex> lock(mutex);
    std::shared_ptr<MasterWatch> watch = shared.lock();
    if (!watch) {
      watch.reset(new MasterWatch);
      shared = watch;
    }
    return watch;
  }

 private:
  // Its own queue and thread: a slow master never delays the nodelets' callbacks.
  MasterWatch() {
    ros::NodeHandle nh;
    nh.setCallbackQueue(&queue_);
    timer_ =
        nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { poll(); });
    spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
    spinner_->start();
  }

  static bool call(const std::string& method, XmlRpc::XmlRpcValue args,
                   XmlRpc::XmlRpcValue& payload) {
    XmlRpc::XmlRpcValue result;
    return ros::master::execute(method, args, result, payload, false);
  }

  void poll() {
    XmlRpc::XmlRpcValue args, payload;
    args[0] = ros::this_node::getName();
    if (!call("getPid", args, payload) || payload.getType() != XmlRpc::XmlRpcValue::TypeInt)
      return;  // no master at the moment
    const int pid = payload;
    if (master_pid_ == 0 || pid == master_pid_) {
      master_pid_ = pid;
      rememberServices();
      return;
    }
    ROS_WARN(
        "the ROS master restarted (pid %d, was %d): registering %s's topics and %zu "
        "service(s) again",
        pid, master_pid_, ros::this_node::getName().c_str(), services_.size());
    master_pid_ = pid;
    reregister();
  }

  // roscpp keeps no list of a process's services: remember those the master names this node
  // as the provider of, while it is the master we registered with.
  void rememberServices() {
    XmlRpc::XmlRpcValue args, state;
    args[0] = ros::this_node::getName();
    if (!call("getSystemState", args, state) || state.size() < 3) return;
    XmlRpc::XmlRpcValue& services = state[2];
    std::set<std::string> mine;
    for (int i = 0; i < services.size(); ++i)
      for (int j = 0; j < services[i][1].size(); ++j)
        if (static_cast<std::string>(services[i][1][j]) == ros::this_node::getName())
          mine.insert(static_cast<std::string>(services[i][0]));
    services_ = mine;
  }

  void reregister() {
    const std::string caller = ros::this_node::getName();
    const std::string api = ros::XMLRPCManager::instance()->getServerURI();
    auto topics = ros::TopicManager::instance();
    std::vector<std::string> names;
    topics->getAdvertisedTopics(names);
    for (const std::string& topic : names) {
      const ros::PublicationPtr publication = topics->lookupPublication(topic);
      if (!publication) continue;
      XmlRpc::XmlRpcValue args, payload;
      args[0] = caller;
      args[1] = topic;
      args[2] = publication->getDataType();
      args[3] = api;
      if (!call("registerPublisher", args, payload))
        ROS_WARN("registering the publisher of %s again failed", topic.c_str());
    }
    const std::string service_api =
        "rosrpc://" + ros::network::getHost() + ":" +
        std::to_string(ros::ConnectionManager::instance()->getTCPPort());
    for (const std::string& service : services_) {
      XmlRpc::XmlRpcValue args, payload;
      args[0] = caller;
      args[1] = service;
      args[2] = service_api;
      args[3] = api;
      if (!call("registerService", args, payload))
        ROS_WARN("registering the service %s again failed", service.c_str());
    }
  }

  int master_pid_ = 0;
  std::set<std::string> services_;
  ros::CallbackQueue queue_;
  ros::WallTimer timer_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;  // stopped first
};

}  // namespace body_scan_merge
