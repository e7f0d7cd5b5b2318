# JSON checks shared by the benchmark smoke tests (check_scale_sweep.cmake,
# check_bench_scenes.cmake): each includes this after setting CHECK_NAME, the ctest name that
# prefixes every failure.
# Paths (lists of keys and indices) print as a.b.0.c.
function(fail message)
  string(REPLACE ";" "." message "${message}")
  message(FATAL_ERROR "${CHECK_NAME}: ${message}")
endfunction()

# GET (the value) or LENGTH of the JSON at the path (a list of keys and indices), failing
# with the path if absent.
function(json_query out mode json)
  string(JSON value ERROR_VARIABLE error ${mode} "${json}" ${ARGN})
  if(error)
    fail("${ARGN}: ${error}")
  endif()
  set(${out} "${value}" PARENT_SCOPE)
endfunction()

# A JSON number at the path, > `min` (or >= with OR_EQUAL); null (a NaN or Inf written by
# the tool) and other types fail.
function(expect_number json min)
  cmake_parse_arguments(ARG "OR_EQUAL" "" "PATH" ${ARGN})
  string(JSON type ERROR_VARIABLE error TYPE "${json}" ${ARG_PATH})
  if(error OR NOT type STREQUAL "NUMBER")
    fail("${ARG_PATH}: expected a number, got ${type} ${error}")
  endif()
  string(JSON value GET "${json}" ${ARG_PATH})
  if(ARG_OR_EQUAL)
    if(value LESS min)
      fail("${ARG_PATH}: expected >= ${min}, got ${value}")
    endif()
  elseif(NOT value GREATER min)
    fail("${ARG_PATH}: expected > ${min}, got ${value}")
  endif()
endfunction()

# Runs the command (the arguments after `json_file`), which must exit 0, and reads
# `json_file`, which must parse: into `out_json`, and its stdout into `out_stdout`.
function(run_for_json out_json out_stdout json_file)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT code EQUAL 0)
    fail("exit code ${code}\n${stdout}\n${stderr}")
  endif()
  if(NOT EXISTS "${json_file}")
    fail("exit code 0 but ${json_file} was not written\n${stdout}\n${stderr}")
  endif()
  file(READ "${json_file}" json)
  string(JSON type ERROR_VARIABLE error TYPE "${json}")
  if(error)
    fail("${json_file} does not parse: ${error}")
  endif()
  set(${out_json} "${json}" PARENT_SCOPE)
  set(${out_stdout} "${stdout}" PARENT_SCOPE)
endfunction()
