# The module system of dtmap's build: dtm_module() turns one folder into an
# OBJECT library that sees the public headers, its own folder and the
# folders of the modules it USES (and, transitively, theirs); nothing else.
# dtm_header_owners() says which module owns each public header, and then
# every module gets a build-time layer check (cmake/layers.cmake) that its
# object library depends on, so an include that reaches up fails the build.

# dtm_module(<name> <folder> USES <module>... [HEADERS_ONLY] [EXCLUDE <regex>])
# EXCLUDE drops the sources whose path matches regex from the build (a
# module built two ways, e.g. src/parallel/ with or without MPI); the layer
# check still reads them all.
function(dtm_module name dir)
  cmake_parse_arguments(M "HEADERS_ONLY" "EXCLUDE" "USES" ${ARGN})
  set(allowed ${name})
  set(dirs ${CMAKE_SOURCE_DIR}/${dir})
  foreach(d ${M_USES})
    get_property(da GLOBAL PROPERTY DTM_ALLOWED_${d})
    get_property(dd GLOBAL PROPERTY DTM_DIRS_${d})
    list(APPEND allowed ${da})
    list(APPEND dirs ${dd})
  endforeach()
  list(REMOVE_DUPLICATES allowed)
  list(REMOVE_DUPLICATES dirs)
  set_property(GLOBAL APPEND PROPERTY DTM_MODULES ${name})
  set_property(GLOBAL PROPERTY DTM_DIR_${name} ${CMAKE_SOURCE_DIR}/${dir})
  set_property(GLOBAL PROPERTY DTM_ALLOWED_${name} ${allowed})
  set_property(GLOBAL PROPERTY DTM_DIRS_${name} ${dirs})
  set_property(GLOBAL PROPERTY DTM_HEADERS_ONLY_${name} ${M_HEADERS_ONLY})
  if(M_HEADERS_ONLY)
    return()
  endif()
  file(GLOB_RECURSE srcs CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/${dir}/*.c)
  list(FILTER srcs EXCLUDE REGEX "/plugins/examples/")
  if(M_EXCLUDE)
    list(FILTER srcs EXCLUDE REGEX "${M_EXCLUDE}")
  endif()
  add_library(dtm_${name} OBJECT ${srcs})
  set_target_properties(dtm_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON C_VISIBILITY_PRESET hidden)
  target_include_directories(dtm_${name} PRIVATE ${CMAKE_SOURCE_DIR}/include ${dirs})
  target_compile_definitions(dtm_${name} PRIVATE _POSIX_C_SOURCE=200809L)
  set_property(GLOBAL APPEND PROPERTY DTM_SOURCE_DIRS ${CMAKE_SOURCE_DIR}/${dir})
endfunction()

# dtm_header_owners(<header>=<module>...): then the layer checks.
function(dtm_header_owners)
  get_property(modules GLOBAL PROPERTY DTM_MODULES)
  foreach(m ${modules})
    get_property(dir GLOBAL PROPERTY DTM_DIR_${m})
    get_property(allowed GLOBAL PROPERTY DTM_ALLOWED_${m})
    get_property(dirs GLOBAL PROPERTY DTM_DIRS_${m})
    get_property(hdr_only GLOBAL PROPERTY DTM_HEADERS_ONLY_${m})
    set(files "")
    if(NOT hdr_only)
      file(GLOB_RECURSE files CONFIGURE_DEPENDS ${dir}/*.c ${dir}/*.h)
      list(FILTER files EXCLUDE REGEX "/plugins/examples/")
    endif()
    foreach(pair ${ARGN})
      if(pair MATCHES "^(.+)=${m}$")
        list(APPEND files ${CMAKE_SOURCE_DIR}/include/dtmap/${CMAKE_MATCH_1})
      endif()
    endforeach()
    set(conf ${CMAKE_BINARY_DIR}/layers/${m}.cmake)
    set(stamp ${CMAKE_BINARY_DIR}/layers/${m}.ok)
    file(WRITE ${conf} "set(MODULE \"${m}\")\nset(DIR \"${dir}\")\nset(ALLOWED \"${allowed}\")\n"
                       "set(ALLOWED_DIRS \"${dirs}\")\nset(FILES \"${files}\")\nset(OWNERS \"${ARGN}\")\n"
                       "set(STAMP \"${stamp}\")\n")
    add_custom_command(OUTPUT ${stamp}
      COMMAND ${CMAKE_COMMAND} -DCONF=${conf} -P ${CMAKE_SOURCE_DIR}/cmake/layers.cmake
      DEPENDS ${files} ${conf} ${CMAKE_SOURCE_DIR}/cmake/layers.cmake
      COMMENT "Checking the layers of module ${m}")
    add_custom_target(dtm_${m}_layers DEPENDS ${stamp})
    if(TARGET dtm_${m})
      add_dependencies(dtm_${m} dtm_${m}_layers)
    else()
      set_property(GLOBAL APPEND PROPERTY DTM_HEADER_CHECKS dtm_${m}_layers)
    endif()
  endforeach()
endfunction()
