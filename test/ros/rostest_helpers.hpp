#pragma once
// Shared by the gtest-in-rostest programs: waiting for what the nodes publish, reading their
// diagnostics, and the main() that runs the tests with a spinner.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace rostest_helpers {

/// Polls `done`, called with `mutex` held (the subscriber callbacks write under it), every 20 ms
/// until it is true (returns true) or `seconds` of wall time have passed (returns false).
inline bool waitFor(std::mutex& mutex, const std::function<bool()>& done, double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (done()) return true;
    }
    ros::WallDuration(0.02).sleep();
  }
  return false;
}

/// Subscribes to /diagnostics and copies, under `mutex`, the key/value pairs of every status whose
/// name contains each of `name_parts` into `values` (the latest report wins).
inline ros::Subscriber subscribeDiagnostics(ros::NodeHandle& nh,
                                            const std::vector<std::string>& name_parts,
                                            std::mutex& mutex,
                                            std::map<std::string, std::string>& values) {
  return nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 20,
      [name_parts, &mutex, &values](const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& status : msg->status) {
          bool named = true;
          for (const std::string& part : name_parts)
            named = named && status.name.find(part) != std::string::npos;
          if (!named) continue;
          for (const auto& kv : status.values)
            values[kv.key] = kv.value;
        }
      });
}

/// main() of a gtest-in-rostest: initialises gtest and ROS as `node_name`, and runs `run` (all the
/// tests by default) while an AsyncSpinner of `spinner_threads` serves the subscriptions.
inline int runWithSpinner(
    int argc, char** argv, const char* node_name, int spinner_threads,
    const std::function<int()>& run = [] { return RUN_ALL_TESTS(); }) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::AsyncSpinner spinner(spinner_threads);
  spinner.start();
  const int result = run();
  spinner.stop();
  ros::shutdown();
  return result;
}

}  // namespace rostest_helpers
