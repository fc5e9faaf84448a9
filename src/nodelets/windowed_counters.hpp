#pragma once
// Diagnostic counters kept per report window and since start, updated under one lock.
#include <ros/time.h>

#include <algorithm>
#include <mutex>

namespace multimodal_nvs {

/// A nodelet's diagnostic counters twice over: since the last report (the rates) and since start
/// (the totals). Every event updates both under one lock, as the subscriber, frame and service
/// callbacks count concurrently.
template <class Counts>
class WindowedCounters {
 public:
  /// Opens the first window: rates are measured from here.
  void start() {
    std::lock_guard<std::mutex> lock(mutex_);
    window_start_ = ros::WallTime::now();
  }

  /// Applies `count(Counts&)` to the window and to the totals.
  template <class Count>
  void update(Count&& count) {
    std::lock_guard<std::mutex> lock(mutex_);
    count(window_);
    count(total_);
  }

  /// Calls `report(window, total, seconds)`, `seconds` being the window's length, then opens a new
  /// window.
  template <class Report>
  void closeWindow(Report&& report) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::WallTime now = ros::WallTime::now();
    const double seconds = std::max(1e-6, (now - window_start_).toSec());
    report(static_cast<const Counts&>(window_), static_cast<const Counts&>(total_), seconds);
    window_ = Counts();
    window_start_ = now;
  }

 private:
  std::mutex mutex_;
  Counts window_, total_;
  ros::WallTime window_start_;
};

}  // namespace multimodal_nvs
