// Standalone node running the multimodal_nvs/ConditioningRenderer nodelet class in its own
// process, with the node's name, namespace, remappings and private parameters.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "conditioning_renderer");
  nodelet::Loader loader(false);  // no manager services: this process hosts exactly one nodelet
  const nodelet::M_string remappings = ros::names::getRemappings();
  const nodelet::V_string nodelet_argv(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "multimodal_nvs/ConditioningRenderer", remappings,
                   nodelet_argv)) {
    ROS_FATAL("could not load the multimodal_nvs/ConditioningRenderer nodelet");
    return 1;
  }
  ros::spin();
  return 0;
}
