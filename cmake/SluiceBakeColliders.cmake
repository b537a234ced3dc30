# sluice_bake_colliders(): bakes meshes into collider assets (.slc) as build steps.
#
#   sluice_bake_colliders(TARGET <name> [ALL]
#                         [OUTPUT_DIR <dir>]
#                         [VOXEL_SIZE <world units> | RESOLUTION <voxels>]
#                         [BACKEND auto|gpu|cgal] [PADDING <voxels>] [SIGN auto|parity|winding]
#                         [STORAGE f32|f16] [SCALE <factor>] [SPARSE [BAND <voxels>]]
#                         [VOLUME_MAPS <support>...]
#                         MESHES <mesh>...)
#
# Every mesh becomes its own custom command, so Ninja or Make schedules the bakes side by side:
# <OUTPUT_DIR>/<stem>.slc from <mesh> (relative meshes are taken from the current source
# folder; OUTPUT_DIR defaults to the current binary folder, relative ones are taken from it).
# The options are those of `sluice-bake bake` (unset ones keep its defaults: RESOLUTION 64,
# BACKEND auto, PADDING 3, SIGN auto, STORAGE f32, SCALE 1; SPARSE bakes narrow-band NanoVDB
# assets, `bake --sparse`, with BAND 3). VOLUME_MAPS bakes the boundary model's volume map for
# each support (a scene's kernel radius over the collider's placement scale, `bake
# --volume-map`), so scenes of those radii load without building them. A custom target <name> depends on
# every output (ALL adds it to the default build), and its SLUICE_COLLIDERS property lists them.
#
# Each step runs `sluice-bake batch` on a one-entry manifest written at configure time (only
# when its content changes). batch compares the mesh's content hash, the settings and the tool
# version recorded in the existing asset, so a mesh touched but not changed, or a rebuilt
# sluice-bake of the same version, rebakes nothing and leaves the asset's bytes alone. It also
# writes a depfile (output: mesh manifest), used where the generator supports DEPFILE.
#
# The baker is the imported Sluice::sluice-bake (find_package(Sluice)) or, inside Sluice's own
# build, the sluice-bake target.

# A JSON string literal for `text`: quotes and backslashes escaped.
function(_sluice_json_string text out_var)
    string(REPLACE "\\" "\\\\" text "${text}")
    string(REPLACE "\"" "\\\"" text "${text}")
    set(${out_var} "\"${text}\"" PARENT_SCOPE)
endfunction()

# Stops configuring unless `value` of option `name` is a non-negative JSON number ("0.0075").
function(_sluice_check_number name value)
    if(NOT value MATCHES "^(0|[1-9][0-9]*)(\\.[0-9]+)?([eE][-+]?[0-9]+)?$")
        message(FATAL_ERROR "sluice_bake_colliders: ${name} ${value} is not a number")
    endif()
endfunction()

# Writes `content` to `path` unless the file already holds it, so its time stamp moves (and
# the bakes depending on it rerun) only when it changes.
function(_sluice_write_if_changed path content)
    if(EXISTS ${path})
        file(READ ${path} old)
        if(old STREQUAL content)
            return()
        endif()
    endif()
    file(WRITE ${path} "${content}")
endfunction()

function(sluice_bake_colliders)
    cmake_parse_arguments(PARSE_ARGV 0 ARG "ALL;SPARSE"
                          "TARGET;OUTPUT_DIR;VOXEL_SIZE;RESOLUTION;BACKEND;PADDING;SIGN;STORAGE;SCALE;BAND"
                          "MESHES;VOLUME_MAPS")
    set(fn sluice_bake_colliders)
    if(ARG_UNPARSED_ARGUMENTS)
        message(FATAL_ERROR "${fn}: unknown arguments: ${ARG_UNPARSED_ARGUMENTS}")
    endif()
    if(NOT ARG_TARGET)
        message(FATAL_ERROR "${fn}: TARGET <name> is required")
    endif()
    if(NOT ARG_MESHES)
        message(FATAL_ERROR "${fn}(TARGET ${ARG_TARGET}): MESHES lists no mesh")
    endif()
    if(DEFINED ARG_VOXEL_SIZE AND DEFINED ARG_RESOLUTION)
        message(FATAL_ERROR "${fn}(TARGET ${ARG_TARGET}): give VOXEL_SIZE or RESOLUTION, not both")
    endif()

    # The manifest entry's settings, as `batch` reads them (field names of the bake options).
    set(settings "")
    if(DEFINED ARG_VOXEL_SIZE)
        _sluice_check_number(VOXEL_SIZE "${ARG_VOXEL_SIZE}")
        string(APPEND settings ", \"voxelSize\": ${ARG_VOXEL_SIZE}")
    endif()
    if(DEFINED ARG_RESOLUTION)
        if(NOT ARG_RESOLUTION MATCHES "^[0-9]+$")
            message(FATAL_ERROR "${fn}: RESOLUTION ${ARG_RESOLUTION} is not a whole number")
        endif()
        string(APPEND settings ", \"resolution\": ${ARG_RESOLUTION}")
    endif()
    if(DEFINED ARG_BAND AND NOT ARG_SPARSE)
        message(FATAL_ERROR "${fn}(TARGET ${ARG_TARGET}): BAND is for SPARSE bakes")
    endif()
    if(ARG_SPARSE)
        string(APPEND settings ", \"sparse\": true")
    endif()
    foreach(option IN ITEMS PADDING SCALE BAND)
        if(DEFINED ARG_${option})
            _sluice_check_number(${option} "${ARG_${option}}")
            string(TOLOWER ${option} key)
            string(APPEND settings ", \"${key}\": ${ARG_${option}}")
        endif()
    endforeach()
    if(ARG_VOLUME_MAPS)
        foreach(support IN LISTS ARG_VOLUME_MAPS)
            _sluice_check_number(VOLUME_MAPS "${support}")
        endforeach()
        list(JOIN ARG_VOLUME_MAPS ", " supports)
        string(APPEND settings ", \"volumeMaps\": [${supports}]")
    endif()
    # The choices of each named option (kept here: a function sees its caller's variables, and
    # find_package(Sluice) may have run in another folder).
    set(BACKEND_choices auto gpu cgal)
    set(SIGN_choices auto parity winding)
    set(STORAGE_choices f32 f16)
    foreach(option IN ITEMS BACKEND SIGN STORAGE)
        if(DEFINED ARG_${option})
            set(choices ${${option}_choices})
            if(NOT ARG_${option} IN_LIST choices)
                list(JOIN choices ", " choices)
                message(FATAL_ERROR "${fn}: ${option} ${ARG_${option}}: expected one of ${choices}")
            endif()
            string(TOLOWER ${option} key)
            string(APPEND settings ", \"${key}\": \"${ARG_${option}}\"")
        endif()
    endforeach()

    if(TARGET Sluice::sluice-bake)
        set(baker Sluice::sluice-bake)
    elseif(TARGET sluice-bake)
        set(baker sluice-bake)
    else()
        message(FATAL_ERROR "${fn}: no sluice-bake program: find_package(Sluice) first")
    endif()
    get_target_property(imported ${baker} IMPORTED)
    if(imported)
        set(baker_dep $<TARGET_FILE:${baker}>) # a file dependency on the installed program
    else()
        set(baker_dep ${baker}) # a target and file dependency on the program built here
    endif()

    set(out_dir ${CMAKE_CURRENT_BINARY_DIR})
    if(DEFINED ARG_OUTPUT_DIR)
        cmake_path(ABSOLUTE_PATH ARG_OUTPUT_DIR BASE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
                   NORMALIZE OUTPUT_VARIABLE out_dir)
    endif()
    set(work_dir ${CMAKE_CURRENT_BINARY_DIR}/sluice_colliders/${ARG_TARGET})
    set(use_depfile OFF)
    if(CMAKE_GENERATOR MATCHES "Ninja|Makefiles")
        set(use_depfile ON)
    endif()

    set(outputs "")
    foreach(mesh IN LISTS ARG_MESHES)
        cmake_path(ABSOLUTE_PATH mesh BASE_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} NORMALIZE)
        cmake_path(GET mesh STEM LAST_ONLY stem)
        set(output ${out_dir}/${stem}.slc)
        if(output IN_LIST outputs)
            message(FATAL_ERROR "${fn}(TARGET ${ARG_TARGET}): two meshes would both write "
                                "${stem}.slc; give them different names")
        endif()
        list(APPEND outputs ${output})

        _sluice_json_string("${mesh}" mesh_json)
        _sluice_json_string("${output}" output_json)
        set(manifest ${work_dir}/${stem}.json)
        _sluice_write_if_changed(${manifest}
            "{\"colliders\": [{\"mesh\": ${mesh_json}, \"output\": ${output_json}${settings}}]}\n")

        set(depfile_args "")
        if(use_depfile)
            set(depfile ${work_dir}/${stem}.d)
            set(depfile_args DEPFILE ${depfile})
            set(depfile_option --depfile ${depfile})
        else()
            set(depfile_option "")
        endif()
        add_custom_command(
            OUTPUT ${output}
            COMMAND ${CMAKE_COMMAND} -E make_directory ${out_dir}
            COMMAND ${baker} batch ${manifest} --quiet ${depfile_option}
            DEPENDS ${mesh} ${manifest} ${baker_dep}
            ${depfile_args}
            COMMENT "Baking collider ${stem}.slc"
            VERBATIM)
    endforeach()

    set(all "")
    if(ARG_ALL)
        set(all ALL)
    endif()
    add_custom_target(${ARG_TARGET} ${all} DEPENDS ${outputs})
    set_property(TARGET ${ARG_TARGET} PROPERTY SLUICE_COLLIDERS ${outputs})
endfunction()
