# Benchmarks (Google Benchmark). Built only when the library is found (Debian: libbenchmark-dev),
# so the package builds without it. Never registered as a test: bench/run_bench.sh runs it and
# writes docs/performance.md.
option(PREADAPTIVE_MRAC_BUILD_BENCH "Build the Google Benchmark executable when available" ON)
if(PREADAPTIVE_MRAC_BUILD_BENCH)
  find_package(benchmark QUIET)
  if(benchmark_FOUND)
    add_executable(bench_controller bench/bench_controller.cpp)
    target_link_libraries(bench_controller preadaptive_mrac_io benchmark::benchmark)
    set_target_properties(bench_controller PROPERTIES
      RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})
  else()
    message(STATUS "Google Benchmark not found (apt-get install libbenchmark-dev): "
                   "bench_controller is not built")
  endif()
endif()

# The machine's floor for a 1 kHz loop: timer wake-up lateness and CPU taken from a spinning
# thread, one thread, no ROS. bench/ros_bench.sh prints it beside the realtime runs.
add_executable(wakeup_floor bench/wakeup_floor.cpp)
set_target_properties(wakeup_floor PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})

# The plant engines' per-step cost: linear RK4 against the JSBSim coupling, and the
# socket round trips under it. Needs JSBSim at run time (scripts/install_jsbsim), not to build.
add_executable(bench_jsbsim bench/bench_jsbsim.cpp)
target_link_libraries(bench_jsbsim preadaptive_mrac_io preadaptive_mrac_jsbsim)
set_target_properties(bench_jsbsim PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})

# The recorder's writing alone (no ROS communication): rosbag::Bag against BagWriter on a
# lockstep run's messages (docs/performance.md).
add_executable(bench_bag_writer bench/bench_bag_writer.cpp)
target_link_libraries(bench_bag_writer preadaptive_mrac_ros)
set_target_properties(bench_bag_writer PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})
