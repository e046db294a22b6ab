# ROS nodes. Included after catkin_package().
# The node classes live in a library (so rostest gtests can reuse them); each node file
# holds only main().

# ROS-free parts of the glue (parameter reading, the publisher guard, latency statistics):
# tested without a master. Parameter reading reads a JSBSim aircraft's elevator
# (~elevator_from_aircraft), so it uses the JSBSim engine's library.
add_library(preadaptive_mrac_ros_params
  src/ros/node_params.cpp
  src/ros/publisher_guard.cpp
  src/ros/latency_stats.cpp
  src/ros/tick_source.cpp)
target_link_libraries(preadaptive_mrac_ros_params PUBLIC preadaptive_mrac_io preadaptive_mrac_jsbsim)
# node_params reads the struct generated from params/nodes.yaml (cmake/params.cmake)
add_dependencies(preadaptive_mrac_ros_params pmrac_params_headers)

# ROS headers for everything from here on (the core and io libraries above have none). The
# generated message and dynamic_reconfigure headers (devel include/) are on the path already:
# generate_messages() and generate_dynamic_reconfigure_options() add them.
include_directories(SYSTEM ${catkin_INCLUDE_DIRS})
add_library(preadaptive_mrac_ros
  src/ros/ros_params.cpp
  src/ros/node_context.cpp
  src/ros/inline_queue.cpp
  src/ros/plant_sim_node.cpp
  src/ros/lockstep_clock.cpp
  src/ros/realtime_clock.cpp
  src/ros/node_status.cpp
  src/ros/mrac_controller_node.cpp
  src/ros/attention_msg.cpp
  src/ros/run_monitor.cpp
  src/ros/bag_recorder.cpp
  src/ros/bag_writer.cpp
  src/ros/controller_reconfigure.cpp)
target_link_libraries(preadaptive_mrac_ros PUBLIC preadaptive_mrac_ros_params ${catkin_LIBRARIES})
pmrac_link_engines(preadaptive_mrac_ros SHARED)
add_dependencies(preadaptive_mrac_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)

add_executable(plant_sim_node src/nodes/plant_sim_node.cpp)
target_link_libraries(plant_sim_node preadaptive_mrac_ros)
add_executable(mrac_controller_node src/nodes/mrac_controller_node.cpp)
target_link_libraries(mrac_controller_node preadaptive_mrac_ros)
add_executable(run_monitor_node src/nodes/run_monitor_node.cpp)
target_link_libraries(run_monitor_node preadaptive_mrac_ros)
add_executable(bag_recorder_node src/nodes/bag_recorder_node.cpp)
target_link_libraries(bag_recorder_node preadaptive_mrac_ros)
set_target_properties(plant_sim_node mrac_controller_node run_monitor_node bag_recorder_node
  PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})

# The same classes as nodelets (nodelet_plugins.xml, exported in package.xml), and a manager
# that returns the exit code a required nodelet asked for.
add_library(preadaptive_mrac_nodelets SHARED src/ros/nodelets.cpp)
target_link_libraries(preadaptive_mrac_nodelets PUBLIC preadaptive_mrac_ros)
add_executable(pmrac_manager src/nodes/pmrac_manager.cpp)
target_link_libraries(pmrac_manager preadaptive_mrac_ros)
set_target_properties(pmrac_manager PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})


# LD_PRELOAD shim that keeps roscpp's XML-RPC server (which binds 0.0.0.0 whatever
# ROS_IP says) on loopback in single-machine runs; preloaded by scripts/lib/ros_env.
add_library(pmrac_loopback_bind SHARED src/loopback/loopback_bind.cpp)
target_link_libraries(pmrac_loopback_bind ${CMAKE_DL_LIBS})
set_target_properties(pmrac_loopback_bind PROPERTIES
  LIBRARY_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_LIB_DESTINATION})
