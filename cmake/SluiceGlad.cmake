# Generates the GL 4.5 core + EGL 1.5 loaders with the glad2 generator (PyPI) at configure time,
# into a virtual environment inside the build folder, and defines the static library sluice_glad.
# Its symbols and headers are Sluice's own (cmake/glad_prefix.py: sluice_glad_glGenBuffers,
# sluice_gladLoadGL, <sluice_glad/gl.h>), so a game linking its own glad or another loader
# shares nothing with it. Nothing generated is committed; a second configure reuses the venv and
# the generated files.

set(SLUICE_GLAD_VERSION "2.0.8" CACHE STRING "glad2 generator version from PyPI")
set(_glad_root ${CMAKE_BINARY_DIR}/_glad)
set(_glad_venv ${_glad_root}/venv)
set(_glad_out ${_glad_root}/out)
set(_glad_prefixed ${_glad_root}/prefixed)
set(_glad_apis "gl:core=4.5,egl=1.5")
# EGL extensions for headless contexts: NVIDIA's device platform and Mesa's surfaceless one.
set(_glad_exts
    EGL_EXT_platform_base EGL_EXT_platform_device EGL_EXT_device_base EGL_EXT_device_enumeration
    EGL_EXT_device_query EGL_MESA_platform_surfaceless EGL_KHR_create_context
    EGL_KHR_surfaceless_context GL_KHR_debug)
list(JOIN _glad_exts "," _glad_ext_csv)
file(SHA256 ${CMAKE_CURRENT_LIST_DIR}/glad_prefix.py _glad_prefix_hash)
set(_glad_key "${SLUICE_GLAD_VERSION}|${_glad_apis}|${_glad_ext_csv}|${_glad_prefix_hash}")

find_package(Python3 REQUIRED COMPONENTS Interpreter)

set(_glad_stamp ${_glad_root}/stamp.txt)
set(_glad_have "")
if(EXISTS ${_glad_stamp})
    file(READ ${_glad_stamp} _glad_have)
endif()

if(NOT _glad_have STREQUAL _glad_key OR NOT EXISTS ${_glad_prefixed}/src/gl.c)
    message(STATUS "glad: generating GL/EGL loaders with glad2 ${SLUICE_GLAD_VERSION}")
    if(NOT EXISTS ${_glad_venv}/bin/python)
        execute_process(COMMAND ${Python3_EXECUTABLE} -m venv ${_glad_venv}
                        RESULT_VARIABLE _rc)
        if(NOT _rc EQUAL 0)
            message(FATAL_ERROR "glad: could not create a Python venv in ${_glad_venv}")
        endif()
    endif()
    execute_process(COMMAND ${_glad_venv}/bin/python -m pip install --quiet --disable-pip-version-check
                            "glad2==${SLUICE_GLAD_VERSION}"
                    RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0)
        message(FATAL_ERROR "glad: pip install glad2==${SLUICE_GLAD_VERSION} failed (PyPI reachable?)")
    endif()
    file(REMOVE_RECURSE ${_glad_out})
    # --reproducible: use the Khronos XML bundled with glad2 instead of fetching it.
    execute_process(COMMAND ${_glad_venv}/bin/python -m glad --quiet --reproducible
                            --api ${_glad_apis} --extensions ${_glad_ext_csv}
                            --out-path ${_glad_out} c --loader
                    RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0 OR NOT EXISTS ${_glad_out}/src/gl.c)
        message(FATAL_ERROR "glad: generation failed")
    endif()
    execute_process(COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_LIST_DIR}/glad_prefix.py
                            ${_glad_out} ${_glad_prefixed}
                    RESULT_VARIABLE _rc)
    if(NOT _rc EQUAL 0 OR NOT EXISTS ${_glad_prefixed}/src/gl.c)
        message(FATAL_ERROR "glad: renaming the loader's symbols failed")
    endif()
    file(WRITE ${_glad_stamp} "${_glad_key}")
endif()

add_library(sluice_glad STATIC ${_glad_prefixed}/src/gl.c ${_glad_prefixed}/src/egl.c)
target_include_directories(sluice_glad SYSTEM PUBLIC ${_glad_prefixed}/include)
set_target_properties(sluice_glad PROPERTIES POSITION_INDEPENDENT_CODE ON)
target_link_libraries(sluice_glad PUBLIC ${CMAKE_DL_LIBS})
