# The pytest suites of tests/ (mpi, serve, python): Debian's interpreter, and whether it has the
# modules a suite imports. One probe for all, so the suites skip alike, saying why.
#
# fixpoint_pytest_ready(OUT WHAT MODULE...): OUT is true when ${Python_EXECUTABLE} (Debian's
# /usr/bin/python3 unless the build chose one) imports every MODULE; otherwise false, with a
# warning "<python> cannot import <modules>: no WHAT tests".
function(fixpoint_pytest_ready out what)
  if(NOT Python_EXECUTABLE)
    find_program(Python_EXECUTABLE NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
  endif()
  string(REPLACE ";" ", " modules "${ARGN}")
  execute_process(COMMAND ${Python_EXECUTABLE} -c "import ${modules}"
    RESULT_VARIABLE probe OUTPUT_QUIET ERROR_QUIET)
  if(probe EQUAL 0)
    set(${out} TRUE PARENT_SCOPE)
  else()
    message(WARNING "${Python_EXECUTABLE} cannot import ${modules}: no ${what} tests")
    set(${out} FALSE PARENT_SCOPE)
  endif()
endfunction()
