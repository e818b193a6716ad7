# Runs one mpirun suite of the sanitizer tree (cmake -P: MPIEXEC NP_FLAG RANKS SUITE runs
# `MPIEXEC NP_FLAG RANKS --oversubscribe --allow-run-as-root SUITE`), and runs it once more
# when, and only when, its first run failed because LeakSanitizer's own tracer crashed at exit:
# "Tracer caught signal" and "LeakSanitizer has encountered a fatal error" (google/sanitizers#1353,
# intermittent), with GoogleTest's "[  PASSED  ]", no test failed and no leak, memory error or
# undefined behaviour reported. Any other failure fails at once; the same crash twice fails.
# Only the last run's output is printed whole, so its test and skip lines count once.
cmake_minimum_required(VERSION 3.25)

foreach(variable MPIEXEC NP_FLAG RANKS SUITE)
  if(NOT ${variable})
    message(FATAL_ERROR "retry_lsan_tracer.cmake: no ${variable} given")
  endif()
endforeach()

function(run_suite rc_var out_var err_var)
  execute_process(COMMAND ${MPIEXEC} ${NP_FLAG} ${RANKS} --oversubscribe --allow-run-as-root ${SUITE}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${rc_var} "${rc}" PARENT_SCOPE)
  set(${out_var} "${out}" PARENT_SCOPE)
  set(${err_var} "${err}" PARENT_SCOPE)
endfunction()

# True when the run's text shows the tracer's crash and nothing else wrong.
function(only_tracer_crash text result_var)
  set(crash FALSE)
  string(FIND "${text}" "Tracer caught signal" tracer)
  string(FIND "${text}" "LeakSanitizer has encountered a fatal error" fatal)
  string(FIND "${text}" "[  PASSED  ]" passed)
  if(tracer GREATER_EQUAL 0 AND fatal GREATER_EQUAL 0 AND passed GREATER_EQUAL 0)
    set(crash TRUE)
    foreach(other "[  FAILED  ]" "detected memory leaks" "ERROR: AddressSanitizer" "runtime error:")
      string(FIND "${text}" "${other}" at)
      if(at GREATER_EQUAL 0)
        set(crash FALSE)
      endif()
    endforeach()
  endif()
  set(${result_var} ${crash} PARENT_SCOPE)
endfunction()

run_suite(rc out err)
if(NOT rc EQUAL 0)
  only_tracer_crash("${out}\n${err}" retry)
  if(retry)
    string(REGEX MATCHALL "[^\n]*(Tracer caught signal|LeakSanitizer has encountered)[^\n]*" crash_lines "${err}\n${out}")
    list(JOIN crash_lines "\n" crash_lines)
    message("retry_lsan_tracer: the first run exited ${rc} with every test passed, only because "
            "LeakSanitizer's tracer crashed at exit (google/sanitizers#1353):\n${crash_lines}\n"
            "retry_lsan_tracer: running the suite once more")
    run_suite(rc out err)
  endif()
endif()
message("${out}")
message("${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the suite exited ${rc}")
endif()
