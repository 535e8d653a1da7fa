# Build options and the dependencies only some parts need. A plain
# `cmake -S . -B build && cmake --build build` is a user build: libdtmap, the
# dtmap command, its man page and completion, and the Python module; no
# tests, no benchmarks, no sanitizers, warnings reported but not fatal.
# scripts/build.sh and scripts/test.sh (and so CI) turn the developer
# options on.
option(DTM_TESTS "Build the ctest suite (needs cmocka, PLplot and Debian's python3 with gmsh, numpy, jsonschema)" OFF)
option(DTM_BENCHMARKS "Build the benchmark programs of bench/ (never run by ctest)" OFF)
option(DTM_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(DTM_WERROR "Treat compiler warnings as errors (-Werror)" OFF)
option(DTM_MPI "Build the distributed run, mpirun -n P dtmap run (needs Open MPI, PETSc and SLEPc)" OFF)
option(DTM_FUZZ "Build the libFuzzer targets of tests/fuzz/ (clang, with DTM_TESTS; scripts/fuzz.sh)" OFF)
set(DTM_PLOT AUTO CACHE STRING "PLplot for the plot of `dtmap sweep`: AUTO (when found), ON (required), OFF")
set_property(CACHE DTM_PLOT PROPERTY STRINGS AUTO ON OFF)
set(DTM_PYTHON /usr/bin/python3 CACHE FILEPATH
    "The python3 the tests drive the Python module with (Debian's, with python3-gmsh)")
# Debian's python3 searches PREFIX/lib/python3.X/dist-packages for /usr and
# /usr/local (and lib/python3/dist-packages only for /usr).
execute_process(COMMAND ${DTM_PYTHON} -c "import sys; print('lib/python%d.%d/dist-packages' % sys.version_info[:2])"
                OUTPUT_VARIABLE dtm_py_dir OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT dtm_py_dir)
  set(dtm_py_dir lib/python3/dist-packages)
endif()
set(DTM_PYTHON_INSTALL_DIR ${dtm_py_dir} CACHE STRING
    "Where the Python module dtmap goes, relative to the prefix (on Debian's python3 path for /usr/local)")

add_compile_options(-Wall -Wextra)
if(DTM_WERROR)
  add_compile_options(-Werror)
endif()
if(DTM_SANITIZE)
  set(DTM_SANITIZE_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_compile_options(${DTM_SANITIZE_FLAGS})
  add_link_options(-fsanitize=address,undefined)
endif()
if(DTM_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=address,undefined)
endif()

# PLplot draws `dtmap sweep --plot` (src/cli/plot.c). Without it the CLI is
# built with src/cli/noplot.c: the sweep writes its CSV and says why there is
# no plot.
set(DTM_HAVE_PLOT OFF)
if(NOT DTM_PLOT STREQUAL "OFF")
  pkg_check_modules(PLPLOT IMPORTED_TARGET plplot)
  if(PLPLOT_FOUND)
    set(DTM_HAVE_PLOT ON)
  elseif(DTM_PLOT STREQUAL "ON" OR DTM_TESTS)
    message(FATAL_ERROR "PLplot not found: it draws `dtmap sweep --plot`, which the tests check. "
                        "Install libplplot-dev and plplot-driver-cairo (bash scripts/setup.sh does), "
                        "or configure with -DDTM_PLOT=OFF -DDTM_TESTS=OFF.")
  else()
    message(STATUS "PLplot not found: `dtmap sweep` will write its CSV but no plot "
                   "(install libplplot-dev and plplot-driver-cairo for the plot)")
  endif()
endif()

# What the test suite needs beyond the build: cmocka for the C tests, and
# Debian's python3 with gmsh, numpy and jsonschema for the Python module's
# tests and the report schema.
if(DTM_TESTS)
  pkg_check_modules(CMOCKA IMPORTED_TARGET cmocka)
  if(NOT CMOCKA_FOUND)
    message(FATAL_ERROR "DTM_TESTS=ON needs cmocka: install libcmocka-dev (bash scripts/setup.sh does), "
                        "or configure with -DDTM_TESTS=OFF for a build without tests.")
  endif()
  execute_process(COMMAND ${DTM_PYTHON} -c "import gmsh, numpy, jsonschema" RESULT_VARIABLE py_rc
                  OUTPUT_QUIET ERROR_VARIABLE py_err)
  if(NOT py_rc EQUAL 0)
    message(FATAL_ERROR "DTM_TESTS=ON needs ${DTM_PYTHON} with the modules gmsh, numpy and jsonschema "
                        "(Debian: python3-gmsh python3-numpy python3-jsonschema; bash scripts/setup.sh installs them), "
                        "or configure with -DDTM_TESTS=OFF. Python said: ${py_err}")
  endif()
endif()

# The distributed run (src/parallel/): MPI, PETSc and SLEPc from Debian
# (openmpi-bin, libopenmpi-dev, libpetsc-real-dev, libslepc-real-dev);
# without DTM_MPI dtmap needs none of them.
if(DTM_MPI)
  find_package(MPI COMPONENTS C)
  pkg_check_modules(PETSC IMPORTED_TARGET petsc)
  pkg_check_modules(SLEPC IMPORTED_TARGET slepc)
  find_program(DTM_MPIEXEC NAMES mpirun mpiexec)
  if(NOT MPI_C_FOUND OR NOT PETSC_FOUND OR NOT SLEPC_FOUND OR NOT DTM_MPIEXEC)
    message(FATAL_ERROR "DTM_MPI=ON needs Open MPI, PETSc and SLEPc: install openmpi-bin, libopenmpi-dev, "
                        "libpetsc-real-dev and libslepc-real-dev (bash scripts/setup.sh does), "
                        "or configure with -DDTM_MPI=OFF.")
  endif()
endif()
