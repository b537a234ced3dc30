# What the installed-package tests share (PackageTest.cmake, ExampleTest.cmake): their required
# variables, running a command that must succeed, and installing a build to a prefix and configuring a consumer
# project against it only.

# Stops the test `test` unless every variable named after it was given with -D.
function(require_variables test)
    foreach(var ${ARGN})
        if(NOT DEFINED ${var})
            message(FATAL_ERROR "${test}: -D${var}=... is required")
        endif()
    endforeach()
endfunction()

# Runs a command; stops the test with its output if it fails. Its output lands in `out_var`.
function(run out_var)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT rc EQUAL 0)
        list(JOIN ARGN " " command)
        message(FATAL_ERROR "`${command}` failed (${rc}):\n${out}")
    endif()
    set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

# Installs BUILD_DIR into `prefix`, then configures `source` into `build` against that prefix
# only, with the build's GENERATOR, MAKE_PROGRAM, CXX_COMPILER, CXX_FLAGS and LINKER_FLAGS (the
# consumer links static libraries: it needs the same sanitizer flags); ARGN are more -D options.
function(install_and_configure prefix source build)
    run(out ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
    set(make_program "")
    if(MAKE_PROGRAM)
        set(make_program -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
    endif()
    run(out ${CMAKE_COMMAND} -S ${source} -B ${build} -G ${GENERATOR} ${make_program}
        -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=Release
        "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}"
        -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF ${ARGN})
endfunction()
