# cmake -D BINARY=TEST_BINARY -D FILTER=GTEST_FILTER -P expect_no_cases.cmake
# Fails, naming them, when the GoogleTest binary has cases that FILTER
# selects. With FILTER "-" and the filters of the ctest tests that run the
# binary, it fails when a case is in none of those tests.
execute_process(COMMAND ${BINARY} --gtest_list_tests --gtest_filter=${FILTER}
                OUTPUT_VARIABLE listed RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${BINARY} --gtest_list_tests failed (${status})")
endif()
string(STRIP "${listed}" listed)
if(NOT listed STREQUAL "")
  message(FATAL_ERROR "cases that no ctest test runs:\n${listed}")
endif()
message(STATUS "every case of ${BINARY} is run by a ctest test")
