/* Assertion macros for rodsolve test programs: they add the file and line of the assertion.
   Used with tests/support/assert.F90 (module rs_test_assert). */
#define CHECK_TRUE(cond, msg) call assert_true(cond, msg, __FILE__, __LINE__)
#define CHECK_CLOSE(actual, expected, atol, rtol, msg) call assert_close(actual, expected, atol, rtol, msg, __FILE__, __LINE__)
#define CHECK_EQUAL(actual, expected, msg) call assert_equal(actual, expected, msg, __FILE__, __LINE__)
#define CHECK_CONTAINS(text, fragment, msg) call assert_contains(text, fragment, msg, __FILE__, __LINE__)
