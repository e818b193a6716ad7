# frnn_mpi_bench at 1 and 2 ranks (cmake -P): each run must exit 0 and report its rank count,
# the single-process grid at 1 rank must find pairs, and the distributed search at 1 and at 2
# ranks exactly as many. Variables: MPIEXEC, BENCH (the executable), ARGS (its options).
cmake_minimum_required(VERSION 3.25)

separate_arguments(args UNIX_COMMAND "${ARGS}")

function(run_bench ranks out_var)
  execute_process(COMMAND ${MPIEXEC} -np ${ranks} --oversubscribe --allow-run-as-root ${BENCH} ${args}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 100)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "frnn_mpi_bench at ${ranks} ranks exited ${rc}:\n${out}\n${err}")
  endif()
  string(STRIP "${out}" out)
  string(JSON reported ERROR_VARIABLE bad GET "${out}" ranks)
  if(bad OR NOT reported EQUAL ranks)
    message(FATAL_ERROR "frnn_mpi_bench at ${ranks} ranks printed no rank count ${ranks}: ${out} ${bad}")
  endif()
  message(STATUS "${ranks} ranks: ${out}")
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

run_bench(1 one)
run_bench(2 two)
string(JSON serial GET "${one}" serial_pairs)
string(JSON pairs_one GET "${one}" pairs)
string(JSON pairs_two GET "${two}" pairs)
if(NOT serial GREATER 0)
  message(FATAL_ERROR "the single-process grid found no pairs (${serial})")
endif()
if(NOT pairs_one EQUAL serial OR NOT pairs_two EQUAL serial)
  message(FATAL_ERROR "pairs: single process ${serial}, 1 rank ${pairs_one}, 2 ranks ${pairs_two}")
endif()
message(STATUS "pairs: ${serial} at 1 process, 1 rank and 2 ranks")
