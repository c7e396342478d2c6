# GNU Octave reads the run.mat of a short paper run and finds the numbers of
# its CSV files (tests/octave/check_run_mat.m). Run by CTest as
#   cmake -DCLI=<ipmc-swim> -DSOURCE_DIR=<project> -DWORK_DIR=<scratch> -P check_run_mat.cmake
# The scratch folder is removed whatever the outcome.
file(REMOVE_RECURSE ${WORK_DIR})
# scenarios/paper.toml made quick: one 10 s cycle instead of three of 100 s.
execute_process(
  COMMAND ${CLI} run ${SOURCE_DIR}/scenarios/paper.toml --cycles 1
          --set waveform.frequency_Hz=0.1 --out ${WORK_DIR}/run --format mat
  RESULT_VARIABLE run_status OUTPUT_QUIET ERROR_VARIABLE run_error)
if(run_status EQUAL 0)
  execute_process(
    COMMAND octave --no-gui --quiet --no-init-file --no-history --eval
            "addpath('${SOURCE_DIR}/tests/octave'); check_run_mat('${WORK_DIR}/run')"
    RESULT_VARIABLE octave_status OUTPUT_VARIABLE octave_output ERROR_VARIABLE octave_error)
endif()
file(REMOVE_RECURSE ${WORK_DIR})
if(NOT run_status EQUAL 0)
  message(FATAL_ERROR "ipmc-swim run failed: ${run_error}")
endif()
if(NOT octave_status EQUAL 0)
  message(FATAL_ERROR "octave could not read run.mat as the CSV: ${octave_output}${octave_error}")
endif()
message(STATUS "${octave_output}")
