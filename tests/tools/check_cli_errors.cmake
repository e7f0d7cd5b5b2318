# ctest tools_cli_errors: the benchmark programs refuse bad options with exit code 2 and one
# line on stderr that names the program, the option and the value given (never an abort,
# never a number read from half of it), and --help exits 0 describing every option. Only
# bad-argument and --help runs: nothing is benchmarked. Usage:
#   cmake -DHYPERELASTIC=... -DCONTACT=... -DRENDER=... -DWORK_PRECISION=... -DKERNELS=... -DSINGLE_SOLVE=... -DREALTIME=... -DFORK_JOIN=... -DASSEMBLY=... -DOUT=dir -P this file.
cmake_minimum_required(VERSION 3.19)

set(CHECK_NAME tools_cli_errors)
include(${CMAKE_CURRENT_LIST_DIR}/json_checks.cmake)  # fail()

file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
set(out_file "${OUT}/out.json")

# `program` run with the arguments after `option` (which include it) exits 2, writes nothing,
# and prints one line "NAME: ..." naming `option` and, when one follows it, its value. The
# timeout fails a program that took the bad value and started its benchmark.
function(expect_refused program option)
  get_filename_component(name "${program}" NAME_WE)
  execute_process(COMMAND "${program}" --out "${out_file}" ${ARGN} WORKING_DIRECTORY "${OUT}" TIMEOUT 20
                  RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE stderr)
  string(REPLACE ";" " " args "${ARGN}")
  if(NOT code STREQUAL "2")
    fail("${name} ${args}: expected exit code 2, got '${code}' (stderr '${stderr}')")
  endif()
  string(FIND "${stderr}" "${option}" at_option)
  list(FIND ARGN "${option}" index)
  math(EXPR index "${index} + 1")
  list(LENGTH ARGN count)
  set(at_value 0)
  if(index GREATER 0 AND index LESS count)  # "--option VALUE", not "--option=VALUE" or a last "--option"
    list(GET ARGN ${index} value)
    string(FIND "${stderr}" "'${value}'" at_value)
  endif()
  if(NOT stderr MATCHES "^${name}: [^\n]+\n$" OR at_option EQUAL -1 OR at_value EQUAL -1)
    fail("${name} ${args}: expected one line '${name}: ...' naming ${option} and its value, got '${stderr}'")
  endif()
  if(EXISTS "${out_file}")
    fail("${name} ${args} wrote ${out_file}")
  endif()
endfunction()

# --help exits 0 and lists every option on stdout.
function(expect_help program)
  get_filename_component(name "${program}" NAME_WE)
  execute_process(COMMAND "${program}" --help WORKING_DIRECTORY "${OUT}" TIMEOUT 20
                  RESULT_VARIABLE code OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT code STREQUAL "0")
    fail("${name} --help: expected exit code 0, got '${code}' (stderr '${stderr}')")
  endif()
  foreach(option IN LISTS ARGN)
    string(FIND "${stdout}" "${option}" at)
    if(at EQUAL -1)
      fail("${name} --help does not describe ${option}")
    endif()
  endforeach()
endfunction()

expect_help("${HYPERELASTIC}" --steps --warmup --delassus-reuse --refactor-interval --stale-factor-precision
            --hessian-reuse-tolerance --mesh --mode
            --threads --out)
foreach(bad "--steps;abc" "--steps;3abc" "--steps;0" "--warmup;-1" "--warmup;1.5" "--delassus-reuse;x"
            "--delassus-reuse;0" "--refactor-interval;8x" "--threads;abc" "--threads;3" "--mesh;bunny"
            "--mode;newton" "--stale-factor-precision;half" "--hessian-reuse-tolerance;-1e-3"
            "--hessian-reuse-tolerance;x" "--hessian-reuse-tolerance;nan" "--bogus")
  list(GET bad 0 option)
  expect_refused("${HYPERELASTIC}" ${option} ${bad})
endforeach()
expect_refused("${HYPERELASTIC}" --steps --steps)  # no value

expect_help("${ASSEMBLY}" --repeats --settle --mesh --threads --out)
foreach(bad "--repeats;abc" "--repeats;0" "--settle;-1" "--settle;1.5" "--mesh;bunny" "--threads;3" "--threads;abc"
            "--bogus")
  list(GET bad 0 option)
  expect_refused("${ASSEMBLY}" ${option} ${bad})
endforeach()

expect_help("${CONTACT}" --repeats --threads --grid --brute-force-bodies --out)
foreach(bad "--repeats;abc" "--repeats;3abc" "--repeats;0" "--threads;two" "--threads;2x" "--grid;0" "--grid;1.5"
            "--brute-force-bodies=yes")
  list(GET bad 0 option)
  string(REGEX REPLACE "=.*" "" option "${option}")
  expect_refused("${CONTACT}" ${option} ${bad})
endforeach()

expect_help("${RENDER}" --scene --frames --warmup --size --samples --out)
foreach(bad "--frames;abc" "--frames;60fps" "--frames;0" "--warmup;x" "--samples;-1" "--samples;4x" "--size;640"
            "--size;0x480" "--size;640xabc" "--size;640x480x2" "--size;x480")
  list(GET bad 0 option)
  expect_refused("${RENDER}" ${option} ${bad})
endforeach()

expect_help("${WORK_PRECISION}" --quick --out --only --threads --cache --fresh)
foreach(bad "--threads;abc" "--threads;3abc" "--threads;0")
  expect_refused("${WORK_PRECISION}" --threads ${bad})
endforeach()

expect_help("${KERNELS}" --repeats --out)
foreach(bad "--repeats;abc" "--repeats;3abc" "--repeats;0" "--bogus")
  list(GET bad 0 option)
  expect_refused("${KERNELS}" ${option} ${bad})
endforeach()

expect_help("${SINGLE_SOLVE}" --repeats --threads --out)
foreach(bad "--repeats;abc" "--repeats;0" "--threads;0" "--threads;2x" "--bogus")
  list(GET bad 0 option)
  expect_refused("${SINGLE_SOLVE}" ${option} ${bad})
endforeach()

expect_help("${FORK_JOIN}" --rounds --out)
foreach(bad "--rounds;abc" "--rounds;9" "--rounds;1e3" "--bogus")
  list(GET bad 0 option)
  expect_refused("${FORK_JOIN}" ${option} ${bad})
endforeach()

expect_help("${REALTIME}" --size --scene-file --frames --budget --threads --out)
file(WRITE "${OUT}/broken.json" "{\"bodies\": [")
foreach(bad "--size;abc" "--size;0" "--frames;1.5" "--frames;0" "--budget;0" "--budget;fast" "--threads;0" "--bogus"
            "--size;100;--scene-file;none.json" "--scene-file;none.json" "--scene-file;${OUT}/broken.json"
            "--out;${OUT}/no/such/folder/x.json")
  list(GET bad 0 option)
  expect_refused("${REALTIME}" ${option} ${bad})
endforeach()

message(STATUS "tools_cli_errors: bad options refused with exit code 2, --help complete")
