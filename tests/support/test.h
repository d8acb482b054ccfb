/* test.h - the unit-test runner: TEST(name) { CHECK(...); } in tests/unit/test_*.c.
 *
 * Each test file is one executable (test_main.c supplies main). A failed CHECK records the
 * failure with file and line and returns from the test; the executable exits non-zero when
 * any test failed and prints "N passed, N failed". Run one test with `test_x name`. */
#ifndef TEXOPT_TEST_H
#define TEXOPT_TEST_H

#include <math.h>
#include <stdio.h>

typedef void (*test_fn)(void);
void test_register(const char *name, test_fn fn);
void test_fail(const char *file, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
int test_failed_now(void);

#define TEST(name)                                                                                                     \
    static void name(void);                                                                                            \
    __attribute__((constructor)) static void register_##name(void)                                                     \
    {                                                                                                                  \
        test_register(#name, name);                                                                                    \
    }                                                                                                                  \
    static void name(void)

#define CHECK(cond)                                                                                                    \
    do {                                                                                                               \
        if (!(cond)) {                                                                                                 \
            test_fail(__FILE__, __LINE__, "CHECK(%s)", #cond);                                                         \
            return;                                                                                                    \
        }                                                                                                              \
    } while (0)

#define CHECK_MSG(cond, ...)                                                                                           \
    do {                                                                                                               \
        if (!(cond)) {                                                                                                 \
            test_fail(__FILE__, __LINE__, __VA_ARGS__);                                                                \
            return;                                                                                                    \
        }                                                                                                              \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                                          \
    do {                                                                                                               \
        double check_a_ = (double)(a), check_b_ = (double)(b);                                                         \
        if (!(fabs(check_a_ - check_b_) <= (tol))) {                                                                   \
            test_fail(__FILE__, __LINE__, "CHECK_NEAR(%s, %s): %.9g vs %.9g (tol %g)", #a, #b, check_a_, check_b_,     \
                      (double)(tol));                                                                                  \
            return;                                                                                                    \
        }                                                                                                              \
    } while (0)

#define CHECK_EQ_INT(a, b)                                                                                             \
    do {                                                                                                               \
        long long check_a_ = (long long)(a), check_b_ = (long long)(b);                                                \
        if (check_a_ != check_b_) {                                                                                    \
            test_fail(__FILE__, __LINE__, "CHECK_EQ_INT(%s, %s): %lld vs %lld", #a, #b, check_a_, check_b_);           \
            return;                                                                                                    \
        }                                                                                                              \
    } while (0)

/* Checks a texopt_status is TEXOPT_OK and prints the message buffer when it is not. */
#define CHECK_OK(status, errbuf)                                                                                       \
    do {                                                                                                               \
        int check_s_ = (int)(status);                                                                                  \
        if (check_s_ != 0) {                                                                                           \
            test_fail(__FILE__, __LINE__, "%s returned %d: %s", #status, check_s_, (errbuf));                          \
            return;                                                                                                    \
        }                                                                                                              \
    } while (0)

#endif
