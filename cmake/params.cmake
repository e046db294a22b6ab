# One declaration per parameter: each table params/<component>.yaml becomes the header
# preadaptive_mrac/params/<component>_params.hpp (its struct with defaults and docs, the
# visitor the generic reader and range checks use, the tunables and their reconfigure copies),
# written by src/preadaptive_mrac/params_codegen.py into the devel space's include folder,
# beside the message headers (so a package built against the devel space finds them too), and
# installed with them. Generated at configure time, so that every target finds them from the
# start, and again whenever a table or the generator changes (a header is rewritten only when
# its text changes, so its dependants rebuild only then). The nodes' table has one struct per
# node (`structs`); the plant and scenario tables one per row `struct` (their scalars; the
# matrices, vectors and schedules are read by hand).
set(PMRAC_GENERATED_INCLUDE ${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_INCLUDE_DESTINATION})
file(GLOB PMRAC_PARAM_TABLES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/params/*.yaml)
set(PMRAC_PARAMS_CODEGEN
  ${CMAKE_COMMAND} -E env PYTHONPATH=${CMAKE_CURRENT_SOURCE_DIR}/src
  ${PYTHON_EXECUTABLE} -m preadaptive_mrac.params_codegen ${PMRAC_GENERATED_INCLUDE})
# (with every table, the modes' table params/modes.yaml becomes
# preadaptive_mrac/params/modes_params.hpp: the rows of the C++ mode registry)
execute_process(COMMAND ${PMRAC_PARAMS_CODEGEN} RESULT_VARIABLE _pmrac_codegen_rc)
if(NOT _pmrac_codegen_rc EQUAL 0)
  message(FATAL_ERROR "preadaptive_mrac: params_codegen failed on params/*.yaml (see above)")
endif()
add_custom_command(
  OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/params_codegen.stamp
  COMMAND ${PMRAC_PARAMS_CODEGEN}
  COMMAND ${CMAKE_COMMAND} -E touch ${CMAKE_CURRENT_BINARY_DIR}/params_codegen.stamp
  DEPENDS ${PMRAC_PARAM_TABLES}
          ${CMAKE_CURRENT_SOURCE_DIR}/src/preadaptive_mrac/params_codegen.py
          ${CMAKE_CURRENT_SOURCE_DIR}/src/preadaptive_mrac/params_table.py
          ${CMAKE_CURRENT_SOURCE_DIR}/src/preadaptive_mrac/modes.py
  COMMENT "preadaptive_mrac: C++ parameter structs from params/*.yaml")
add_custom_target(pmrac_params_headers DEPENDS ${CMAKE_CURRENT_BINARY_DIR}/params_codegen.stamp)
# (generated, so outside the package's source folder)
#catkin_lint: ignore_once external_directory
install(DIRECTORY ${PMRAC_GENERATED_INCLUDE}/preadaptive_mrac/params
        DESTINATION ${CATKIN_GLOBAL_INCLUDE_DESTINATION}/preadaptive_mrac)
