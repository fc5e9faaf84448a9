#pragma once
// A diagnostic task published on a wall timer, so diagnostics flow while a bag is paused.
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <array>
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

/// Adds a "rejected <reason>" row per input fault, counted since start, and "rejected total";
/// returns how many inputs were rejected in the window. Fault 0 is "ok", not a rejection.
template <class Fault, std::size_t kFaultCount>
unsigned long addRejectedRows(diagnostic_updater::DiagnosticStatusWrapper& status,
                              const std::array<unsigned long, kFaultCount>& window_faults,
                              const std::array<unsigned long, kFaultCount>& total_faults) {
  unsigned long rejected_total = 0, rejected_window = 0;
  for (std::size_t f = 1; f < kFaultCount; ++f) {
    rejected_total += total_faults[f];
    rejected_window += window_faults[f];
    status.add(std::string("rejected ") + toString(static_cast<Fault>(f)), total_faults[f]);
  }
  status.add("rejected total", rejected_total);
  return rejected_window;
}

}  // namespace multimodal_nvs
