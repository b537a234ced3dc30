# install() rules and the exported CMake package `Sluice`, included at the end of the top-level
# CMakeLists.txt once every target exists. After `cmake --install`, a game's build does
#   find_package(Sluice 0.1 REQUIRED)
# and gets Sluice::sluice-bake (the baker, imported), Sluice::format (the asset format library),
# sluice_bake_colliders() (cmake/SluiceBakeColliders.cmake), and, when they are built,
# Sluice::gpu (with Sluice::glad), Sluice::runtime and Sluice::sluice-play. The baking library
# (CGAL, OpenVDB, assimp) is not installed: a game only runs the baker.
#
# Layout under the prefix: bin/ the programs; lib/ the static libraries; include/sluice/<module>/
# the public headers (the GL loader under include/sluice/glad/sluice_glad/, the GLSL/C++ shared headers under
# include/sluice/shaders/shared/); lib/cmake/Sluice/ the package files.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SLUICE_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Sluice)

# The module CMakeLists files give include folders as plain paths, which install(EXPORT) refuses
# (they point into the source or build tree). Wraps each plain entry of `target`'s interface
# include folders in $<BUILD_INTERFACE:...> and adds the installed folders given after it,
# relative to the prefix, as $<INSTALL_INTERFACE:...>. The build itself sees no change.
function(_sluice_install_includes target)
    foreach(property INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
        get_target_property(dirs ${target} ${property})
        if(NOT dirs)
            continue()
        endif()
        set(wrapped "")
        foreach(dir IN LISTS dirs)
            if(dir MATCHES "^\\$<")
                list(APPEND wrapped "${dir}")
            else()
                list(APPEND wrapped "$<BUILD_INTERFACE:${dir}>")
            endif()
        endforeach()
        foreach(dir IN LISTS ARGN)
            list(APPEND wrapped "$<INSTALL_INTERFACE:${dir}>")
        endforeach()
        set_property(TARGET ${target} PROPERTY ${property} "${wrapped}")
    endforeach()
endfunction()

# A static library's PRIVATE links stay in its exported interface as $<LINK_ONLY:...>, so a
# consumer would have to find them too. For header-only libraries that is pointless (nothing is
# linked): keep those links for this build only, so find_package(Sluice) does not need them.
function(_sluice_drop_header_only_links target)
    set(header_only cereal::cereal CLI11::CLI11 nlohmann_json::nlohmann_json)
    get_target_property(libs ${target} INTERFACE_LINK_LIBRARIES)
    if(NOT libs)
        return()
    endif()
    set(kept "")
    foreach(lib IN LISTS libs)
        if(lib MATCHES "^\\$<LINK_ONLY:(.*)>$" AND CMAKE_MATCH_1 IN_LIST header_only)
            set(lib "$<BUILD_INTERFACE:${lib}>")
        endif()
        list(APPEND kept "${lib}")
    endforeach()
    set_property(TARGET ${target} PROPERTY INTERFACE_LINK_LIBRARIES "${kept}")
endfunction()

# The find_dependency() lines SluiceConfig.cmake needs for the third-party targets in the link
# interfaces of `targets` (static libraries carry even their PRIVATE links there, as
# $<LINK_ONLY:...>). Stored in `out_var`. A first-party library outside `targets` cannot be
# exported with them: it is named in `missing_var` instead.
function(_sluice_package_dependencies out_var missing_var)
    set(targets ${ARGN})
    set(packages "")
    set(missing "")
    foreach(target IN LISTS targets)
        get_target_property(libs ${target} INTERFACE_LINK_LIBRARIES)
        if(NOT libs)
            continue()
        endif()
        foreach(lib IN LISTS libs)
            string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" lib "${lib}")
            if(lib MATCHES "^\\$<")
                continue()
            endif()
            # Imported targets found in a subfolder are not visible here: judge those by name.
            set(imported TRUE)
            if(TARGET ${lib})
                get_target_property(aliased ${lib} ALIASED_TARGET)
                if(aliased)
                    set(lib ${aliased})
                endif()
                get_target_property(imported ${lib} IMPORTED)
            endif()
            if(lib IN_LIST targets)
                continue()
            elseif(NOT imported)
                list(APPEND missing "${target} -> ${lib}")
            elseif(lib STREQUAL "PkgConfig::XXHASH")
                list(APPEND packages xxhash)
            elseif(lib STREQUAL "glfw")
                list(APPEND packages glfw3)
            elseif(lib MATCHES "^(glm|cereal|CLI11|nlohmann_json|TBB|Threads|OpenGL|fmt|spdlog)::")
                list(APPEND packages ${CMAKE_MATCH_1})
            elseif(lib MATCHES "::")
                message(WARNING "SluiceInstall: the exported Sluice package needs ${lib} (linked "
                                "by ${target}); add its find_dependency() to cmake/SluiceInstall.cmake")
            endif() # anything else is a plain system library, such as dl
        endforeach()
    endforeach()
    list(REMOVE_DUPLICATES packages)
    set(code "")
    foreach(package IN LISTS packages)
        if(package STREQUAL "xxhash")
            # Debian's libxxhash-dev has no CMake package; recreate the pkg-config target.
            string(APPEND code "find_dependency(PkgConfig)\n"
                   "if(NOT TARGET PkgConfig::XXHASH)\n"
                   "    pkg_check_modules(XXHASH REQUIRED QUIET IMPORTED_TARGET libxxhash)\n"
                   "endif()\n")
        else()
            string(APPEND code "find_dependency(${package})\n")
        endif()
    endforeach()
    set(${out_var} "${code}" PARENT_SCOPE)
    set(${missing_var} "${missing}" PARENT_SCOPE)
endfunction()

# --- What is installed -------------------------------------------------------------------------

# The asset format: the library every Sluice user links.
set(_sluice_libraries sluice_format)
set_target_properties(sluice_format PROPERTIES EXPORT_NAME format)
_sluice_install_includes(sluice_format ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/format/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

# The GL support library and its loader, which the runtime's interface carries.
list(APPEND _sluice_libraries sluice_glad sluice_gpu sluice_collider_gpu)
set_target_properties(sluice_glad PROPERTIES EXPORT_NAME glad)
set_target_properties(sluice_gpu PROPERTIES EXPORT_NAME gpu)
set_target_properties(sluice_collider_gpu PROPERTIES EXPORT_NAME collider_gpu)
_sluice_install_includes(sluice_collider_gpu ${CMAKE_INSTALL_INCLUDEDIR})
_sluice_install_includes(sluice_glad ${CMAKE_INSTALL_INCLUDEDIR}/sluice/glad)
_sluice_install_includes(sluice_gpu ${CMAKE_INSTALL_INCLUDEDIR}
                         ${CMAKE_INSTALL_INCLUDEDIR}/sluice/shaders)
# The loader's headers, generated at configure time by cmake/SluiceGlad.cmake.
install(DIRECTORY ${CMAKE_BINARY_DIR}/_glad/prefixed/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sluice/glad)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/gpu/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shaders/shared
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sluice/shaders FILES_MATCHING PATTERN "*.h")
# sluice/gpu/GpuShaders.h and ColliderShaders.h, generated by sluice_embed_shaders
# (cmake/SluiceEmbed.cmake).
install(DIRECTORY ${CMAKE_BINARY_DIR}/gpu/embedded_sluice_gpu/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${CMAKE_BINARY_DIR}/gpu/embedded_sluice_collider_gpu/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

if(TARGET sluice_runtime)
    list(APPEND _sluice_libraries sluice_runtime)
    set_target_properties(sluice_runtime PROPERTIES EXPORT_NAME runtime)
    _sluice_install_includes(sluice_runtime ${CMAKE_INSTALL_INCLUDEDIR})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/runtime/include/
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()

foreach(library IN LISTS _sluice_libraries)
    _sluice_drop_header_only_links(${library})
endforeach()
_sluice_package_dependencies(_sluice_dependencies _sluice_missing ${_sluice_libraries})
if(_sluice_missing)
    # Exporting would fail at generate time and stop the whole build; leave the runtime out
    # instead (the others link only each other) and say what to add to the list above.
    message(WARNING "SluiceInstall: not installing sluice_runtime: its interface links "
                    "first-party libraries that are not installed (${_sluice_missing})")
    list(REMOVE_ITEM _sluice_libraries sluice_runtime)
    _sluice_package_dependencies(_sluice_dependencies _sluice_missing ${_sluice_libraries})
endif()

set(_sluice_programs sluice-bake)
if(TARGET sluice-play)
    list(APPEND _sluice_programs sluice-play)
endif()
if(NOT TARGET sluice_runtime OR NOT sluice_runtime IN_LIST _sluice_libraries)
    list(REMOVE_ITEM _sluice_programs sluice-play)
endif()

install(TARGETS ${_sluice_programs} ${_sluice_libraries}
        EXPORT SluiceTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})

# --- The package files -------------------------------------------------------------------------

install(EXPORT SluiceTargets NAMESPACE Sluice:: DESTINATION ${SLUICE_INSTALL_CMAKEDIR})

set(_sluice_config ${CMAKE_BINARY_DIR}/package/SluiceConfig.cmake)
set(_sluice_config_text [=[
# SluiceConfig.cmake: find_package(Sluice) for the installed baker, format library and runtime.
# Generated by cmake/SluiceInstall.cmake.
include(CMakeFindDependencyMacro)
@_sluice_dependencies@
include(${CMAKE_CURRENT_LIST_DIR}/SluiceTargets.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/SluiceBakeColliders.cmake)
]=])
file(CONFIGURE OUTPUT ${_sluice_config} CONTENT "${_sluice_config_text}" @ONLY)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/SluiceConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${_sluice_config} ${CMAKE_BINARY_DIR}/package/SluiceConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/SluiceBakeColliders.cmake
        DESTINATION ${SLUICE_INSTALL_CMAKEDIR})
