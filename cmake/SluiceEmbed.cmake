# Embeds GLSL sources into a library at build time, so programs run from any folder.
#
#   sluice_embed_shaders(<target> NAMESPACE <c++ namespace> HEADER <include path>
#                        SOURCES <files relative to shaders/>)
#
# Each source has its `#include "..."` lines resolved against shaders/ (GLSL has no include by
# default), then against NANOVDB_INCLUDE_DIR (for "nanovdb/PNanoVDB.h", NanoVDB's GLSL/C
# reader), and the result becomes a string in a generated .cpp. The generated header
# declares   std::string_view shaderSource(std::string_view fileName);   in NAMESPACE, returning
# an empty view for an unknown name.

set(SLUICE_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/SluiceEmbedScript.cmake)
set(SLUICE_SHADER_DIR ${CMAKE_CURRENT_LIST_DIR}/../shaders)

function(sluice_embed_shaders target)
    cmake_parse_arguments(ARG "" "NAMESPACE;HEADER" "SOURCES" ${ARGN})
    set(gen_dir ${CMAKE_CURRENT_BINARY_DIR}/embedded_${target})
    set(out_cpp ${gen_dir}/EmbeddedShaders.cpp)
    set(out_h ${gen_dir}/include/${ARG_HEADER})
    set(abs_sources "")
    foreach(src IN LISTS ARG_SOURCES)
        list(APPEND abs_sources ${SLUICE_SHADER_DIR}/${src})
    endforeach()
    file(GLOB shared_headers CONFIGURE_DEPENDS ${SLUICE_SHADER_DIR}/shared/*.h
         ${SLUICE_SHADER_DIR}/glsl/*.h)
    list(APPEND shared_headers ${NANOVDB_INCLUDE_DIR}/nanovdb/PNanoVDB.h)
    list(JOIN ARG_SOURCES "|" src_list)
    add_custom_command(
        OUTPUT ${out_cpp} ${out_h}
        COMMAND ${CMAKE_COMMAND} -DSHADER_DIR=${SLUICE_SHADER_DIR} "-DSOURCES=${src_list}"
                -DEXTRA_INCLUDE_DIR=${NANOVDB_INCLUDE_DIR}
                -DNAMESPACE=${ARG_NAMESPACE} -DHEADER=${ARG_HEADER} -DOUT_CPP=${out_cpp}
                -DOUT_H=${out_h} -P ${SLUICE_EMBED_SCRIPT}
        DEPENDS ${abs_sources} ${shared_headers} ${SLUICE_EMBED_SCRIPT}
        COMMENT "Embedding shaders for ${target}"
        VERBATIM)
    target_sources(${target} PRIVATE ${out_cpp} ${out_h})
    target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${gen_dir}/include>)
endfunction()
