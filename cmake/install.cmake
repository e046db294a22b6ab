# Install space (catkin_make install, catkin build with install, a Debian package built from it):
# everything a user of the package needs, found at run time through share/preadaptive_mrac
# (rospack, $(find preadaptive_mrac), or relative to the executable: configDir()), never through
# the source tree. Whole folders where possible, so a file added to one is installed without a
# change here. Left out on purpose (development only, and catkin_lint is told so in
# test/scripts/catkin_lint.sh): bench/ (benchmarks, wakeup_floor, bench_controller), fuzz/,
# test/ and the development scripts (check_format, test, install_deps, run_demo, the studies,
# fuzz, junit_wrap, python_files, summarize_tests, slurm/, two_machines_env.sh), which expect
# a source checkout.
# So that catkin_lint -W1 on a user's workspace says nothing, its two warnings about them are
# off for this package; test/scripts/catkin_lint.sh lists each left-out executable with its
# reason and fails when any other is not installed (catkin_lint --show-ignored).
#catkin_lint: ignore uninstalled_script uninstalled_target

# Libraries: the exported ones (catkin_package LIBRARIES), the nodes' and nodelets' (the
# plugin file names lib/libpreadaptive_mrac_nodelets) and the loopback shim (scripts/lib/ros_env).
install(TARGETS preadaptive_mrac_core preadaptive_mrac_io preadaptive_mrac_jsbsim preadaptive_mrac_cli
                preadaptive_mrac_ros_params preadaptive_mrac_ros preadaptive_mrac_nodelets
                pmrac_loopback_bind pmrac_jsbsim_lane
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})

# Nodes and the nodelet manager: rosrun / roslaunch find them in lib/preadaptive_mrac.
set(PMRAC_NODES plant_sim_node mrac_controller_node run_monitor_node bag_recorder_node pmrac_manager)
install(TARGETS ${PMRAC_NODES} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

# Batch tools: catkin's global bin, on PATH once the space is sourced; and for rosrun (which
# looks in lib/preadaptive_mrac only) a relative link there to each, in the devel space and
# installed (install() keeps a link a link).
install(TARGETS ${PMRAC_BATCH_TOOLS} RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})
file(MAKE_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION}
     ${CMAKE_CURRENT_BINARY_DIR}/rosrun_links)
foreach(tool ${PMRAC_BATCH_TOOLS})
  file(RELATIVE_PATH _pmrac_link /${CATKIN_PACKAGE_BIN_DESTINATION}
       /${CATKIN_GLOBAL_BIN_DESTINATION}/${tool})
  foreach(dir ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION}
              ${CMAKE_CURRENT_BINARY_DIR}/rosrun_links)
    file(CREATE_LINK ${_pmrac_link} ${dir}/${tool} SYMBOLIC)
  endforeach()
  #catkin_lint: ignore_once missing_file (made above, at configure time)
  install(PROGRAMS ${CMAKE_CURRENT_BINARY_DIR}/rosrun_links/${tool}
    DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()

# rosrun in the README's standalone build (build/ inside the source): rosrun searches the devel
# space's lib/preadaptive_mrac and the package's source folder, but drops every path under
# <source>/build/ (`find ... ! -regex ".*$pkgdir/build/.*"`, meant for old rosbuild trees), so it
# found no compiled executable there. Only in that layout, a link to each in the hidden source
# folder .rosrun/ (git-ignored): rosrun's find walks hidden folders, roslaunch's find_node
# (roslib) skips them, so roslaunch never sees two copies. In a catkin workspace (devel outside
# the source) nothing is made. Tested by test/scripts/tools_on_path.sh.
string(FIND "${CATKIN_DEVEL_PREFIX}/" "${CMAKE_CURRENT_SOURCE_DIR}/build/" _pmrac_in_source_build)
if(_pmrac_in_source_build EQUAL 0)
  file(MAKE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/.rosrun)
  foreach(exe ${PMRAC_NODES} ${PMRAC_BATCH_TOOLS})
    file(RELATIVE_PATH _pmrac_link ${CMAKE_CURRENT_SOURCE_DIR}/.rosrun
         ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_BIN_DESTINATION}/${exe})
    file(CREATE_LINK ${_pmrac_link} ${CMAKE_CURRENT_SOURCE_DIR}/.rosrun/${exe} SYMBOLIC)
  endforeach()
endif()

# The devel space has no copy of the package's files; the batch tools find config/ there
# through this link (configDir(): share/preadaptive_mrac/config beside the executable's prefix).
file(MAKE_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_SHARE_DESTINATION})
file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR}/config
     ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_SHARE_DESTINATION}/config SYMBOLIC)
# Likewise the JSBSim aircraft folder (share/preadaptive_mrac/jsbsim, JSBSim's --root).
file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR}/jsbsim
     ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_SHARE_DESTINATION}/jsbsim SYMBOLIC)

install(DIRECTORY include/ DESTINATION ${CATKIN_GLOBAL_INCLUDE_DESTINATION})
# Launch files, YAML configuration, rviz view, the dynamic_reconfigure definition and the
# nodelet plugin description (package.xml exports ${prefix}/nodelet_plugins.xml).
install(DIRECTORY config launch params rviz cfg DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(FILES nodelet_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
# The JSBSim aircraft, initial condition and engine files (JSBSim's --root; jsbsim/README.md),
# without the development probe in jsbsim/tools/.
install(DIRECTORY jsbsim DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION} PATTERN tools EXCLUDE)

# Python tools for users (run with the system python3 that has the ROS modules): thin entry
# points of the Python package src/preadaptive_mrac (catkin_python_setup() installs it).
catkin_install_python(PROGRAMS scripts/analyze_bag scripts/viz_markers scripts/live_plot
                               scripts/reindex_bags
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# The controller's run-time tuning client that exits 2 when a request is refused.
catkin_install_python(PROGRAMS scripts/tune DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# Examples of a user's own node against ours (docs/tutorials/own_controller.md, own_plant.md).
catkin_install_python(PROGRAMS scripts/examples/example_lqr_controller scripts/examples/example_plant
  DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# roslaunch that exits non-zero when a node died (docs/reference/ros.md), with the environment it sources.
install(PROGRAMS scripts/lib/launch_checked DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(FILES scripts/lib/ros_env DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# The launch-prefix compare.launch's pairs name their parent namespace's manager, recorder
# progress and tf with (parent_names), and the command giving the plant its truth subscriber
# count from params/modes.yaml (mode_info): launch files name them
# $(find preadaptive_mrac)/scripts/lib/..., the source tree's in the devel space, so installed
# at that place under share/ (beside share/params), not in a bin folder.
#catkin_lint: ignore_once wrong_bin_install_destination
install(PROGRAMS scripts/lib/parent_names scripts/lib/mode_info
  DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/scripts/lib)
