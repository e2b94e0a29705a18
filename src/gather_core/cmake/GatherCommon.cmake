# Shared by the gather packages: build type, warnings, and a test helper that
# registers GoogleTest suites with catkin (run_tests) or with CTest (plain CMake).
if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()
set(CMAKE_CXX_STANDARD 17)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
# Nothing interposes gather's own functions: position-independent code may
# then call a non-inline function of its own library directly and inline
# it, as code built without -fPIC does (GCC otherwise keeps such exported
# functions out of inlining and calls them through the PLT). No fused
# multiply-adds either (GCC's default for C++ where the target has them,
# e.g. aarch64): what gets inlined, and where, never changes a result, and
# a robot's agent computes what the OC's planner and simulator compute.
add_compile_options(-fno-semantic-interposition -ffp-contract=off)

# Root of the repository (tests/, maps/ live there).
get_filename_component(_gather_cmake_dir "${CMAKE_CURRENT_LIST_DIR}" REALPATH)  # through the catkin_ws/src link
get_filename_component(GATHER_REPO_DIR "${_gather_cmake_dir}/../../.." ABSOLUTE)

if(CATKIN_TOPLEVEL)
  set(GATHER_CATKIN ON)
else()
  set(GATHER_CATKIN OFF)
  include(CTest)
endif()

# Sanitized build (make test-plain): AddressSanitizer and UndefinedBehavior-
# Sanitizer, with float-to-int overflow, on every target; any report aborts
# the process (-fno-sanitize-recover), so a test or fuzz case that triggers
# one fails. -O1 (after the build type's -O3, so it wins): what the
# sanitizers' documentation recommends, and it compiles in less time.
option(GATHER_SANITIZE "Build with -fsanitize=address,undefined,float-cast-overflow" OFF)
if(GATHER_SANITIZE)
  add_compile_options(-O1 -fsanitize=address,undefined -fsanitize=float-cast-overflow -fno-sanitize-recover=all
                      -fno-omit-frame-pointer -g1)
  add_link_options(-fsanitize=address,undefined)
  # Several sources compiled as one (8 a unit): about a third less time to
  # build under the sanitizers. It needs file-local names that differ
  # between sources of a target (shared constants live in headers:
  # gather_core/numeric.hpp).
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 8)
endif()

# Our targets build without warnings: any warning fails the build.
function(gather_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Werror)
endfunction()

# gather_add_gtest(NAME SOURCES... LIBS libs...)
function(gather_add_gtest name)
  cmake_parse_arguments(T "" "" "SOURCES;LIBS" ${ARGN})
  if(GATHER_CATKIN)
    catkin_add_gtest(${name} ${T_SOURCES} WORKING_DIRECTORY ${GATHER_REPO_DIR})
    if(NOT TARGET ${name})
      message(FATAL_ERROR "GoogleTest not found by catkin (install libgtest-dev)")
    endif()
    # Debian's catkin links gtest but not its main().
    target_link_libraries(${name} gtest_main)
  else()
    if(NOT BUILD_TESTING)
      return()
    endif()
    find_package(GTest REQUIRED)
    include(GoogleTest)
    add_executable(${name} ${T_SOURCES})
    target_link_libraries(${name} GTest::gtest_main)
    gtest_discover_tests(${name} WORKING_DIRECTORY ${GATHER_REPO_DIR} DISCOVERY_TIMEOUT 60)
  endif()
  target_link_libraries(${name} ${T_LIBS})
  target_compile_definitions(${name} PRIVATE GATHER_REPO_DIR="${GATHER_REPO_DIR}")
  gather_warnings(${name})
endfunction()
