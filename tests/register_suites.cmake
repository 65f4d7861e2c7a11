# Run after nearcap_tests is linked (cmake -P): lists its tests and writes
# one ctest entry per test suite, named after the suite, into OUTPUT, which
# ctest includes.  The sanitizer build registers its tests so: there a start
# of nearcap_tests costs about a third of a second (UBSan's records relocated,
# LeakSanitizer's scan at exit), paid once a suite instead of once a test.
# Arguments: TEST_EXECUTABLE, OUTPUT, EXCLUDED (suites registered elsewhere,
# separated by commas), TIMEOUT (seconds an entry may run).
cmake_minimum_required(VERSION 3.16)
string(REPLACE "," ";" EXCLUDED "${EXCLUDED}")
execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
                OUTPUT_VARIABLE listing RESULT_VARIABLE status TIMEOUT 60)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed (${status}): ${listing}")
endif()
string(REPLACE ";" "\\;" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(script "")
set(count 0)
foreach(line IN LISTS lines)
  # A suite's line starts in the first column and ends its name with a dot
  # (a typed suite's line goes on with a comment); its tests' lines are indented.
  if(line MATCHES "^([^ #]+)\\.( |$)")
    set(suite "${CMAKE_MATCH_1}")
    if(NOT suite IN_LIST EXCLUDED)
      string(APPEND script "add_test([==[${suite}]==] \"${TEST_EXECUTABLE}\" [==[--gtest_filter=${suite}.*]==])\n"
                           "set_tests_properties([==[${suite}]==] PROPERTIES TIMEOUT ${TIMEOUT})\n")
      math(EXPR count "${count} + 1")
    endif()
  endif()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests listed no test suite")
endif()
file(WRITE "${OUTPUT}" "${script}")
