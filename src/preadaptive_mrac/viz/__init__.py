"""rviz helpers of preadaptive_mrac (need rospy and the ROS message modules)."""
