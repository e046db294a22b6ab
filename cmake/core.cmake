# The core: Eigen + STL only. Nothing here may include a ROS header.
add_library(preadaptive_mrac_core
  src/core/params.cpp
  src/core/solvers.cpp
  src/core/plant.cpp
  src/core/scenario.cpp
  src/core/network.cpp
  src/core/controller.cpp
  src/core/paper_preadaptation.cpp
  src/core/oracle_preadaptation.cpp
  src/core/robust_preadaptation.cpp
  src/core/regime_memory.cpp
  src/core/closed_loop.cpp
  src/core/scenario_family.cpp
  src/core/input_guard.cpp
  src/core/tunables.cpp)
target_include_directories(preadaptive_mrac_core PUBLIC
  $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> ${EIGEN3_INCLUDE_DIRS})
set_target_properties(preadaptive_mrac_core PROPERTIES POSITION_INDEPENDENT_CODE ON)

# io: YAML files, weights files, run set-up and JSON/CSV output (yaml-cpp, no ROS).
add_library(preadaptive_mrac_io
  src/io/yaml_params.cpp
  src/io/weights_io.cpp
  src/io/setup.cpp)
target_link_libraries(preadaptive_mrac_io PUBLIC preadaptive_mrac_core yaml-cpp)
target_compile_definitions(preadaptive_mrac_io PRIVATE
  PREADAPTIVE_MRAC_CONFIG_DIR="${CMAKE_CURRENT_SOURCE_DIR}/config")
set_target_properties(preadaptive_mrac_io PROPERTIES POSITION_INDEPENDENT_CODE ON)

# Batch tools: no ROS master needed.
add_library(preadaptive_mrac_cli src/tools/cli_common.cpp)
target_link_libraries(preadaptive_mrac_cli PUBLIC preadaptive_mrac_io Threads::Threads)
find_package(Threads REQUIRED)

add_executable(preadapt_sim src/tools/preadapt_sim.cpp)
target_link_libraries(preadapt_sim preadaptive_mrac_cli)
add_executable(preadapt_sweep src/tools/preadapt_sweep.cpp)
target_link_libraries(preadapt_sweep preadaptive_mrac_cli)
add_executable(preadapt_family src/tools/preadapt_family.cpp)
target_link_libraries(preadapt_family preadaptive_mrac_cli)
set_target_properties(preadapt_sim preadapt_sweep preadapt_family PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION})

install(TARGETS preadaptive_mrac_core preadaptive_mrac_io preadaptive_mrac_cli
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(TARGETS preadapt_sim preadapt_sweep preadapt_family RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY include/ DESTINATION ${CATKIN_GLOBAL_INCLUDE_DESTINATION})
install(DIRECTORY config launch rviz DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}
  OPTIONAL)

# Python tools (run with the system python3 that has the ROS modules): thin entry points; the
# code is the Python package src/preadaptive_mrac (catkin_python_setup() in CMakeLists.txt).
catkin_install_python(PROGRAMS scripts/analyze_bag scripts/viz_markers
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
