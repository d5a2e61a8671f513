/* A double-precision "near" assertion for cmocka tests.
 *
 * cmocka's assert_float_equal converts both values to float, so a tolerance
 * below about 1e-7 relative to the values compares nothing finer than float
 * rounding. assert_double_near compares in double: it fails when
 * |a - b| > tol, and when either value is NaN. Include it after <cmocka.h>. */
#ifndef PLUMAGE_TESTS_ASSERT_DOUBLE_H
#define PLUMAGE_TESTS_ASSERT_DOUBLE_H

#include <math.h>

static inline void plm_assert_double_near(double a, double b, double tol,
                                          const char *a_text, const char *b_text,
                                          const char *file, int line)
{
    if (fabs(a - b) <= tol) /* false for NaN, so NaN fails */
        return;
    print_error("%s = %.17g\n%s = %.17g\ndiffer by %.3g, allowed %.3g\n",
                a_text, a, b_text, b, fabs(a - b), tol);
    _fail(file, line);
}

#define assert_double_near(a, b, tol) \
    plm_assert_double_near((a), (b), (tol), #a, #b, __FILE__, __LINE__)

#endif
