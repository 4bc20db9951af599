#pragma once
// Knots of the estimated trajectory as ROS messages: nav_msgs/Odometry (pose and body-frame twist),
// geometry_msgs/PoseStamped and the TF transform world -> camera. The pose is T_w_c (camera-to-world) and
// the twist the body-frame velocity [v; w] (DESIGN.md §3), which is what Odometry's twist in child_frame_id
// means.

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/time.h>

#include <cstdint>
#include <string>

#include "asynevo/backend/trajectory.hpp"

namespace asynevo::ros_node {

/// Nanoseconds (non-negative, as ROS time is) to ros::Time.
ros::Time rosTime(int64_t t_ns);

geometry_msgs::PoseStamped poseMessage(const backend::Knot& knot, const std::string& world_frame);
nav_msgs::Odometry odometryMessage(const backend::Knot& knot, const std::string& world_frame,
                                   const std::string& camera_frame);
geometry_msgs::TransformStamped transformMessage(const backend::Knot& knot, const std::string& world_frame,
                                                 const std::string& camera_frame);

}  // namespace asynevo::ros_node
