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
  ros::Publisher points_pub = nh.advertise<sensor_msgs::PointCloud2>("points", 2);
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>("image", 2);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>("camera_info", 2);
  // Built once: only the stamps change from frame to frame.
  sensor_msgs::PointCloud2 cloud = synthetic_scene::cloud(ros::Time(0));
  sensor_msgs::Image image = synthetic_scene::image(ros::Time(0));
  sensor_msgs::CameraInfo info = synthetic_scene::cameraInfo(ros::Time(0));
  ros::Rate rate(rate_hz);
  while (ros::ok()) {
    const ros::Time stamp = ros::Time::now();
    cloud.header.stamp = image.header.stamp = info.header.stamp = stamp;
    points_pub.publish(cloud);
    image_pub.publish(image);
    info_pub.publish(info);
    ros::spinOnce();
    rate.sleep();
  }
  return 0;
}
