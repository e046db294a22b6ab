/// \file pmrac_manager.cpp
/// \brief main() of pmrac_manager: a nodelet manager (like `nodelet manager`) whose exit code
/// is the one a required nodelet of this package asked for (NodeContext::end): 2 when a
/// nodelet refused its parameters, 3 on a run-time failure, 0 at a normal end. So a launch
/// file that requires the manager ends, and scripts/lib/launch_checked tells why.

#include <nodelet/loader.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "preadaptive_mrac/ros/node_context.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "pmrac_manager");
  namespace pm = preadaptive_mrac::ros1;
  pm::deferProcessShutdown();
  {
    // Services ~load_nodelet, ~unload_nodelet, ~list; ~num_worker_threads worker threads.
    nodelet::Loader loader;
    // ros::spin() until a nodelet ends the process (or SIGINT).
    ros::CallbackQueue* queue = ros::getGlobalCallbackQueue();
    while (ros::ok() && !pm::processExitRequested()) queue->callAvailable(ros::WallDuration(0.1));
    // Unload every nodelet now (the recorder closes its bag, the controller saves its weights),
    // with ROS still up so that their bonds can say goodbye (pm::deferProcessShutdown): left to
    // ~Loader, the bonds of loaders that are already gone unload them again after the loader's
    // callback queues are destroyed (boost::lock_error, SIGABRT).
    loader.clear();
  }
  ros::shutdown();
  return pm::processExitCode();
}
