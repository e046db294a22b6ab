# ROS tests: included from the end of cmake/tests.cmake.
# Two tiers: gtest without a master for the ROS-free glue, rostest for whole-node behaviour.
# rostest runs one master per test on the same port, so `make run_tests` runs them one by one.
if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)

  # Parameter readers of the nodes and the latency statistics: no master.
  catkin_add_gtest(test_ros_node_params test/ros/test_node_params.cpp)
  target_link_libraries(test_ros_node_params preadaptive_mrac_ros_params gtest_main)
  target_compile_definitions(test_ros_node_params PRIVATE
    PMRAC_CONFIG_DIR="${CMAKE_CURRENT_SOURCE_DIR}/config"
    PMRAC_PARAMS_DIR="${CMAKE_CURRENT_SOURCE_DIR}/params"
    PMRAC_JSBSIM_ROOT="${CMAKE_CURRENT_SOURCE_DIR}/jsbsim")
  # ~accept_from's matching: which caller ids pass, drops counted and warned once.
  catkin_add_gtest(test_ros_publisher_guard test/ros/test_publisher_guard.cpp)
  target_link_libraries(test_ros_publisher_guard preadaptive_mrac_ros_params gtest_main)
  # The controller's InlineCallbackQueue: messages run in the delivering thread, one callback
  # at a time, timers and waiting ones on the queue's thread, in order.
  catkin_add_gtest(test_ros_inline_queue test/ros/test_inline_queue.cpp)
  target_link_libraries(test_ros_inline_queue preadaptive_mrac_ros gtest_main)
  # Configuration on the nodes' side: parameter-server numbers read as the CLI reads them, and
  # the controller's baseline answer to a non-finite state.
  catkin_add_gtest(test_ros_config test/ros/test_ros_config.cpp)
  target_link_libraries(test_ros_config preadaptive_mrac_ros gtest_main)
  # BagWriter: the same file as rosbag::Bag writes for the same calls, byte for byte.
  catkin_add_gtest(test_ros_bag_writer test/ros/test_bag_writer.cpp)
  target_link_libraries(test_ros_bag_writer preadaptive_mrac_ros gtest_main)

  # Lockstep against the batch CLI, one registration per mode and shape (same .test, args):
  # the paper's modes, pa_robust (its DECISION events and verification fields) and the oracle
  # yardstick (like pa_learn_exact, it needs plant/truth), and l1 (docs/research/l1.md).
  add_executable(test_ros_lockstep test/ros/lockstep_equivalence_test.cpp)
  target_link_libraries(test_ros_lockstep preadaptive_mrac_ros ${GTEST_LIBRARIES} yaml-cpp)
  target_include_directories(test_ros_lockstep SYSTEM PRIVATE ${GTEST_INCLUDE_DIRS})
  target_compile_definitions(test_ros_lockstep PRIVATE PMRAC_SIM_BIN="$<TARGET_FILE:preadapt_sim>")
  set_target_properties(test_ros_lockstep PROPERTIES
    RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})
  add_dependencies(test_ros_lockstep preadapt_sim plant_sim_node mrac_controller_node)
  if(TARGET tests)
    add_dependencies(tests test_ros_lockstep)
  endif()
  # Both shapes: plant and controller as nodelets in one pmrac_manager, and as processes.
  foreach(shape nodelet process)
    foreach(mode rac pa_learn pa_learn_exact pa_robust oracle l1)
      add_rostest(test/ros/lockstep.test ARGS mode:=${mode} shape:=${shape}
        DEPENDENCIES test_ros_lockstep plant_sim_node mrac_controller_node pmrac_manager
                     preadaptive_mrac_nodelets preadapt_sim)
    endforeach()
  endforeach()
  # Plant loop and controller thread pinned to one CPU (~cpu_affinity): the same run.
  add_rostest(test/ros/lockstep.test ARGS mode:=pa_learn shape:=nodelet cpu_affinity:=0 name_suffix:=_cpu0
    DEPENDENCIES test_ros_lockstep plant_sim_node mrac_controller_node pmrac_manager
                 preadaptive_mrac_nodelets preadapt_sim)
  # The plant with servo delay, lag and Dryden turbulence, in both shapes (pa_robust
  # identifies the plant from the applied elevator): still the CLI's run, and the applied
  # elevator, the command and the gust published equal the CLI's CSV columns.
  foreach(shape nodelet process)
    add_rostest(test/ros/lockstep.test ARGS mode:=pa_robust shape:=${shape} name_suffix:=_conditions
      test_plant:=conditions
      DEPENDENCIES test_ros_lockstep plant_sim_node mrac_controller_node pmrac_manager
                   preadaptive_mrac_nodelets preadapt_sim)
  endforeach()

  # A plant whose envelope scenario 1 leaves (max_alpha 0.05 rad): the truth says the
  # CLI's exit (bound, time) from the sample after it; the run goes on, still the CLI's run.
  add_rostest(test/ros/lockstep.test ARGS mode:=rac shape:=nodelet name_suffix:=_envelope
    test_plant:=envelope
    DEPENDENCIES test_ros_lockstep plant_sim_node mrac_controller_node pmrac_manager
                 preadaptive_mrac_nodelets preadapt_sim)
  # JSBSim as the plant engine, in the plant node too: a 6 s scenario in lockstep
  # equals the batch CLI's run on JSBSim bit for bit (one process each: the plant node forks
  # its JSBSim, preadapt_sim its own).
  # In both shapes: in the nodelet shape the plant nodelet's JSBSim is forked from a thread
  # that lives as long as the manager (PR_SET_PDEATHSIG follows the forking thread). The truth's
  # flight outputs (pitch, airspeed, altitude, flight_path) equal the CSV's columns.
  foreach(shape process nodelet)
    add_rostest(test/ros/lockstep.test ARGS mode:=rac shape:=${shape} name_suffix:=_jsbsim
      test_plant:=jsbsim
      test_scenario:=jsbsim
      DEPENDENCIES test_ros_lockstep plant_sim_node mrac_controller_node pmrac_manager
                   preadaptive_mrac_nodelets preadapt_sim)
  endforeach()
  # JSBSim on the realtime clock (process shape; recorded whole, no JSBSim left after the run),
  # and killed mid-run in lockstep (nodelet shape: the run ends with an ERROR naming it, the bag
  # .incomplete.bag, no JSBSim left).
  add_rostest(test/ros/jsbsim.test ARGS case:=realtime shape:=process
    DEPENDENCIES plant_sim_node mrac_controller_node bag_recorder_node)
  add_rostest(test/ros/jsbsim.test ARGS case:=killed shape:=nodelet
    DEPENDENCIES plant_sim_node mrac_controller_node bag_recorder_node pmrac_manager
                 preadaptive_mrac_nodelets)

  # Broken parameters: nodes exit non-zero naming the key and never publish a command.
  add_rostest(test/ros/broken_config.test
    DEPENDENCIES plant_sim_node mrac_controller_node)

  # Realtime (wall clock, 1 kHz): no state lost, every state answered once and in order
  # (behaviour, not speed: rates and latencies are the benchmarks' business).
  add_rostest(test/ros/realtime_answers.test
    DEPENDENCIES plant_sim_node mrac_controller_node)
  # The end of a realtime run is not a fault (no stale commands after the last state).
  add_rostest(test/ros/realtime_end.test
    DEPENDENCIES plant_sim_node mrac_controller_node)
  # A run that loses the aircraft says so, and ends at a non-finite state.
  foreach(clock realtime lockstep)
    add_rostest(test/ros/envelope.test ARGS clock:=${clock}
      DEPENDENCIES plant_sim_node mrac_controller_node)
  endforeach()

  # Reliability (wall clock). The controller alone, fed by the test: NaN states are
  # answered safely and do not refresh the staleness timer; silence gives stale safe commands
  # (-K x_last or 0) at the sample rate; /diagnostics reports rejections and staleness.
  foreach(policy baseline_hold zero)
    add_rostest(test/ros/stale_input.test ARGS policy:=${policy}
      DEPENDENCIES mrac_controller_node)
  endforeach()
  # The plant alone, commanded by the test: NaN/Inf commands rejected and counted, trim after
  # ~cmd_timeout without a valid command, the measured (noisy) state and applied elevator.
  add_rostest(test/ros/plant_command.test DEPENDENCIES plant_sim_node)
  # The recorder killed with SIGKILL mid-recording (split series): scripts/reindex_bags
  # recovers the .bag.active it leaves; the bags hold every state up to near the kill.
  add_rostest(test/ros/recorder_crash.test DEPENDENCIES bag_recorder_node)
  # The recorder's ~accept_from: a stray node's states on a recorded topic never reach the bag.
  add_rostest(test/ros/recorder_guard.test DEPENDENCIES bag_recorder_node)
  # A lockstep plant's re-sent states are recorded once.
  add_rostest(test/ros/recorder_repeats.test DEPENDENCIES plant_sim_node bag_recorder_node)
  # Controller and plant SIGKILLed and restarted mid-run (realtime): trim, stale safe commands,
  # recovery, the controller resumes from its saved weights, the run completes.
  add_rostest(test/ros/faults.test DEPENDENCIES plant_sim_node mrac_controller_node)
  # c_ed changed mid-run (lockstep) through the dynamic_reconfigure client, an invalid
  # value refused naming the key; the bag holds the change stamped with its step and equals
  # the CLI run with the new c_ed bit for bit.
  add_rostest(test/ros/reconfigure.test
    DEPENDENCIES plant_sim_node mrac_controller_node bag_recorder_node preadapt_sim)
  # The same in lockstep: the plant restarted from step 0; the controller killed after a
  # learning episode, the plant waiting (repeating its state) until the restarted controller
  # answers; the run completes with every step answered.
  add_rostest(test/ros/faults_lockstep.test DEPENDENCIES plant_sim_node mrac_controller_node)
  # ~accept_from: stray nodes publishing commands and states into the guarded loop
  # (realtime) are dropped, counted on /diagnostics and warned about once; the loop runs on.
  foreach(shape nodelet process)
    add_rostest(test/ros/stray_publisher.test ARGS shape:=${shape}
      DEPENDENCIES plant_sim_node mrac_controller_node pmrac_manager preadaptive_mrac_nodelets)
  endforeach()
endif()
