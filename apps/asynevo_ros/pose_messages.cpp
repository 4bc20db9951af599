#include "pose_messages.hpp"

namespace asynevo::ros_node {

ros::Time rosTime(int64_t t_ns) {
  ros::Time t;
  t.sec = static_cast<uint32_t>(t_ns / 1000000000);
  t.nsec = static_cast<uint32_t>(t_ns % 1000000000);
  return t;
}

namespace {

// Knot::pose is [t_x t_y t_z q_x q_y q_z q_w].
void fillPose(const backend::Knot& k, geometry_msgs::Pose& pose) {
  pose.position.x = k.pose[0];
  pose.position.y = k.pose[1];
  pose.position.z = k.pose[2];
  pose.orientation.x = k.pose[3];
  pose.orientation.y = k.pose[4];
  pose.orientation.z = k.pose[5];
  pose.orientation.w = k.pose[6];
}

}  // namespace

geometry_msgs::PoseStamped poseMessage(const backend::Knot& knot, const std::string& world_frame) {
  geometry_msgs::PoseStamped m;
  m.header.stamp = rosTime(knot.t_ns);
  m.header.frame_id = world_frame;
  fillPose(knot, m.pose);
  return m;
}

nav_msgs::Odometry odometryMessage(const backend::Knot& knot, const std::string& world_frame,
                                   const std::string& camera_frame) {
  nav_msgs::Odometry m;
  m.header.stamp = rosTime(knot.t_ns);
  m.header.frame_id = world_frame;
  m.child_frame_id = camera_frame;
  fillPose(knot, m.pose.pose);
  // Knot::velocity is [v; w] in the body (camera) frame, as Odometry's twist in child_frame_id.
  m.twist.twist.linear.x = knot.velocity[0];
  m.twist.twist.linear.y = knot.velocity[1];
  m.twist.twist.linear.z = knot.velocity[2];
  m.twist.twist.angular.x = knot.velocity[3];
  m.twist.twist.angular.y = knot.velocity[4];
  m.twist.twist.angular.z = knot.velocity[5];
  // The covariances stay zero: the estimator does not publish its uncertainty (docs/guide/ros.md#limits).
  return m;
}

geometry_msgs::TransformStamped transformMessage(const backend::Knot& knot, const std::string& world_frame,
                                                 const std::string& camera_frame) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = rosTime(knot.t_ns);
  m.header.frame_id = world_frame;
  m.child_frame_id = camera_frame;
  m.transform.translation.x = knot.pose[0];
  m.transform.translation.y = knot.pose[1];
  m.transform.translation.z = knot.pose[2];
  m.transform.rotation.x = knot.pose[3];
  m.transform.rotation.y = knot.pose[4];
  m.transform.rotation.z = knot.pose[5];
  m.transform.rotation.w = knot.pose[6];
  return m;
}

}  // namespace asynevo::ros_node
