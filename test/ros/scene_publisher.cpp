// Publishes the synthetic scene (points, image, camera_info with equal stamps, extrinsic on
// /tf_static) at ~rate Hz: the input side of the hztest rostests.
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "synthetic_scene.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "scene_publisher");
  ros::NodeHandle nh, pnh("~");
  const double rate_hz = pnh.param("rate", 10.0);
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(synthetic_scene::sensorToCameraMsg(ros::Time(0)));
  const synthetic_scene::InputPublishers inputs(nh, 2);
  // Built once: only the stamps change from frame to frame.
  synthetic_scene::InputSet set = synthetic_scene::inputSet(ros::Time(0));
  ros::Rate rate(rate_hz);
  while (ros::ok()) {
    const ros::Time stamp = ros::Time::now();
    set.cloud.header.stamp = set.image.header.stamp = set.info.header.stamp = stamp;
    inputs.publish(set);
    ros::spinOnce();
    rate.sleep();
  }
  return 0;
}
