# Test: the layer check refuses an upward include. A kernel file that
# includes the analysis header, and a spectral file that includes a private
# header of another folder, must both fail cmake/layers.cmake.
# Inputs: SRC (the source tree), WORK (a scratch folder).
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/kernel ${WORK}/spectral)
file(WRITE ${WORK}/kernel/up.c "#include \"dtmap/analysis.h\"\n")
file(WRITE ${WORK}/spectral/side.c "#include \"analysis-impl.h\"\n")
set(cases "kernel\;${WORK}/kernel/up.c\;may not include dtmap/analysis.h"
          "spectral\;${WORK}/spectral/side.c\;private header analysis-impl.h")
foreach(c ${cases})
  list(GET c 0 module)
  list(GET c 1 file)
  list(GET c 2 expect)
  file(WRITE ${WORK}/${module}.cmake
       "set(MODULE ${module})\nset(DIR ${WORK}/${module})\nset(ALLOWED \"${module};base\")\n"
       "set(ALLOWED_DIRS \"${WORK}/${module}\")\nset(FILES \"${file}\")\n"
       "set(OWNERS \"analysis.h=analysis;error.h=base\")\nset(STAMP ${WORK}/${module}.ok)\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -DCONF=${WORK}/${module}.cmake -P ${SRC}/cmake/layers.cmake
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "the layer check accepted ${file}")
  endif()
  string(REPLACE "\n" " " flat "${err}")
  string(REGEX REPLACE " +" " " flat "${flat}")
  if(NOT flat MATCHES "${expect}")
    message(FATAL_ERROR "unexpected message for ${file}: ${err}")
  endif()
endforeach()
message(STATUS "the layer check refused both upward includes")
