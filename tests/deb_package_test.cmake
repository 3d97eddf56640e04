# Builds the Debian package (cpack -G DEB), installs it into a temporary root with
# dpkg-deb, and runs the installed CLI from there: --version and a bake.
# Run as: cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DVERSION=... -P deb_package_test.cmake
include(${CMAKE_CURRENT_LIST_DIR}/script_steps.cmake)
require_script_vars(deb_package_test.cmake BUILD_DIR SOURCE_DIR WORK_DIR VERSION)
file(MAKE_DIRECTORY "${WORK_DIR}/root")

step(cpack cpack -G DEB --config "${BUILD_DIR}/CPackConfig.cmake" -B "${WORK_DIR}/package")
file(GLOB debs "${WORK_DIR}/package/medspheres_*.deb")
list(LENGTH debs n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one medspheres_*.deb in ${WORK_DIR}/package, found: ${debs}")
endif()
step(fields dpkg-deb --field "${debs}" Package Version Depends)
message(STATUS "${step_output}")
if(NOT step_output MATCHES "Version: ${VERSION}" OR NOT step_output MATCHES "libassimp")
  message(FATAL_ERROR "the package's fields lack the version ${VERSION} or assimp: ${step_output}")
endif()
step(install dpkg-deb -x "${debs}" "${WORK_DIR}/root")

set(cli "${WORK_DIR}/root/usr/bin/medspheres")
step(version "${cli}" --version)
if(NOT step_output MATCHES "${VERSION}")
  message(FATAL_ERROR "medspheres --version printed '${step_output}', not ${VERSION}")
endif()
step(bake "${cli}" bake "${SOURCE_DIR}/examples/data/eight.off" -o "${WORK_DIR}/eight.spheres.json")
message(STATUS "${step_output}")
if(NOT step_output MATCHES "634 triangles" OR NOT EXISTS "${WORK_DIR}/eight.spheres.json")
  message(FATAL_ERROR "the installed CLI's bake did not bake eight.off: ${step_output}")
endif()
foreach(f include/medspheres/sphere_set.h lib/cmake/medspheres/medspheresConfig.cmake)
  if(NOT EXISTS "${WORK_DIR}/root/usr/${f}")
    message(FATAL_ERROR "the package lacks /usr/${f}")
  endif()
endforeach()

# The mesh import program is installed beside the CLI (the bake above used it); a CLI
# copied alone elsewhere says that it is missing instead of loading in-process.
if(NOT EXISTS "${WORK_DIR}/root/usr/bin/medspheres-import")
  message(FATAL_ERROR "the package lacks /usr/bin/medspheres-import")
endif()
file(MAKE_DIRECTORY "${WORK_DIR}/alone")
file(COPY "${cli}" DESTINATION "${WORK_DIR}/alone")
if(NOT EXISTS "/usr/local/bin/medspheres-import" AND NOT EXISTS "/usr/bin/medspheres-import")
  execute_process(COMMAND "${WORK_DIR}/alone/medspheres" bake "${SOURCE_DIR}/examples/data/eight.off"
                          -o "${WORK_DIR}/alone.spheres.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT err MATCHES "medspheres-import" OR EXISTS "${WORK_DIR}/alone.spheres.json")
    message(FATAL_ERROR "a CLI without its import program gave (${rc}): ${out}${err}")
  endif()
  message(STATUS "alone: ${err}")
endif()

# The Python module of the package finds the program beside itself. (The one-line program
# holds no ';': step() forwards its arguments as a CMake list, which would split it there.)
file(GLOB modules "${WORK_DIR}/root/usr/lib/python3*/dist-packages/medspheres/_medspheres*.so")
if(modules)
  list(GET modules 0 module)
  get_filename_component(package "${module}" DIRECTORY)
  get_filename_component(site "${package}" DIRECTORY)
  if(NOT EXISTS "${package}/medspheres-import")
    message(FATAL_ERROR "the package's Python module lacks medspheres-import beside it")
  endif()
  step(python_load ${CMAKE_COMMAND} -E env --unset=MEDSPHERES_IMPORT_HELPER "PYTHONPATH=${site}"
       /usr/bin/python3 -c
       "print(len(__import__('medspheres').load_mesh('${SOURCE_DIR}/examples/data/eight.off')[1]), 'triangles')")
  if(NOT step_output MATCHES "634 triangles")
    message(FATAL_ERROR "the installed Python module did not load eight.off: ${step_output}")
  endif()
endif()
