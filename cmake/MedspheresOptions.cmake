# Compiler settings shared by every medspheres target.
include(GNUInstallDirs)

if(MEDSPHERES_SANITIZE)
  # Applied to every target of this project, tests and benchmarks included, so that
  # instrumented and uninstrumented code never share a container layout.
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  # Executables at a fixed address: a position-independent one has the loader apply a
  # relocation to every pointer in its data at each start, and the instrumented globals'
  # descriptors make that most of its pages (the CLI's --version: 20,600 page faults and
  # 0.5 to 0.6 s, 9,000 and 0.3 to 0.4 s without). The sanitizer stage starts about 2,300
  # programs (docs/reliability.md).
  string(APPEND CMAKE_EXE_LINKER_FLAGS " -no-pie")
endif()

if(MEDSPHERES_FUZZ OR MEDSPHERES_TSAN)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "MEDSPHERES_FUZZ and MEDSPHERES_TSAN need clang (-DCMAKE_CXX_COMPILER=clang++-14)")
  endif()
endif()
if(MEDSPHERES_FUZZ)
  # Coverage feedback for libFuzzer in every target; the fuzz targets alone link libFuzzer's
  # main (fuzz/CMakeLists.txt).
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
if(MEDSPHERES_TSAN)
  # clang's OpenMP runtime (libomp) tells ThreadSanitizer about its barriers and tasks through
  # the Archer tool (libarcher, loaded with OMP_TOOL_LIBRARIES, see .ci/tsan); GCC's libgomp
  # cannot, and would be reported as racing with itself.
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()

if(MEDSPHERES_ASSERTS)
  add_compile_definitions(MEDSPHERES_ENABLE_ASSERTS=1)
endif()

# medspheres_configure_target(<target>): C++17, warnings, the include layout.
function(medspheres_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  # Debian's libfcl is built as C++11/14, so the Eigen-holding FCL classes it allocates
  # (BVNode, BVHModel, ...) come from Eigen's class-specific aligned operator new. Under
  # C++17 Eigen drops those operators, and a C++17 translation unit would release such
  # objects with the global operator delete: a mismatch AddressSanitizer reports, and an
  # ODR difference between libfcl and its users. Keeping Eigen's pre-C++17 operators makes
  # every medspheres target, and every consumer of one (PUBLIC), agree with libfcl.
  target_compile_definitions(${target} PUBLIC EIGEN_HAS_CXX17_OVERALIGN=0)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                           -Wnon-virtual-dtor -Wno-unused-parameter)
    if(MEDSPHERES_WERROR)
      target_compile_options(${target} PRIVATE -Werror)
    endif()
  endif()
endfunction()

# medspheres_add_library(<name> <alias> SOURCES ...): a library exported as medspheres::<alias>.
function(medspheres_add_library name alias)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  add_library(${name} ${ARG_SOURCES})
  add_library(medspheres::${alias} ALIAS ${name})
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${alias} OUTPUT_NAME ${name})
  medspheres_configure_target(${name})
  set_property(GLOBAL APPEND PROPERTY MEDSPHERES_EXPORTED_TARGETS ${name})
endfunction()

# medspheres_export_headers(<target> <dir>): <dir>/medspheres/ holds <target>'s public
# headers: <dir> is on the include path of <target> and its users, and is installed.
function(medspheres_export_headers target dir)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${dir}>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  install(DIRECTORY ${dir}/medspheres DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
