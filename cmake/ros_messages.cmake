# ROS messages: owned by the ROS-nodes work (issue 3). Included before catkin_package().
add_message_files(
  DIRECTORY msg
  FILES
    PlantState.msg
    PlantTruth.msg
    ElevatorCommand.msg
    AttentionEvent.msg
    AdaptationStatus.msg
    RecorderProgress.msg)
generate_messages(DEPENDENCIES std_msgs)
