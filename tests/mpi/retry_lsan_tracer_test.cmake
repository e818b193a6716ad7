# Checks retry_lsan_tracer.cmake (cmake -P) with fake_mpiexec.sh in place of mpiexec: it runs the
# suite twice only after the tracer's crash with every test passed, and fails on anything else.
cmake_minimum_required(VERSION 3.25)
set(here ${CMAKE_CURRENT_LIST_DIR})
if(DEFINED ENV{TMPDIR})
  set(tmp $ENV{TMPDIR})
else()
  set(tmp /tmp)
endif()
string(RANDOM LENGTH 12 tag)
set(calls_file ${tmp}/retry-lsan-tracer-${tag}.calls)
set(problems "")

# The wrapper on SCENARIO must succeed (want_ok TRUE) or fail (FALSE) after want_calls runs.
function(expect scenario want_ok want_calls)
  file(REMOVE ${calls_file})
  execute_process(COMMAND ${CMAKE_COMMAND} -E env FAKE_MPIEXEC_CALLS=${calls_file}
                          ${CMAKE_COMMAND} -DMPIEXEC=${here}/fake_mpiexec.sh -DNP_FLAG=-n -DRANKS=3
                          -DSUITE=${scenario} -P ${here}/retry_lsan_tracer.cmake
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  file(READ ${calls_file} calls)
  string(STRIP "${calls}" calls)
  if(rc EQUAL 0)
    set(ok TRUE)
  else()
    set(ok FALSE)
  endif()
  if(NOT ok STREQUAL want_ok OR NOT calls EQUAL want_calls)
    set(problems "${problems}\n  ${scenario}: exit ${rc} after ${calls} runs, want success ${want_ok} after ${want_calls}"
        PARENT_SCOPE)
  endif()
endfunction()

expect(tracer-once TRUE 2)
expect(tracer-always FALSE 2)
expect(failed-then-tracer FALSE 1)
expect(leak FALSE 1)
expect(no-tests FALSE 1)
file(REMOVE ${calls_file})
if(problems)
  message(FATAL_ERROR "retry_lsan_tracer.cmake:${problems}")
endif()
message(STATUS "retry_lsan_tracer.cmake: 5 scenarios as expected")
