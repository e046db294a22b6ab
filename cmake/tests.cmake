# Tests: gtest for the core (no ROS master), rostest for the nodes (cmake/tests_ros.cmake).
if(CATKIN_ENABLE_TESTING)
  set(PMRAC_CORE_TESTS solvers attention gradients closed_loop weights_io config safety family
      tunables)
  foreach(name ${PMRAC_CORE_TESTS})
    catkin_add_gtest(test_${name} test/core/test_${name}.cpp)
    target_link_libraries(test_${name} preadaptive_mrac_io gtest_main)
    target_include_directories(test_${name} PRIVATE test/core)
  endforeach()
  # The CLI test runs the real executable.
  add_dependencies(test_config preadapt_sim)
  target_compile_definitions(test_config PRIVATE
    PMRAC_SIM_BIN="$<TARGET_FILE:preadapt_sim>")
endif()

include(cmake/tests_ros.cmake)  # ROS node tests (issue 3)
if(CATKIN_ENABLE_TESTING)
  add_dependencies(test_family preadapt_family)
  target_compile_definitions(test_family PRIVATE PMRAC_FAMILY_BIN="$<TARGET_FILE:preadapt_family>")
endif()
