/* test_bayesopt.c - Bayesian optimisation on standard test functions with known minima
 * (Branin, Hartmann-6; Surjanovic and Bingham's library of test functions), determinism,
 * infeasible regions, initial points and known initial values, early stops, bad options. */
#include <stdlib.h>
#include <string.h>

#include "bayesopt.h"
#include "test.h"

#define BRANIN_MIN 0.397887357729738
#define HARTMANN6_MIN (-3.32236801141551)

typedef struct counter {
    int calls;
    int infeasible_seen;
} counter;

/* Branin on [-5, 10] x [0, 15], mapped from the unit box. */
static double branin_unit(const double *u)
{
    double x = -5.0 + 15.0 * u[0], y = 15.0 * u[1];
    const double pi = 3.14159265358979323846;
    double b = 5.1 / (4.0 * pi * pi), c = 5.0 / pi, t = 1.0 / (8.0 * pi);
    double q = y - b * x * x + c * x - 6.0;
    return q * q + 10.0 * (1.0 - t) * cos(x) + 10.0;
}

static double branin(void *user, const double *u)
{
    ((counter *)user)->calls++;
    return branin_unit(u);
}

/* Only u >= 0.7 is feasible: two of Branin's three minima are cut off, the third,
 * (9.42478, 2.475) -> (0.9617, 0.165), remains. */
static double constrained_branin(void *user, const double *u)
{
    counter *c = user;
    c->calls++;
    if (u[0] < 0.7) {
        c->infeasible_seen++;
        return INFINITY;
    }
    return branin_unit(u);
}

static double hartmann6(void *user, const double *x)
{
    static const double alpha[4] = {1.0, 1.2, 3.0, 3.2};
    static const double a[4][6] = {
        {10, 3, 17, 3.5, 1.7, 8}, {0.05, 10, 17, 0.1, 8, 14}, {3, 3.5, 1.7, 10, 17, 8}, {17, 8, 0.05, 10, 0.1, 14}};
    static const double p[4][6] = {{0.1312, 0.1696, 0.5569, 0.0124, 0.8283, 0.5886},
                                   {0.2329, 0.4135, 0.8307, 0.3736, 0.1004, 0.9991},
                                   {0.2348, 0.1451, 0.3522, 0.2883, 0.3047, 0.6650},
                                   {0.4047, 0.8828, 0.8732, 0.5743, 0.1091, 0.0381}};
    ((counter *)user)->calls++;
    double sum = 0.0;
    for (int i = 0; i < 4; i++) {
        double e = 0.0;
        for (int j = 0; j < 6; j++)
            e += a[i][j] * (x[j] - p[i][j]) * (x[j] - p[i][j]);
        sum += alpha[i] * exp(-e);
    }
    return -sum;
}

/* BO is a randomised global search: over seeds 0..9 Branin reaches 1e-2 in 9-10 of 10
 * runs, Hartmann-6 reaches 0.05 in 7 of 10 (the others sit in its -3.203 local minimum;
 * BENCHMARKS.md@9f788a8). The tests ask for two seeds of three, so a regression that breaks the
 * search fails them while one unlucky seed does not. */
TEST(branin_reaches_its_minimum_within_60_evaluations)
{
    texopt_bo *bo = texopt_bo_create(2, 60);
    CHECK(bo != NULL);
    int successes = 0;
    for (uint64_t seed = 0; seed < 3; seed++) {
        texopt_bo_options opt = {.seed = seed};
        counter c = {0, 0};
        double x[2], fbest;
        int evaluations = 0;
        char err[256] = "";
        CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &c, x, &fbest, &evaluations, err, sizeof err), err);
        CHECK_EQ_INT(evaluations, 60);
        CHECK_EQ_INT(c.calls, 60);
        CHECK_NEAR(branin_unit(x), fbest, 1e-12);
        CHECK(fbest >= BRANIN_MIN - 1e-9);
        successes += fabs(fbest - BRANIN_MIN) <= 1e-2;
    }
    CHECK(successes >= 2);
    texopt_bo_destroy(bo);
}

TEST(hartmann6_reaches_its_minimum_within_150_evaluations)
{
    texopt_bo *bo = texopt_bo_create(6, 150);
    CHECK(bo != NULL);
    int successes = 0;
    for (uint64_t seed = 0; seed < 3; seed++) {
        texopt_bo_options opt = {.seed = seed};
        counter c = {0, 0};
        double x[6], fbest;
        char err[256] = "";
        CHECK_OK(texopt_bo_minimize(bo, &opt, hartmann6, &c, x, &fbest, NULL, err, sizeof err), err);
        CHECK(c.calls <= 150);
        successes += fabs(fbest - HARTMANN6_MIN) <= 0.05;
    }
    CHECK(successes >= 2);
    texopt_bo_destroy(bo);
}

TEST(same_seed_same_evaluations_other_seed_other_evaluations)
{
    texopt_bo *bo = texopt_bo_create(2, 25);
    CHECK(bo != NULL);
    texopt_bo_options opt = {.seed = 42};
    counter c = {0, 0};
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &c, NULL, NULL, NULL, err, sizeof err), err);
    const double *hx, *hf;
    int n = texopt_bo_history(bo, &hx, &hf);
    CHECK_EQ_INT(n, 25);
    double first_x[50], first_f[25];
    memcpy(first_x, hx, sizeof first_x);
    memcpy(first_f, hf, sizeof first_f);
    CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &c, NULL, NULL, NULL, err, sizeof err), err);
    CHECK_EQ_INT(texopt_bo_history(bo, &hx, &hf), 25);
    CHECK(memcmp(first_x, hx, sizeof first_x) == 0);
    CHECK(memcmp(first_f, hf, sizeof first_f) == 0);
    opt.seed = 43;
    CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &c, NULL, NULL, NULL, err, sizeof err), err);
    CHECK(memcmp(first_x, hx, sizeof first_x) != 0);
    texopt_bo_destroy(bo);
}

TEST(infeasible_region_is_avoided_and_history_keeps_infinity)
{
    texopt_bo *bo = texopt_bo_create(2, 80);
    CHECK(bo != NULL);
    const double start[2] = {0.9, 0.9}; /* a feasible warm start */
    texopt_bo_options opt = {.seed = 3, .initial_points = start, .initial_point_count = 1};
    counter c = {0, 0};
    double x[2], fbest;
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, constrained_branin, &c, x, &fbest, NULL, err, sizeof err), err);
    CHECK(x[0] >= 0.7);
    CHECK_NEAR(fbest, BRANIN_MIN, 1e-2);
    CHECK_NEAR(x[0], 0.9617, 0.01);
    CHECK_NEAR(x[1], 0.165, 0.01);
    CHECK(c.infeasible_seen > 0); /* the design did probe the infeasible part */
    const double *hx, *hf;
    int n = texopt_bo_history(bo, &hx, &hf);
    int infinite = 0, late_infeasible = 0;
    for (int i = 0; i < n; i++) {
        infinite += hf[i] == INFINITY;
        late_infeasible += i >= n / 2 && hf[i] == INFINITY;
    }
    CHECK_EQ_INT(infinite, c.infeasible_seen);
    /* Once the surrogate knows the region is bad it stops sampling there (mostly). */
    CHECK(late_infeasible <= n / 8);
    texopt_bo_destroy(bo);
}

/* +INFINITY, NaN and -INFINITY in turn: all of them mean "infeasible". */
static double always_infeasible(void *user, const double *x)
{
    (void)user;
    static const double kinds[3] = {INFINITY, NAN, -INFINITY};
    return kinds[(int)(x[1] * 2.999)];
}

TEST(all_infeasible_reports_infinity_and_the_first_point)
{
    texopt_bo *bo = texopt_bo_create(3, 12);
    const double start[3] = {0.25, 0.5, 2.0}; /* clamped to 1.0 */
    texopt_bo_options opt = {.initial_points = start, .initial_point_count = 1};
    double x[3], fbest = 0.0;
    int evaluations = 0;
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, always_infeasible, NULL, x, &fbest, &evaluations, err, sizeof err), err);
    CHECK(fbest == INFINITY);
    CHECK_EQ_INT(evaluations, 12);
    const double *hf;
    CHECK_EQ_INT(texopt_bo_history(bo, NULL, &hf), 12);
    for (int i = 0; i < 12; i++)
        CHECK(hf[i] == INFINITY);
    CHECK(x[0] == 0.25 && x[1] == 0.5 && x[2] == 1.0);
    texopt_bo_destroy(bo);
}

TEST(initial_points_come_first_and_target_stops_early)
{
    texopt_bo *bo = texopt_bo_create(2, 50);
    const double pts[4] = {0.5428, 0.1517, 0.1, 0.1}; /* the first is near a minimum */
    texopt_bo_options opt = {.initial_points = pts, .initial_point_count = 2, .has_target = 1, .target = 0.5};
    counter c = {0, 0};
    double fbest;
    int evaluations = 0;
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &c, NULL, &fbest, &evaluations, err, sizeof err), err);
    CHECK_EQ_INT(evaluations, 1);
    CHECK(fbest <= 0.5);
    const double *hx;
    CHECK_EQ_INT(texopt_bo_history(bo, &hx, NULL), 1);
    CHECK(hx[0] == pts[0] && hx[1] == pts[1]);
    texopt_bo_destroy(bo);
}

static double flat(void *user, const double *x)
{
    ((counter *)user)->calls++;
    return 1.0 + 0.0 * x[0];
}

TEST(expected_improvement_early_stop_saves_evaluations_on_a_flat_function)
{
    texopt_bo *bo = texopt_bo_create(2, 100);
    texopt_bo_options opt = {.iterations = 90, .early_stop_ei = 1e-6, .early_stop_patience = 3};
    counter c = {0, 0};
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, flat, &c, NULL, NULL, NULL, err, sizeof err), err);
    CHECK(c.calls < 20);
    texopt_bo_destroy(bo);
}

TEST(known_initial_values_are_not_evaluated_and_steer_the_search)
{
    /* 30 Branin points on a grid with their values given: the objective is called only for
     * the 20 model-guided iterations, which improve well on the grid's best (a given
     * infeasible point stays +INFINITY in the history). */
    enum { KNOWN = 30, DIM = 2 };
    double x[KNOWN * DIM], f[KNOWN];
    for (int i = 0; i < KNOWN; i++) {
        x[DIM * i] = (i % 6) / 5.0;
        x[DIM * i + 1] = (i / 6) / 4.0;
        f[i] = i == 7 ? INFINITY : branin_unit(x + DIM * i);
    }
    double best_known = INFINITY;
    for (int i = 0; i < KNOWN; i++)
        best_known = f[i] < best_known ? f[i] : best_known;
    texopt_bo *bo = texopt_bo_create(DIM, KNOWN + 20);
    texopt_bo_options opt = {.iterations = 20,
                             .initial_points = x,
                             .initial_values = f,
                             .initial_point_count = KNOWN,
                             .initial_design = -1,
                             .seed = 5};
    counter c = {0, 0};
    double best_f = 0.0;
    int evaluations = 0;
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &c, NULL, &best_f, &evaluations, err, sizeof err), err);
    CHECK_EQ_INT(c.calls, 20);
    CHECK_EQ_INT(evaluations, KNOWN + 20);
    /* the best given value is 2.50; a minimum (0.398) is reached closely */
    CHECK_MSG(best_f < 0.3 * best_known && best_f < BRANIN_MIN + 0.5, "best %g after 20 guided evaluations, %g given",
              best_f, best_known);
    const double *hx, *hf;
    CHECK_EQ_INT(texopt_bo_history(bo, &hx, &hf), KNOWN + 20);
    CHECK(isinf(hf[7]) && hf[3] == f[3] && hx[2 * 3] == x[2 * 3]);
    texopt_bo_destroy(bo);
}

TEST(stall_stop_ends_when_evaluations_stop_improving)
{
    /* On a flat function no evaluation improves: patience 4 stops after exactly 4 guided
     * evaluations; with a tolerance of 0 Branin keeps improving now and then, so it runs
     * longer than that. */
    texopt_bo *bo = texopt_bo_create(2, 100);
    texopt_bo_options opt = {.iterations = 60, .stall_patience = 4, .stall_tolerance = 1e-3};
    counter c = {0, 0};
    char err[256] = "";
    CHECK_OK(texopt_bo_minimize(bo, &opt, flat, &c, NULL, NULL, NULL, err, sizeof err), err);
    CHECK_EQ_INT(c.calls, 2 * 2 + 2 + 4);
    counter b = {0, 0};
    opt.stall_tolerance = 0.0;
    CHECK_OK(texopt_bo_minimize(bo, &opt, branin, &b, NULL, NULL, NULL, err, sizeof err), err);
    CHECK(b.calls > 2 * 2 + 2 + 4);
    opt.stall_tolerance = -1.0;
    CHECK(texopt_bo_minimize(bo, &opt, branin, &b, NULL, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_bo_destroy(bo);
}

TEST(bayesopt_rejects_bad_options)
{
    texopt_bo *bo = texopt_bo_create(2, 10);
    counter c = {0, 0};
    char err[256] = "";
    texopt_bo_options opt = {.candidates = -1};
    CHECK(texopt_bo_minimize(bo, &opt, branin, &c, NULL, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "candidates") != NULL);
    texopt_bo_options opt2 = {.initial_point_count = 2};
    CHECK(texopt_bo_minimize(bo, &opt2, branin, &c, NULL, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_bo_minimize(bo, NULL, NULL, &c, NULL, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK_EQ_INT(c.calls, 0);
    CHECK(texopt_bo_create(0, 10) == NULL);
    CHECK(texopt_bo_create(17, 10) == NULL);
    texopt_bo_destroy(bo);
    texopt_bo_destroy(NULL);
}
