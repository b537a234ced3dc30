# Enforces the module rule: bake and runtime never link each other (a game embeds the runtime
# Walks each library's LINK_LIBRARIES transitively at configure time; a violation stops the build.

function(_sluice_collect_links target out_var)
    set(seen "")
    set(stack ${target})
    while(stack)
        list(POP_BACK stack cur)
        if(NOT TARGET ${cur} OR cur IN_LIST seen)
            continue()
        endif()
        list(APPEND seen ${cur})
        get_target_property(libs ${cur} LINK_LIBRARIES)
        get_target_property(ilibs ${cur} INTERFACE_LINK_LIBRARIES)
        foreach(lib IN LISTS libs ilibs)
            if(lib AND NOT lib MATCHES "-NOTFOUND$" AND NOT lib MATCHES "^\\$<")
                list(APPEND stack ${lib})
            endif()
        endforeach()
    endwhile()
    set(${out_var} ${seen} PARENT_SCOPE)
endfunction()

function(sluice_check_link_rules)
    # sluice_play is the runtime program's library (window, capture, command line).
    foreach(pair "sluice_bake;sluice_runtime" "sluice_runtime;sluice_bake"
                 "sluice_bake;sluice_play" "sluice_play;sluice_bake")
        list(GET pair 0 from)
        list(GET pair 1 to)
        if(TARGET ${from})
            _sluice_collect_links(${from} deps)
            if(${to} IN_LIST deps)
                message(FATAL_ERROR "Link rule broken: ${from} depends on ${to}. "
                                    "bake and runtime share only format/ and shaders/.")
            endif()
        endif()
    endforeach()
endfunction()
