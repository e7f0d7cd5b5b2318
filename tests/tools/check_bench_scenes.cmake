# ctest bench_paper_scenes_quick: runs `sinew_bench --paper-scenes` for two timed steps and
# checks what it wrote, never how fast anything was. Usage:
#   cmake -DBENCH=path/to/sinew_bench -DSCENES=assets/scenes -DOUT=dir -P this file.
# Checks: bad options and scene files (missing, malformed, two of the same name) exit 2 and
# write nothing; the run exits 0; its JSON parses and holds every assets/scenes/paper*.json by
# name, each with elements, DOFs, two timed steps, a finite end state, a positive median
# step, steps per second, h, multiple of real time and an object of worst violations; the
# summary table has its header and a row per scene. `--repeat 2` on one scene file reports two
# per-run medians, their median, and that both runs ended in the same state.
cmake_minimum_required(VERSION 3.19)  # string(JSON)

set(CHECK_NAME bench_paper_scenes_quick)
include(${CMAKE_CURRENT_LIST_DIR}/json_checks.cmake)

file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
set(json_file "${OUT}/bench.json")

# Bad input: a clear error, exit code 2, no output file.
file(WRITE "${OUT}/malformed/s.json" "{\"bodies\": [}")
file(COPY "${SCENES}/paper000_sphere_1MPa.json" DESTINATION "${OUT}/a")
file(COPY "${SCENES}/paper000_sphere_1MPa.json" DESTINATION "${OUT}/b")
foreach(bad "--steps;x" "--steps;0" "--warmup;-1" "--threads;0" "--scene;no_such_scene" "--scene;"
            "--scene-file;${OUT}/missing.json" "--scene-file;${OUT}/malformed/s.json"
            "--scene-file;${OUT}/a/paper000_sphere_1MPa.json;--scene-file;${OUT}/b/paper000_sphere_1MPa.json"
            "--scene-file;--paper-scenes" "--paper-scenes;--scene;beam56" "--linear;lu" "--repeat;0"
            "--repeat;two" "--hessian-reuse-tolerance;-1e-3" "--hessian-reuse-tolerance;x")
  execute_process(COMMAND "${BENCH}" ${bad} --out "${json_file}" RESULT_VARIABLE code OUTPUT_QUIET
                  ERROR_VARIABLE stderr)
  if(NOT code EQUAL 2 OR stderr STREQUAL "")
    fail("'${bad}': expected exit code 2 and a message, got ${code} '${stderr}'")
  endif()
  if(EXISTS "${json_file}")
    fail("'${bad}' wrote ${json_file}")
  endif()
endforeach()

run_for_json(json stdout "${json_file}" "${BENCH}" --paper-scenes --steps 2 --warmup 1 --out "${json_file}")

file(GLOB paper_files "${SCENES}/paper*.json")
list(LENGTH paper_files expected)
json_query(measured LENGTH "${json}" scenes)
if(NOT measured EQUAL expected OR expected LESS 20)
  fail("${expected} paper scenes in ${SCENES}, ${measured} in the results")
endif()
foreach(file IN LISTS paper_files)
  get_filename_component(name "${file}" NAME_WLE)
  expect_number("${json}" 0 PATH scenes ${name} elements)
  expect_number("${json}" 0 PATH scenes ${name} dofs)
  json_query(steps GET "${json}" scenes ${name} steps)
  if(NOT steps EQUAL 2)
    fail("scenes.${name}.steps is ${steps}, expected 2")
  endif()
  json_query(finite GET "${json}" scenes ${name} finite)
  if(NOT finite)
    fail("scenes.${name}: the state is not finite")
  endif()
  expect_number("${json}" 0 PATH scenes ${name} stages step median_ms)
  expect_number("${json}" 0 PATH scenes ${name} steps_per_second)
  expect_number("${json}" 0 PATH scenes ${name} realtime_factor)
  expect_number("${json}" 0 PATH scenes ${name} h)
  json_query(kind TYPE "${json}" scenes ${name} violation_max)
  if(NOT kind STREQUAL "OBJECT")
    fail("scenes.${name}.violation_max is ${kind}, expected an object")
  endif()
endforeach()
# The summary table: its header, then one row per scene.
if(NOT stdout MATCHES "scene +elements +median ms +p95 ms +steps/s +x real")
  fail("no summary table on stdout")
endif()
foreach(file IN LISTS paper_files)
  get_filename_component(name "${file}" NAME_WLE)
  string(REPLACE "." "\\." pattern "${name}")
  if(NOT stdout MATCHES "\n${pattern} +[0-9]+ +[0-9.]+ +[0-9.]+ +[0-9.]+ +[0-9.]+\n")
    fail("no summary row for ${name}")
  endif()
endforeach()
# Repeats: the same steps run twice from the start.
set(repeat_file "${OUT}/repeat.json")
run_for_json(json stdout "${repeat_file}" "${BENCH}" --scene-file "${SCENES}/paper000_sphere_1MPa.json" --steps 2
             --warmup 1 --repeat 2 --out "${repeat_file}")
json_query(repeats GET "${json}" scenes paper000_sphere_1MPa repeats)
json_query(medians LENGTH "${json}" scenes paper000_sphere_1MPa step_median_per_repeat)
json_query(identical GET "${json}" scenes paper000_sphere_1MPa repeats_identical)
if(NOT repeats EQUAL 2 OR NOT medians EQUAL 2 OR NOT identical STREQUAL "ON")
  fail("--repeat 2: repeats ${repeats}, ${medians} per-run medians, identical ${identical}")
endif()
expect_number("${json}" 0 PATH scenes paper000_sphere_1MPa step_median_of_repeats)
expect_number("${json}" 0 PATH scenes paper000_sphere_1MPa step_median_per_repeat 1)
if(NOT stdout MATCHES "step median of each of 2 repeats: [0-9.]+ [0-9.]+ ms; their median [0-9.]+ ms, every repeat ended in the same state")
  fail("--repeat 2: no per-run medians on stdout")
endif()
message(STATUS "bench_paper_scenes_quick: ${measured} paper scenes, output well-formed")
