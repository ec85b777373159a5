# Included by ctest after the tests are discovered (TEST_INCLUDE_FILES, tests/CMakeLists.txt):
# the tests named in tests/sanitize-skip.txt, the slowest in the release build or under ASan,
# get a high COST, so ctest starts them first. Without a previous run's timings (a fresh
# build, as in CI) it starts tests in the order they are listed, and a long test listed near
# the end kept one core busy after the other had finished (about 30 s of a 8-minute run).
file(STRINGS "${CMAKE_CURRENT_LIST_DIR}/sanitize-skip.txt" fvx_slow_tests REGEX "^[A-Za-z]")
foreach(fvx_test IN LISTS fvx_slow_tests)
  set_tests_properties(${fvx_test} PROPERTIES COST 1000)
endforeach()
