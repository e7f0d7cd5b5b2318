# Register one ctest entry per test source file, filtered with doctest's --source-file.
# A file listed in SPLIT_TEST_CASES as NAME=PATTERN runs as two entries, the cases matching
# PATTERN and the rest, so that ctest -j can run them side by side: test_solve_newton.cpp
# took 127 s in one process in CI's sanitizer stage (of its 193 s), 50 s of it in one case.
# SLOW_TEST_FILES start first (ctest runs higher COST first): on a fresh clone ctest has no
# timings, and a long test started last leaves the other core idle at the end.
set(SPLIT_TEST_CASES "test_solve_newton.cpp=*preconditioned*")
set(SLOW_TEST_FILES test_solve_newton.cpp test_paper003_scrambled_cube.cpp test_paper001_finger.cpp test_paper001_beam.cpp
    test_session.cpp test_closest_point.cpp test_strain_limit_curvature.cpp test_mesh_sdf.cpp)
foreach(src ${TEST_SOURCES})
  file(RELATIVE_PATH rel ${CMAKE_CURRENT_SOURCE_DIR} ${src})
  get_filename_component(name ${rel} NAME)
  set(pattern "")
  foreach(split ${SPLIT_TEST_CASES})
    string(REPLACE "=" ";" parts ${split})
    list(GET parts 0 split_name)
    if(split_name STREQUAL name)
      list(GET parts 1 pattern)
    endif()
  endforeach()
  set(entries ${rel})
  if(pattern STREQUAL "")
    add_test(NAME ${rel} COMMAND sinew_tests --source-file=*${name} --no-version)
  else()
    add_test(NAME ${rel} COMMAND sinew_tests --source-file=*${name} --test-case-exclude=${pattern} --no-version)
    add_test(NAME ${rel}:${pattern} COMMAND sinew_tests --source-file=*${name} --test-case=${pattern} --no-version)
    list(APPEND entries ${rel}:${pattern})
  endif()
  set_tests_properties(${entries} PROPERTIES WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
  if(name IN_LIST SLOW_TEST_FILES)
    set_tests_properties(${entries} PROPERTIES COST 1000)
  endif()
endforeach()
