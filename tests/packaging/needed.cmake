# Test: libdtmap and the dtmap program do not link CHOLMOD (nor what it
# pulls in): it is loaded when the certificate or --modes first needs it
# (src/spectral/cholmod_dl.c), so that no command pays 20 ms of dynamic
# linking for it at start. Inputs: LIB (libdtmap.so), CLI (dtmap),
# READELF (the readelf program).
foreach(f ${LIB} ${CLI})
  execute_process(COMMAND ${READELF} -d ${f} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "readelf failed on ${f}")
  endif()
  string(REGEX MATCHALL "\\(NEEDED\\)[^\n]*" needed "${out}")
  foreach(n ${needed})
    if(n MATCHES "cholmod|suitesparse|blas|lapack|gfortran")
      message(FATAL_ERROR "${f} links ${n}: CHOLMOD is to be loaded at first use, not at start")
    endif()
  endforeach()
  list(LENGTH needed count)
  message(STATUS "${f}: ${count} libraries needed, CHOLMOD not among them")
endforeach()
