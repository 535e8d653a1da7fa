# Run the built dtmap at build time and keep its standard output as a file
# (cmake -P): the man page and the bash completion are printed by the CLI
# from the same command tables as --help (`dtmap --generate man`), so the
# three never disagree. Inputs: EXE (the dtmap binary), WHAT (man or
# bash-completion), OUT (the file to write).
set(ENV{ASAN_OPTIONS} "detect_leaks=0") # a sanitizer build runs this too
get_filename_component(dir ${OUT} DIRECTORY)
file(MAKE_DIRECTORY ${dir})
execute_process(COMMAND ${EXE} --generate ${WHAT} OUTPUT_FILE ${OUT}.tmp RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  file(REMOVE ${OUT}.tmp)
  message(FATAL_ERROR "${EXE} --generate ${WHAT} failed (${rc}): ${err}")
endif()
file(RENAME ${OUT}.tmp ${OUT})
