/* test.h - a tiny test harness: CHECK and CHECK_NEAR count results; test_finish prints the
 * closing line `N passed, N failed` and returns the exit status. */
#ifndef RAD_TEST_H
#define RAD_TEST_H

#include <math.h>
#include <stdio.h>

static int test_passed, test_failed;

#define CHECK(condition)                                                                          \
    do {                                                                                          \
        if (condition) {                                                                          \
            ++test_passed;                                                                        \
        } else {                                                                                  \
            ++test_failed;                                                                        \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #condition);        \
        }                                                                                         \
    } while (0)

#define CHECK_NEAR(actual, expected, tolerance)                                                   \
    do {                                                                                          \
        double test_a = (actual), test_e = (expected), test_t = (tolerance);                      \
        if (fabs(test_a - test_e) <= test_t) {                                                    \
            ++test_passed;                                                                        \
        } else {                                                                                  \
            ++test_failed;                                                                        \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.12g, expected %.12g +- %.3g\n",    \
                    __FILE__, __LINE__, #actual, test_a, test_e, test_t);                         \
        }                                                                                         \
    } while (0)

static inline int test_finish(void) {
    printf("%d passed, %d failed\n", test_passed, test_failed);
    return test_failed ? 1 : 0;
}

#endif
