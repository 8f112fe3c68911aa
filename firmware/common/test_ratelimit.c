/* The log-line budget: a burst gives at most `burst` lines per interval, and every suppressed
 * event is reported exactly once, by the next allowed line or by a flush after the interval. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "common/ratelimit.h"

#define MS 1000000LL

static void test_burst_is_bounded_and_counted(void **state)
{
    (void)state;
    struct mn_ratelimit rl;
    mn_ratelimit_init(&rl, 1000 * MS, 5);
    uint64_t lines = 0, reported = 0, before;
    /* 10 000 rejected datagrams within 0.5 s: five lines, 9995 suppressed. */
    for (int i = 0; i < 10000; i++) {
        if (mn_ratelimit_allow(&rl, 1 * MS + i * 50000LL, &before))
            lines++;
        reported += before;
    }
    assert_int_equal(lines, 5);
    assert_int_equal(reported, 0);
    assert_int_equal(mn_ratelimit_flush(&rl, 900 * MS), 0); /* the interval is not over */
    /* The next event after the interval tells of the 9995 before its own line. */
    assert_true(mn_ratelimit_allow(&rl, 1001 * MS, &before));
    assert_int_equal(before, 9995);
    assert_true(mn_ratelimit_allow(&rl, 1002 * MS, &before));
    assert_int_equal(before, 0);
}

static void test_flush_reports_once_after_the_interval(void **state)
{
    (void)state;
    struct mn_ratelimit rl;
    mn_ratelimit_init(&rl, 100 * MS, 2);
    uint64_t before;
    for (int i = 0; i < 7; i++)
        mn_ratelimit_allow(&rl, 10 * MS, &before);
    assert_int_equal(mn_ratelimit_flush(&rl, 50 * MS), 0);
    assert_int_equal(mn_ratelimit_flush(&rl, 110 * MS), 5);
    assert_int_equal(mn_ratelimit_flush(&rl, 500 * MS), 0);
    assert_true(mn_ratelimit_allow(&rl, 600 * MS, &before));
    assert_int_equal(before, 0);
}

static void test_slow_events_are_never_suppressed(void **state)
{
    (void)state;
    struct mn_ratelimit rl;
    mn_ratelimit_init(&rl, 1000 * MS, 1);
    uint64_t before;
    for (int i = 0; i < 20; i++) {
        assert_true(mn_ratelimit_allow(&rl, (1 + i) * 1000 * MS, &before));
        assert_int_equal(before, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_burst_is_bounded_and_counted),
        cmocka_unit_test(test_flush_reports_once_after_the_interval),
        cmocka_unit_test(test_slow_events_are_never_suppressed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
