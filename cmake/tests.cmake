# Tests: gtest for the core (no ROS master), rostest for the nodes (cmake/tests_ros.cmake).
if(CATKIN_ENABLE_TESTING)
  # Each unit test in the folder of the part it tests, as the part is in src/: test/core/sim/
  # for src/core/sim/, ..., test/io/ for src/io/; the top of test/core/ holds the core's top
  # (solvers, closed loop, margins, step sequencer) and the whole-run tests (configuration and
  # CLI, safety options, fast paths, a second aircraft). One entry: <folder>/<name> makes
  # test_<name> from test/<folder>/test_<name>.cpp.
  set(PMRAC_CORE_TESTS
      core/solvers core/closed_loop core/margins core/step_sequencer core/config core/safety
      core/fast_paths core/own_aircraft core/schema/param_table
      core/sim/plant_parts core/sim/plant_engine core/sim/family
      core/control/attention
      core/robust/robust core/robust/robust_parts core/robust/switch_detection
      core/controller/tunables core/controller/saturation
      io/weights_io)
  # A law's or a strategy's tests, in its folder below test/core/control/: found, not listed
  # (as its sources are, cmake/core.cmake), so a new part adds no line here.
  file(GLOB _pmrac_part_tests CONFIGURE_DEPENDS RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}/test
       ${CMAKE_CURRENT_SOURCE_DIR}/test/core/control/*/test_*.cpp)
  foreach(f ${_pmrac_part_tests})
    string(REGEX REPLACE "/test_([^/]*)\\.cpp$" "/\\1" entry ${f})
    list(APPEND PMRAC_CORE_TESTS ${entry})
  endforeach()
  foreach(entry ${PMRAC_CORE_TESTS})
    get_filename_component(name ${entry} NAME)
    get_filename_component(folder ${entry} DIRECTORY)
    catkin_add_gtest(test_${name} test/${folder}/test_${name}.cpp)
    target_link_libraries(test_${name} preadaptive_mrac_io gtest_main)
    target_include_directories(test_${name} PRIVATE test/core)
  endforeach()
  # The JSBSim engine's own tests (the core's above build and pass without it).
  catkin_add_gtest(test_jsbsim test/jsbsim/test_jsbsim.cpp)
  target_link_libraries(test_jsbsim preadaptive_mrac_io preadaptive_mrac_jsbsim gtest_main)
  target_include_directories(test_jsbsim PRIVATE test/core)
  catkin_add_gtest(test_jsbsim_lane test/jsbsim/test_jsbsim_lane.cpp)
  target_link_libraries(test_jsbsim_lane preadaptive_mrac_jsbsim gtest_main)
  catkin_add_gtest(test_jsbsim_overlay test/jsbsim/test_jsbsim_overlay.cpp)
  target_link_libraries(test_jsbsim_overlay preadaptive_mrac_io preadaptive_mrac_jsbsim gtest_main)
  target_compile_definitions(test_param_table PRIVATE
    PMRAC_PARAMS_DIR="${CMAKE_CURRENT_SOURCE_DIR}/params")
  # The CLI test runs the real executable.
  add_dependencies(test_config preadapt_sim preadapt_sweep)
  target_compile_definitions(test_config PRIVATE
    PMRAC_SIM_BIN="$<TARGET_FILE:preadapt_sim>" PMRAC_SWEEP_BIN="$<TARGET_FILE:preadapt_sweep>")
endif()

include(cmake/tests_ros.cmake)  # ROS node tests
if(CATKIN_ENABLE_TESTING)
  add_dependencies(test_family preadapt_family)
  target_compile_definitions(test_family PRIVATE PMRAC_FAMILY_BIN="$<TARGET_FILE:preadapt_family>")
endif()

# Python unit tests of the package under src/preadaptive_mrac (test/python/test_<module>.py, no
# master, no build products): unittest, one JUnit file through scripts/junit_wrap, so both
# `make run_tests` and scripts/test count them.
if(CATKIN_ENABLE_TESTING)
  set(_pmrac_py_xml ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/python-unittest.xml)
  # One string: run_tests.py runs each COMMAND word as a command of its own.
  catkin_run_tests_target("python" "unittest" "python-unittest.xml"
    COMMAND "${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/scripts/junit_wrap python_unittest ${_pmrac_py_xml} -- ${PYTHON_EXECUTABLE} -m unittest discover -s ${PROJECT_SOURCE_DIR}/test/python -t ${PROJECT_SOURCE_DIR}/test/python -p 'test_*.py' -v")
endif()
