# Run by CTest (tests/install/CMakeLists.txt): installs BUILD_DIR into
# WORK_DIR/prefix, builds CONSUMER_DIR against that prefix only, runs it, and
# compares its output with the expected values. Fails (FATAL_ERROR) at the
# first step that does not work, printing that step's output.
cmake_minimum_required(VERSION 3.25)
foreach(v BUILD_DIR WORK_DIR CONSUMER_DIR CXX DROP_VECTORS)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "install_test.cmake: -D${v}=... is required")
  endif()
endforeach()
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()
set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/consumer-build)
file(REMOVE_RECURSE ${WORK_DIR})

function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${name} failed (${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
# Only the prefix: no package registry, and the source and build trees are
# not on the consumer's include path (it sees the installed headers only).
# Eigen is hidden from this configuration (CMAKE_DISABLE_FIND_PACKAGE_Eigen3):
# a user without Eigen finds, builds and links lockstep.
set(consumer_args -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
step("configure the consumer without Eigen" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${consumer_build}
  ${consumer_args} -DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=TRUE)
step("build the consumer" ${CMAKE_COMMAND} --build ${consumer_build})

step("run fixed_consumer" ${consumer_build}/fixed_consumer)
string(STRIP "${step_output}" fixed_out)
if(NOT fixed_out STREQUAL "2 -65536 81920")
  message(FATAL_ERROR "install test: fixed_consumer printed '${fixed_out}', expected '2 -65536 81920'")
endif()

step("run reference_consumer" ${consumer_build}/reference_consumer)
string(STRIP "${step_output}" hash)
file(READ ${DROP_VECTORS} drop)
string(JSON expected GET "${drop}" hashes 60)
if(NOT hash STREQUAL expected)
  message(FATAL_ERROR "install test: the installed engine's drop hash after frame 60 is '${hash}', "
                      "${DROP_VECTORS} says '${expected}'")
endif()

# The optional lockstep/eigen.hpp: find_package(lockstep), then the
# consumer's own find_package(Eigen3).
set(eigen_build ${WORK_DIR}/consumer-eigen-build)
step("configure the consumer with Eigen" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${eigen_build}
  ${consumer_args} -DCONSUMER_WITH_EIGEN=ON)
step("build eigen_consumer" ${CMAKE_COMMAND} --build ${eigen_build} --target eigen_consumer)
step("run eigen_consumer" ${eigen_build}/eigen_consumer)
string(STRIP "${step_output}" eigen_out)
# The ray from 10 m down hits body 0 (a cube 2 m up, its top at 2.5 m) after
# 7.5 m; its centre is in body 0 only; its pose is 2 m up.
if(NOT eigen_out STREQUAL "0 7.5000 1 2.0000")
  message(FATAL_ERROR "install test: eigen_consumer printed '${eigen_out}', expected '0 7.5000 1 2.0000'")
endif()
message(STATUS "install test: installed into ${prefix}; consumer built without Eigen; Q16 ${fixed_out}; "
               "drop frame 60 ${hash}; with Eigen: ${eigen_out}")
