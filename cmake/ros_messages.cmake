# ROS messages: owned by the ROS-nodes work (issue 3). Included before catkin_package().
add_message_files(
  DIRECTORY msg
  FILES
    PlantState.msg
    PlantTruth.msg
    ElevatorCommand.msg
    AttentionEvent.msg
    AdaptationStatus.msg
    RecorderProgress.msg
    ParamChange.msg)
generate_messages(DEPENDENCIES std_msgs)

# dynamic_reconfigure of the controller (issue 11): cfg/ControllerTuning.cfg generates
# preadaptive_mrac/ControllerTuningConfig.h (and the Python module) for src/ros/controller_reconfigure.cpp.
generate_dynamic_reconfigure_options(cfg/ControllerTuning.cfg)
