#pragma once
// The main() of a standalone node: one nodelet class in its own process, with the node's name,
// namespace, remappings and private parameters.
#include <nodelet/loader.h>
#include <ros/ros.h>

#include <string>

#include "multimodal_nvs/core/common/retain_freed_memory.hpp"

namespace multimodal_nvs {

/// Initialises ROS as `default_name` (a remapped __name wins), loads `nodelet_type` (found through
/// pluginlib at run time) and spins; returns main()'s exit code.
inline int runStandaloneNodelet(int argc, char** argv, const char* default_name,
                                const std::string& nodelet_type) {
  // This process hosts only our nodelet, so the process-wide allocator setting is ours to make:
  // every message (a 1936x1216 RGB image is 7 MB) is deserialised into a fresh buffer, which
  // glibc would otherwise mmap and page-fault in again for each message. Before ROS starts threads.
  retainFreedMemory();
  ros::init(argc, argv, default_name);
  nodelet::Loader loader(false);  // no manager services: this process hosts exactly one nodelet
  const nodelet::M_string remappings = ros::names::getRemappings();
  const nodelet::V_string nodelet_argv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), nodelet_type, remappings, nodelet_argv)) {
    ROS_FATAL("could not load the %s nodelet", nodelet_type.c_str());
    return 1;
  }
  ros::spin();
  return 0;
}

}  // namespace multimodal_nvs
