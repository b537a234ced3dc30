# The game sample (examples/paddle) from the installed package, end to end (ctest runs it with
# cmake -P; label example):
#   1. cmake --install BUILD_DIR into WORK_DIR/prefix;
#   2. configure and build examples/paddle against it only (find_package(Sluice));
#   3. run it under Xvfb for FRAMES scripted frames: it exits 0 when the water is on screen,
#      the paddle felt a force, and the drain took exactly the tap's water.
# Variables: BUILD_DIR, WORK_DIR, EXAMPLE_DIR, FRAMES, GENERATOR, CXX_COMPILER; optional
# MAKE_PROGRAM, and CXX_FLAGS and LINKER_FLAGS as the build used them (sanitizers).

foreach(var BUILD_DIR WORK_DIR EXAMPLE_DIR FRAMES GENERATOR CXX_COMPILER)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "ExampleTest: -D${var}=... is required")
    endif()
endforeach()
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
    message(STATUS "ExampleTest: SKIP: xvfb-run is not installed (Debian: apt-get install xvfb)")
    return()
endif()

function(run out_var)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out
                    WORKING_DIRECTORY ${WORK_DIR})
    if(NOT rc EQUAL 0)
        list(JOIN ARGN " " command)
        message(FATAL_ERROR "ExampleTest: `${command}` failed (${rc}):\n${out}")
    endif()
    set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/paddle)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
run(out ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
set(make_program "")
if(MAKE_PROGRAM)
    set(make_program -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
endif()
run(out ${CMAKE_COMMAND} -S ${EXAMPLE_DIR} -B ${build} -G ${GENERATOR} ${make_program}
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}"
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run(out ${CMAKE_COMMAND} --build ${build})
# xvfb-run with its X authority file in the work folder (a temporary one races under ctest -j).
run(out ${XVFB_RUN} -a -f ${WORK_DIR}/Xauthority -s "-screen 0 800x600x24"
    ${build}/paddle --check ${FRAMES})
message(STATUS "ExampleTest:\n${out}")
