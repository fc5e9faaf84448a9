#pragma once
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <memory>
#include <string>

namespace multimodal_nvs {

/// One diagnostic task published by a diagnostic_updater on a wall timer (twice a second), so that
/// diagnostics keep flowing while a bag's simulated clock is paused. Shared by the nodelets.
class PeriodicDiagnostics {
 public:
  void start(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const std::string& node_name,
             const std::string& task, const diagnostic_updater::TaskFunction& report) {
    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, private_nh, node_name);
    updater_->setHardwareID("none");
    updater_->add(task, report);
    // force_update: the timer is the period. Updater::update() compares with ros::Time, so after
    // simulated time jumps back (a bag played in a loop) it would stay silent for the jump's
    // length.
    timer_ = nh.createWallTimer(ros::WallDuration(0.5),
                                [this](const ros::WallTimerEvent&) { updater_->force_update(); });
  }

 private:
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer timer_;
};

}  // namespace multimodal_nvs
