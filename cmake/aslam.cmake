# aslam_add_test(NAME SOURCES src... LIBS lib... [LABEL long]): one GoogleTest binary, its
# cases registered with CTest one by one (with LABEL long: left to scripts/test-long).
function(aslam_add_test name)
  cmake_parse_arguments(ARG "" "LABEL" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE ASLAM_SOURCE_DIR="${ASLAM_SOURCE_DIR}")
  set(labels "")
  if(ARG_LABEL)
    set(labels LABELS ${ARG_LABEL})
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 300 ${labels})
endfunction()

# aslam_add_benchmark(NAME SOURCES src... LIBS lib...): a Google Benchmark
# binary; built by default (but in a sanitized build, which measures nothing: build it by
# name there), never run by ctest.
function(aslam_add_benchmark name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  if(ASLAM_SANITIZE)
    set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL TRUE)
  endif()
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} benchmark::benchmark)
  target_compile_definitions(${name} PRIVATE ASLAM_SOURCE_DIR="${ASLAM_SOURCE_DIR}")
endfunction()
