# Layer check, run at build time for one module (cmake -P): every quoted
# #include of the module's files must be
#   - a public header "dtmap/X.h" owned by the module itself or by a module
#     it may use (ALLOWED, the transitive closure of its declared links);
#   - a private header "*-impl.h" that lives in the including file's own
#     folder (private headers never cross a folder);
#   - any other header found in the module's folder or in a folder of a
#     module it may use.
# Inputs, set by the file CONF: MODULE, DIR (the module's folder), ALLOWED (;-list of modules),
# ALLOWED_DIRS (their folders), FILES (;-list of files), OWNERS (;-list of
# header=module pairs), STAMP (written on success).
cmake_minimum_required(VERSION 3.18)
include(${CONF})

foreach(pair IN LISTS OWNERS)
  string(REPLACE "=" ";" kv "${pair}")
  list(GET kv 0 header)
  list(GET kv 1 owner)
  set(owner_of_${header} ${owner})
endforeach()

set(errors "")
foreach(file IN LISTS FILES)
  get_filename_component(here "${file}" DIRECTORY)
  file(STRINGS "${file}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" inc "${line}")
    if(inc MATCHES "^dtmap/(.+)$")
      set(h "${CMAKE_MATCH_1}")
      if(NOT DEFINED owner_of_${h})
        string(APPEND errors "${file}: includes ${inc}, which no module owns (add it to DTM_HEADER_OWNERS)\n")
      elseif(NOT owner_of_${h} IN_LIST ALLOWED)
        string(APPEND errors "${file}: module '${MODULE}' may not include ${inc} (module '${owner_of_${h}}' is not below it)\n")
      endif()
    elseif(inc MATCHES "-impl\\.h$")
      if(NOT EXISTS "${here}/${inc}")
        string(APPEND errors "${file}: includes the private header ${inc} of another folder\n")
      endif()
    else()
      set(found FALSE)
      if(EXISTS "${here}/${inc}" OR EXISTS "${DIR}/${inc}")
        set(found TRUE)
      endif()
      foreach(d IN LISTS ALLOWED_DIRS)
        if(EXISTS "${d}/${inc}")
          set(found TRUE)
        endif()
      endforeach()
      if(NOT found)
        string(APPEND errors "${file}: includes ${inc}, which is not in '${MODULE}' or a module below it\n")
      endif()
    endif()
  endforeach()
endforeach()

if(errors)
  message(FATAL_ERROR "layer check failed for module '${MODULE}':\n${errors}(see docs/architecture.md)")
endif()
file(WRITE "${STAMP}" "ok\n")
