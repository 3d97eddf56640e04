# Installs medspheres into a temporary prefix, then configures, builds and runs the
# downstream project in examples/consumer against it with find_package(medspheres).
# Run as: cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DINITIAL_CACHE=...]
#   -P consumer_test.cmake
# INITIAL_CACHE: a file of cache settings every configure of the consumer starts from (the
# compiler launcher of the build under test).
include(${CMAKE_CURRENT_LIST_DIR}/script_steps.cmake)
require_script_vars(consumer_test.cmake BUILD_DIR SOURCE_DIR WORK_DIR)
set(initial_cache)
if(INITIAL_CACHE)
  set(initial_cache -C "${INITIAL_CACHE}")
endif()

step(install ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
step(configure ${CMAKE_COMMAND} ${initial_cache} -S "${SOURCE_DIR}/examples/consumer"
     -B "${WORK_DIR}/build"
     -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix")
step(build ${CMAKE_COMMAND} --build "${WORK_DIR}/build" -j 2)
step(bake "${WORK_DIR}/build/bake_example" "${SOURCE_DIR}/examples/data/eight.off"
     "${WORK_DIR}/eight.spheres.json")
message(STATUS "${step_output}")
if(NOT step_output MATCHES "634 triangles, [0-9]+ spheres")
  message(FATAL_ERROR "unexpected bake_example output: ${step_output}")
endif()
step(library "${WORK_DIR}/build/library_example" "${SOURCE_DIR}/examples/data/eight.off")
message(STATUS "${step_output}")
if(NOT step_output MATCHES "^16 spheres, nerr 0\\.[0-9]+; cover of [1-4] certified; 1 batch input; 32 per link")
  message(FATAL_ERROR "unexpected library_example output: ${step_output}")
endif()
step(fcl "${WORK_DIR}/build/fcl_example" "${WORK_DIR}/eight.spheres.json")
message(STATUS "${step_output}")

# Without CGAL: the run-time targets still configure, build and run; asking for the
# components that need CGAL fails at find_package, naming them and CGAL.
step(configure-without-cgal ${CMAKE_COMMAND} ${initial_cache} -S "${SOURCE_DIR}/examples/consumer"
     -B "${WORK_DIR}/build-nocgal" -DCMAKE_BUILD_TYPE=Release
     "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" -DCMAKE_DISABLE_FIND_PACKAGE_CGAL=ON
     -DCONSUMER_WITH_BAKE=OFF)
step(build-without-cgal ${CMAKE_COMMAND} --build "${WORK_DIR}/build-nocgal" -j 2)
step(fcl-without-cgal "${WORK_DIR}/build-nocgal/fcl_example" "${WORK_DIR}/eight.spheres.json")
execute_process(
  COMMAND ${CMAKE_COMMAND} ${initial_cache} -S "${SOURCE_DIR}/examples/consumer"
          -B "${WORK_DIR}/build-nobake"
          -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix"
          -DCMAKE_DISABLE_FIND_PACKAGE_CGAL=ON -DCONSUMER_WITH_BAKE=ON
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES
   "the bake, measure, cover, robot_bake, batch, options components need CGAL")
  message(FATAL_ERROR "COMPONENTS bake without CGAL should fail naming CGAL (${rc}):\n${out}\n${err}")
endif()
message(STATUS "bake-without-cgal: fails as it should")
file(REMOVE_RECURSE "${WORK_DIR}")
