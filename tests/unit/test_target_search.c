/* test_target_search.c - the target_loss budget search and the equal-loss cost (target_search.h, compare.h). */
#include <math.h>

#include "compare.h"
#include "target_search.h"
#include "test.h"

/* A loss that halves with every doubling of the cost: q(c) = 0.02 / sqrt(c). */
typedef struct counter {
    int calls;
    double last_cost;
} counter;

static texopt_status sqrt_loss(void *user, double cost, double *q, char *err, size_t len)
{
    (void)err, (void)len;
    counter *c = user;
    c->calls++;
    c->last_cost = cost;
    *q = 0.02 / sqrt(cost);
    return TEXOPT_OK;
}

static texopt_status failing_loss(void *user, double cost, double *q, char *err, size_t len)
{
    (void)user, (void)cost, (void)q;
    return texopt_fail(err, len, TEXOPT_E_RENDER, "no renderer");
}

TEST(search_finds_the_smallest_cost_meeting_the_target)
{
    /* q <= 0.04 exactly when c >= 0.25. */
    counter c = {0};
    texopt_target_search s;
    char err[128] = "";
    CHECK_OK(texopt_search_target_loss(sqrt_loss, &c, 0.04, 0.01, 1.0, 0.01, 30, &s, err, sizeof err), err);
    CHECK(s.reached);
    CHECK(s.relative_cost >= 0.25);
    CHECK(s.relative_cost <= 0.25 * 1.01);
    CHECK(s.q <= 0.04);
    CHECK_EQ_INT(s.evaluations, c.calls);
    /* log2(100) / log2(1.01) ~ 9.3 halvings of the log bracket, plus the two ends. */
    CHECK(s.evaluations <= 13);
}

TEST(search_reports_an_unreachable_target)
{
    counter c = {0};
    texopt_target_search s;
    char err[128] = "";
    CHECK_OK(texopt_search_target_loss(sqrt_loss, &c, 0.001, 0.01, 2.0, 0, 0, &s, err, sizeof err), err);
    CHECK(!s.reached);
    CHECK_EQ_INT(s.evaluations, 1);
    CHECK_NEAR(s.relative_cost, 2.0, 0);
    CHECK_NEAR(s.q, 0.02 / sqrt(2.0), 1e-15);
}

TEST(search_stops_at_the_floor_when_it_is_good_enough)
{
    counter c = {0};
    texopt_target_search s;
    char err[128] = "";
    CHECK_OK(texopt_search_target_loss(sqrt_loss, &c, 0.5, 0.05, 1.0, 0, 0, &s, err, sizeof err), err);
    CHECK(s.reached);
    CHECK_EQ_INT(s.evaluations, 2);
    CHECK_NEAR(s.relative_cost, 0.05, 0);
}

TEST(search_passes_failures_and_refuses_bad_ranges)
{
    texopt_target_search s;
    char err[128] = "";
    CHECK(texopt_search_target_loss(failing_loss, NULL, 0.1, 0.1, 1, 0, 0, &s, err, sizeof err) == TEXOPT_E_RENDER);
    CHECK(texopt_search_target_loss(sqrt_loss, NULL, 0.1, 1, 0.5, 0, 0, &s, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_search_target_loss(sqrt_loss, NULL, 0.1, 0.1, 5, 0, 0, &s, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
}

TEST(cost_at_loss_interpolates_in_log_cost)
{
    texopt_compare_curve curve = {.point_count = 4};
    const double costs[] = {0.5, 0.1, 1.0, 0.2}; /* unsorted on purpose */
    for (int i = 0; i < 4; i++) {
        curve.points[i].status = TEXOPT_OK;
        curve.points[i].cost_achieved = costs[i];
        curve.points[i].q = 0.3 - 0.1 * log10(costs[i] / 0.1) * 2; /* 0.3 at 0.1, 0.1 at 1.0 */
    }
    /* q = 0.2 at c = 10^0.5 * 0.1 = 0.316: between 0.2 and 0.5 in log-linear exactly. */
    CHECK_NEAR(texopt_compare_cost_at_loss(&curve, 0.2), 0.1 * sqrt(10.0), 1e-12);
    CHECK_NEAR(texopt_compare_cost_at_loss(&curve, 0.35), 0.1, 0);
    CHECK_NEAR(texopt_compare_cost_at_loss(&curve, 0.05), -1, 0);
    curve.points[2].status = TEXOPT_E_UNSUPPORTED; /* a failed point is skipped */
    CHECK_NEAR(texopt_compare_cost_at_loss(&curve, 0.1), -1, 0);
}
