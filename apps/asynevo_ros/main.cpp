// asynevo_ros_node: AsynEVO as a ROS1 node (docs/guide/ros.md). Parameters are read from the private
// namespace; the AsynEVO configuration is the YAML file of `asynevo run --config` (~config).
// On SIGINT/SIGTERM the node processes what it has queued, makes the estimator's last solve, publishes the
// remaining final knots and exits; a shutdown requested through ROS (rosnode kill) stops it the same way.

#include <ros/ros.h>

#include <atomic>
#include <csignal>
#include <exception>

#include "asynevo/core/error.hpp"
#include "node_options.hpp"
#include "odometry_node.hpp"

namespace {

// Set by the signal handler, read by main's loop: the one piece of process-wide state a handler can touch.
volatile std::sig_atomic_t g_stop_requested = 0;

void requestStop(int) { g_stop_requested = 1; }

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "asynevo", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  try {
    asynevo::ros_node::OdometryNode node(nh, private_nh, asynevo::ros_node::readNodeOptions(private_nh));
    ros::AsyncSpinner spinner(1);
    spinner.start();
    while (ros::ok() && g_stop_requested == 0) ros::WallDuration(0.05).sleep();
    spinner.stop();  // no callback runs while the node finishes
    node.finish();
    ros::WallDuration(0.5).sleep();  // let the last messages leave before the connections close
  } catch (const asynevo::Error& e) {
    ROS_FATAL("asynevo: %s", e.what());
    ros::shutdown();
    return 2;
  } catch (const std::exception& e) {
    ROS_FATAL("asynevo: unexpected error: %s", e.what());
    ros::shutdown();
    return 1;
  }
  ros::shutdown();
  return 0;
}
