# ROS messages. Included before catkin_package().
add_message_files(
  DIRECTORY msg
  FILES
    PlantState.msg
    PlantTruth.msg
    ElevatorCommand.msg
    AttentionEvent.msg
    AdaptationStatus.msg
    RecorderProgress.msg
    RecorderConnections.msg
    ParamChange.msg)
generate_messages(DEPENDENCIES std_msgs)

# dynamic_reconfigure of the controller: cfg/ControllerTuning.cfg generates
# preadaptive_mrac/ControllerTuningConfig.h (and the Python module) for src/ros/controller_reconfigure.cpp.
generate_dynamic_reconfigure_options(cfg/ControllerTuning.cfg)
# The .cfg reads its parameters from params/controller.yaml and its parts' tables (robust):
# a changed table regenerates the config.
add_custom_command(OUTPUT ${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_INCLUDE_DESTINATION}/${PROJECT_NAME}/ControllerTuningConfig.h
  APPEND DEPENDS ${PROJECT_SOURCE_DIR}/params/controller.yaml ${PROJECT_SOURCE_DIR}/params/robust.yaml
  ${PROJECT_SOURCE_DIR}/src/preadaptive_mrac/params_table.py)
