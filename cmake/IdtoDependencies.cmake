# Every dependency comes from a Debian package and is found through its CMake config file.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(urdfdom REQUIRED)
find_package(ccd REQUIRED)
find_package(fcl 0.7 REQUIRED)
find_package(yaml-cpp REQUIRED)

# TinyXML (urdfdom's own XML library) is used directly by the URDF parser to read the document
# order of the joints; console_bridge comes with urdfdom_LIBRARIES.
find_library(IDTO_TINYXML_LIBRARY NAMES tinyxml REQUIRED)

# Private to the library: they never appear in public headers.
set(IDTO_PRIVATE_DEPS ${urdfdom_LIBRARIES} ${IDTO_TINYXML_LIBRARY} fcl yaml-cpp)

# std::thread for the library's own thread pool (no OpenMP).
find_package(Threads REQUIRED)

# MuJoCo: an optional oracle (tests), peer (benchmarks) and plant (MPC).
set(IDTO_HAVE_MUJOCO OFF)
if(NOT IDTO_WITH_MUJOCO STREQUAL "OFF")
  if(IDTO_WITH_MUJOCO STREQUAL "ON")
    find_package(mujoco REQUIRED)
  else()
    find_package(mujoco QUIET)
  endif()
  if(mujoco_FOUND)
    set(IDTO_HAVE_MUJOCO ON)
    # Debian's MuJoCo 2.2.2 lists /usr/include/libqhull_r/ (from libqhull-dev) as an include
    # directory; drop directories that do not exist so a machine without it still configures.
    get_target_property(_mj_inc mujoco::mujoco INTERFACE_INCLUDE_DIRECTORIES)
    set(_mj_inc_ok "")
    foreach(_dir ${_mj_inc})
      if(EXISTS "${_dir}")
        list(APPEND _mj_inc_ok "${_dir}")
      endif()
    endforeach()
    set_target_properties(mujoco::mujoco PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_mj_inc_ok}")
  endif()
endif()
message(STATUS "idto: MuJoCo ${IDTO_HAVE_MUJOCO}")

if(IDTO_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(IDTO_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
