# The installed package end to end (ctest runs it with cmake -P):
#   1. cmake --install BUILD_DIR into WORK_DIR/prefix;
#   2. configure and build tests/cmake/package against it only (find_package(Sluice),
#      sluice_bake_colliders() on MESH, a program linking Sluice::format);
#   3. the collider exists, the program reads it (a ball of radius 0.25 m: phi(0) = -0.25);
#   4. a second build bakes nothing: the asset's bytes and time stamp stay as they were.
# Variables: BUILD_DIR, WORK_DIR, CONSUMER_DIR, MESH, GENERATOR, CXX_COMPILER; optional
# MAKE_PROGRAM, and CXX_FLAGS and LINKER_FLAGS as the build used them (sanitizers).

include(${CMAKE_CURRENT_LIST_DIR}/ConsumerBuild.cmake)
require_variables(PackageTest BUILD_DIR WORK_DIR CONSUMER_DIR MESH GENERATOR CXX_COMPILER)

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/consumer)
file(REMOVE_RECURSE ${WORK_DIR})

install_and_configure(${prefix} ${CONSUMER_DIR} ${build}
    -DSLUICE_EXPECTED_PREFIX=${prefix} -DSLUICE_TEST_MESH=${MESH})
run(out ${CMAKE_COMMAND} --build ${build})

cmake_path(GET MESH STEM LAST_ONLY stem)
set(asset ${build}/colliders/${stem}.slc)
if(NOT EXISTS ${asset})
    message(FATAL_ERROR "PackageTest: the build did not bake ${asset}:\n${out}")
endif()
run(read ${build}/read_collider ${asset})
if(NOT read MATCHES "dims 23 23 23 source ${stem}.obj tool sluice-bake [0-9.]+ phi\\(0\\) -0\\.2[45]")
    message(FATAL_ERROR "PackageTest: read_collider printed an unexpected asset: ${read}")
endif()

file(SHA256 ${asset} hash_before)
file(TIMESTAMP ${asset} time_before "%s.%f")
run(out ${CMAKE_COMMAND} --build ${build})
file(SHA256 ${asset} hash_after)
file(TIMESTAMP ${asset} time_after "%s.%f")
if(NOT hash_before STREQUAL hash_after OR NOT time_before STREQUAL time_after)
    message(FATAL_ERROR "PackageTest: a second build rewrote ${asset}:\n${out}")
endif()
if(GENERATOR MATCHES "Ninja" AND NOT out MATCHES "no work to do")
    message(FATAL_ERROR "PackageTest: a second build did work:\n${out}")
endif()
message(STATUS "PackageTest: ${read}")
