# Register one ctest entry per test source file, filtered with doctest's --source-file.
foreach(src ${TEST_SOURCES})
  file(RELATIVE_PATH rel ${CMAKE_CURRENT_SOURCE_DIR} ${src})
  get_filename_component(name ${rel} NAME)
  add_test(NAME ${rel} COMMAND sinew_tests --source-file=*${name} --no-version)
  set_tests_properties(${rel} PROPERTIES WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
endforeach()
