# Each library is compiled once, as position-independent objects, and linked twice: as the
# shared library the nodes, nodelets and tests use, and as a static archive for the batch tools
# (a tool then starts without loading and relocating three more shared libraries: about 0.4 ms
# of a 5 ms preadapt_sim run, docs/performance.md). With PMRAC_STATIC_TOOLS (the default) and
# a static yaml-cpp (Debian's libyaml-cpp-dev ships libyaml-cpp.a) the batch tools are linked
# fully static: no dynamic loader, libstdc++ or yaml-cpp relocations at start-up (6.9 -> 5.0 ms
# per preadapt_sim scenario 1 run, hyperfine, docs/performance.md).
macro(pmrac_library name)
  add_library(${name}_objects OBJECT ${ARGN})
  set_target_properties(${name}_objects PROPERTIES POSITION_INDEPENDENT_CODE ON)
  add_library(${name} $<TARGET_OBJECTS:${name}_objects>)
  add_library(${name}_static STATIC $<TARGET_OBJECTS:${name}_objects>)
  foreach(t ${name}_objects ${name} ${name}_static)
    # the devel space's include folder: the structs generated from params/ (cmake/params.cmake)
    #catkin_lint: ignore_once external_directory
    target_include_directories(${t} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
                               $<BUILD_INTERFACE:${PMRAC_GENERATED_INCLUDE}>)
    target_link_libraries(${t} PUBLIC Eigen3::Eigen)
  endforeach()
  add_dependencies(${name}_objects pmrac_params_headers)
endmacro()

# The laws and strategies, each in its folder below src/core/control/: found, not listed, so a
# new part is its folder only (docs/design.md "A new adaptive law"); CONFIGURE_DEPENDS makes
# the build notice a new file. After the rest of the core, so that in a program linked
# statically the built-in parts (mode_registry.cpp) register first.
file(GLOB PMRAC_CONTROL_PARTS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/core/control/*/*.cpp)
# The core: Eigen + STL only. Nothing here may include a ROS header.
pmrac_library(preadaptive_mrac_core
  src/core/schema/params.cpp
  src/core/schema/param_table.cpp
  src/core/solvers.cpp
  src/core/sim/plant.cpp
  src/core/sim/actuator.cpp
  src/core/sim/turbulence.cpp
  src/core/sim/scenario_plant.cpp
  src/core/sim/envelope.cpp
  src/core/sim/plant_engine.cpp
  src/core/sim/scenario.cpp
  src/core/control/network.cpp
  src/core/controller/controller_config.cpp
  src/core/robust/robust_config.cpp
  src/core/control/event.cpp
  src/core/control/velocity_estimator.cpp
  src/core/control/attention.cpp
  src/core/control/attention_thresholds.cpp
  src/core/control/part_registry.cpp
  src/core/controller/mode_registry.cpp
  src/core/controller/controller.cpp
  src/core/robust/identification_window.cpp
  src/core/robust/robust_preadaptation.cpp
  src/core/robust/regime_memory.cpp
  src/core/robust/chunk_sums.cpp
  src/core/robust/loss_estimate.cpp
  src/core/robust/regime_decision.cpp
  src/core/robust/switch_detection.cpp
  src/core/closed_loop.cpp
  src/core/step_sequencer.cpp
  src/core/margins.cpp
  src/core/sim/scenario_family.cpp
  src/core/control/input_guard.cpp
  src/core/controller/tunables.cpp
  ${PMRAC_CONTROL_PARTS})

# The JSBSim engine (process, socket, plant, linearisation): POSIX + STL on top of the core. It
# registers itself with the core's engine registry (plant_engine.hpp) from a static initialiser,
# so what links it must keep it although no symbol of it is referenced: a program takes its
# objects (pmrac_link_engines), a shared library needs it loaded (--no-as-needed).
pmrac_library(preadaptive_mrac_jsbsim
  src/jsbsim/jsbsim_fork.cpp
  src/jsbsim/jsbsim_log.cpp
  src/jsbsim/jsbsim_paths.cpp
  src/jsbsim/jsbsim_process.cpp
  src/jsbsim/jsbsim_lane.cpp
  src/jsbsim/jsbsim_plant.cpp
  src/jsbsim/jsbsim_linearise.cpp
  src/jsbsim/jsbsim_xml.cpp
  src/jsbsim/jsbsim_overlay.cpp)
target_link_libraries(preadaptive_mrac_jsbsim PUBLIC preadaptive_mrac_core)
target_link_libraries(preadaptive_mrac_jsbsim_static PUBLIC preadaptive_mrac_core_static)
target_link_libraries(preadaptive_mrac_jsbsim_objects PUBLIC ${CMAKE_DL_LIBS})
# Preloaded into JSBSim (not linked by anything): its socket bytes through shared memory
# (src/jsbsim/preload). In the library folder, where jsbsim_lane.cpp looks for it.
add_library(pmrac_jsbsim_lane SHARED src/jsbsim/preload/jsbsim_lane_preload.cpp)
target_include_directories(pmrac_jsbsim_lane PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/include)
target_link_libraries(pmrac_jsbsim_lane ${CMAKE_DL_LIBS})
set_target_properties(pmrac_jsbsim_lane PROPERTIES
  LIBRARY_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_LIB_DESTINATION})
add_dependencies(preadaptive_mrac_jsbsim_objects pmrac_jsbsim_lane)
# The plant engines beside the linear model, for `target`: STATIC (a batch tool linked
# against the static archives) or SHARED. STATIC takes the core's objects too, all of them: a
# law or strategy in its folder registers itself from a static initialiser that nothing
# references, which the core's archive would leave out.
macro(pmrac_link_engines target kind)
  if("${kind}" STREQUAL "STATIC")
    target_link_libraries(${target} preadaptive_mrac_core_objects preadaptive_mrac_jsbsim_objects)
  else()
    target_link_libraries(${target} PUBLIC -Wl,--push-state,--no-as-needed preadaptive_mrac_jsbsim
                          -Wl,--pop-state)
  endif()
endmacro()

# io: YAML files, weights files, run set-up and JSON/CSV output (yaml-cpp, no ROS).
pmrac_library(preadaptive_mrac_io
  src/io/yaml_params.cpp
  src/io/weights_io.cpp
  src/io/setup.cpp)
target_link_libraries(preadaptive_mrac_io_objects PUBLIC yaml-cpp)
target_link_libraries(preadaptive_mrac_io PUBLIC preadaptive_mrac_core yaml-cpp)
option(PMRAC_STATIC_TOOLS "link the batch tools (preadapt_sim, _sweep, _family) fully static" ON)
find_library(PMRAC_YAML_CPP_ARCHIVE NAMES libyaml-cpp.a)
set(PMRAC_TOOLS_FULLY_STATIC OFF)
if(PMRAC_STATIC_TOOLS AND PMRAC_YAML_CPP_ARCHIVE)
  set(PMRAC_TOOLS_FULLY_STATIC ON)
  target_link_libraries(preadaptive_mrac_io_static PUBLIC preadaptive_mrac_core_static
                        ${PMRAC_YAML_CPP_ARCHIVE})
else()
  if(PMRAC_STATIC_TOOLS)
    message(STATUS "preadaptive_mrac: no libyaml-cpp.a; batch tools linked dynamically")
  endif()
  target_link_libraries(preadaptive_mrac_io_static PUBLIC preadaptive_mrac_core_static yaml-cpp)
endif()

# Batch tools: no ROS master needed.
find_package(Threads REQUIRED)
pmrac_library(preadaptive_mrac_cli src/tools/cli_common.cpp)
target_link_libraries(preadaptive_mrac_cli_objects PUBLIC yaml-cpp Threads::Threads)
target_link_libraries(preadaptive_mrac_cli PUBLIC preadaptive_mrac_io Threads::Threads)
target_link_libraries(preadaptive_mrac_cli_static PUBLIC preadaptive_mrac_io_static Threads::Threads)
pmrac_link_engines(preadaptive_mrac_cli SHARED)

add_executable(preadapt_sim src/tools/preadapt_sim.cpp src/tools/aircraft_elevator.cpp)
target_link_libraries(preadapt_sim preadaptive_mrac_cli_static)
add_executable(preadapt_sweep src/tools/preadapt_sweep.cpp)
target_link_libraries(preadapt_sweep preadaptive_mrac_cli_static)
add_executable(preadapt_family src/tools/preadapt_family.cpp src/tools/family_draw.cpp
               src/tools/family_run.cpp src/tools/family_report.cpp
               src/tools/aircraft_elevator.cpp)
target_link_libraries(preadapt_family preadaptive_mrac_cli_static)
add_executable(preadapt_margins src/tools/preadapt_margins.cpp)
target_link_libraries(preadapt_margins preadaptive_mrac_cli_static)
add_executable(preadapt_trim src/tools/preadapt_trim.cpp)
target_link_libraries(preadapt_trim preadaptive_mrac_cli_static)
# Command-line tools: catkin's global bin (on PATH once a devel or install space is sourced),
# with a link in the package's lib/ so that `rosrun preadaptive_mrac preadapt_sim` works too.
set(PMRAC_BATCH_TOOLS preadapt_sim preadapt_sweep preadapt_family preadapt_margins preadapt_trim)
foreach(t ${PMRAC_BATCH_TOOLS})
  pmrac_link_engines(${t} STATIC)
endforeach()
set_target_properties(${PMRAC_BATCH_TOOLS} PROPERTIES
  RUNTIME_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_BIN_DESTINATION})
if(PMRAC_TOOLS_FULLY_STATIC)
  foreach(t ${PMRAC_BATCH_TOOLS})
    target_link_options(${t} PRIVATE -static)
  endforeach()
endif()
