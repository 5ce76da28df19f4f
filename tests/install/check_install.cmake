# Run by ctest as `cmake -P` (see CMakeLists.txt here). Installs BUILD_DIR into a fresh
# prefix under WORK_DIR, builds the consumer project against it and checks its output.

foreach(var BUILD_DIR CONFIG WORK_DIR CONSUMER_SOURCE_DIR EXAMPLES_DIR GENERATOR CXX_COMPILER
            EXPECTED_VERSION)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_install.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix "${WORK_DIR}/prefix")
set(consumer_build "${WORK_DIR}/consumer-build")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run_step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${name} failed (${rc})\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

set(config_args "")
if(CONFIG)
  set(config_args --config "${CONFIG}")
endif()

message(STATUS "install test: cmake --install ${BUILD_DIR} --prefix ${prefix}")
run_step("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}"
         ${config_args})
foreach(header voroclip/core.h voroclip/predicates.h)
  if(NOT EXISTS "${prefix}/include/${header}")
    message(FATAL_ERROR "install test: ${prefix}/include/${header} was not installed")
  endif()
endforeach()
file(GLOB_RECURSE config_files "${prefix}/*/voroclipConfig.cmake")
if(NOT config_files)
  message(FATAL_ERROR "install test: no voroclipConfig.cmake under ${prefix}")
endif()

set(configure_args -S "${CONSUMER_SOURCE_DIR}" -B "${consumer_build}" -G "${GENERATOR}"
    "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" "-DCMAKE_PREFIX_PATH=${prefix}"
    "-DVOROCLIP_EXAMPLES_DIR=${EXAMPLES_DIR}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
if(CONFIG)
  list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONFIG}")
endif()
if(MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
message(STATUS "install test: configuring the consumer project")
run_step("configuring the consumer" "${CMAKE_COMMAND}" ${configure_args})

# The package must come from the fresh prefix, not from an older install elsewhere.
file(STRINGS "${consumer_build}/CMakeCache.txt" voroclip_dir REGEX "^voroclip_DIR:")
string(REGEX REPLACE "^voroclip_DIR:[A-Z]+=" "" voroclip_dir "${voroclip_dir}")
file(REAL_PATH "${prefix}" real_prefix)
file(REAL_PATH "${voroclip_dir}" real_voroclip_dir)
string(FIND "${real_voroclip_dir}" "${real_prefix}/" at)
if(NOT at EQUAL 0)
  message(FATAL_ERROR "install test: the consumer found voroclip in '${voroclip_dir}', "
                      "not under the fresh prefix '${prefix}'")
endif()

message(STATUS "install test: building the consumer")
run_step("building the consumer" "${CMAKE_COMMAND}" --build "${consumer_build}" ${config_args})

set(consumer "${consumer_build}/voroclip_consumer")
if(NOT EXISTS "${consumer}" AND CONFIG)
  set(consumer "${consumer_build}/${CONFIG}/voroclip_consumer")
endif()
run_step("running the consumer" "${consumer}")
string(CONCAT expected "voroclip ${EXPECTED_VERSION}\n"
       "orient2d ccw: positive\n"
       "orient2d classroom point on the line: zero\n"
       "orient2d classroom point off the line: negative\n"
       "incircle inside: positive\n"
       "incircle cocircular: zero\n"
       "orient3d: negative\n"
       "insphere cospherical: zero\n"
       "insphere_sos cospherical: nonzero\n")
if(NOT step_output STREQUAL expected)
  message(FATAL_ERROR "install test: the consumer printed\n${step_output}\nexpected\n${expected}")
endif()

# The README's example: the cells of 27 sites fill the box.
set(example "${consumer_build}/clip_cells")
if(NOT EXISTS "${example}" AND CONFIG)
  set(example "${consumer_build}/${CONFIG}/clip_cells")
endif()
run_step("running the example clip_cells" "${example}")
if(NOT step_output MATCHES "\n27 cells, [0-9]+ neighbour pairs, volume 9 \\(domain 9\\), 26 boundary cells\n$")
  message(FATAL_ERROR "install test: the example clip_cells printed\n${step_output}")
endif()

if(WITH_CLI)
  run_step("running the installed CLI" "${prefix}/bin/voroclip" --version)
  if(NOT step_output STREQUAL "voroclip ${EXPECTED_VERSION}\n")
    message(FATAL_ERROR "install test: installed 'voroclip --version' printed '${step_output}'")
  endif()
endif()

message(STATUS "install test: passed (package from ${voroclip_dir})")
