/* test_gp.c - the Matern 5/2 Gaussian process: interpolation, agreement with a dense
 * textbook posterior, incremental Cholesky equal to a full factorisation, length-scale fit. */
#include <stdlib.h>
#include <string.h>

#include "gp.h"
#include "rng.h"
#include "test.h"

static double smooth(const double *x)
{
    return sin(3.0 * x[0]) + 0.5 * cos(5.0 * x[1]) + x[0] * x[1];
}

static texopt_gp *gp_with_samples(int n, double length_scale, double jitter, double *xs, double *ys, unsigned seed)
{
    texopt_gp *gp = texopt_gp_create(2, 64, 16);
    if (!gp || texopt_gp_set_hyper(gp, length_scale, jitter) != TEXOPT_OK)
        return NULL;
    texopt_rng rng;
    texopt_rng_seed(&rng, seed);
    for (int i = 0; i < n; i++) {
        xs[2 * i] = texopt_rng_uniform(&rng);
        xs[2 * i + 1] = texopt_rng_uniform(&rng);
        ys[i] = 10.0 + 3.0 * smooth(xs + 2 * i);
        if (texopt_gp_add(gp, xs + 2 * i, ys[i]) != TEXOPT_OK) {
            texopt_gp_destroy(gp);
            return NULL;
        }
    }
    return gp;
}

TEST(gp_interpolates_its_samples)
{
    double xs[40], ys[20], mean[20], var[20];
    texopt_gp *gp = gp_with_samples(20, 0.4, 1e-10, xs, ys, 1);
    CHECK(gp != NULL);
    texopt_gp_predict(gp, 20, xs, mean, var);
    for (int i = 0; i < 20; i++) {
        CHECK_NEAR(mean[i], ys[i], 1e-5);
        CHECK(var[i] < 1e-6);
    }
    texopt_gp_destroy(gp);
}

static double matern52_reference(const double *a, const double *b, double l)
{
    double r = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]));
    double s = sqrt(5.0) * r / l;
    return (1.0 + s + 5.0 * r * r / (3.0 * l * l)) * exp(-s);
}

TEST(gp_posterior_matches_a_dense_textbook_solve)
{
    enum { N = 7 };
    const double l = 0.3, jitter = 1e-3;
    double xs[2 * N], ys[N];
    texopt_gp *gp = gp_with_samples(N, l, jitter, xs, ys, 2);
    CHECK(gp != NULL);
    /* Standardise as documented: mean 0, sample standard deviation 1. */
    double mu = 0.0, ss = 0.0;
    for (int i = 0; i < N; i++)
        mu += ys[i] / N;
    for (int i = 0; i < N; i++)
        ss += (ys[i] - mu) * (ys[i] - mu);
    double sd = sqrt(ss / (N - 1));
    /* Augmented system [K | k* | y] eliminated by hand. */
    const double probe[2] = {0.37, 0.61};
    double m[N][N + 2];
    for (int i = 0; i < N; i++) {
        for (int j = 0; j < N; j++)
            m[i][j] = matern52_reference(xs + 2 * i, xs + 2 * j, l) + (i == j ? jitter : 0.0);
        m[i][N] = matern52_reference(xs + 2 * i, probe, l);
        m[i][N + 1] = (ys[i] - mu) / sd;
    }
    double kstar[N];
    for (int i = 0; i < N; i++)
        kstar[i] = m[i][N];
    for (int k = 0; k < N; k++)
        for (int i = k + 1; i < N; i++) {
            double f = m[i][k] / m[k][k];
            for (int j = k; j < N + 2; j++)
                m[i][j] -= f * m[k][j];
        }
    double sol[2][N];
    for (int c = 0; c < 2; c++)
        for (int k = N - 1; k >= 0; k--) {
            double s = m[k][N + c];
            for (int j = k + 1; j < N; j++)
                s -= m[k][j] * sol[c][j];
            sol[c][k] = s / m[k][k];
        }
    double expect_mean = 0.0, explained = 0.0;
    for (int i = 0; i < N; i++) {
        expect_mean += kstar[i] * sol[1][i];
        explained += kstar[i] * sol[0][i];
    }
    expect_mean = mu + sd * expect_mean;
    double expect_var = sd * sd * (1.0 - explained);
    double mean, var;
    texopt_gp_predict(gp, 1, probe, &mean, &var);
    CHECK_NEAR(mean, expect_mean, 1e-9);
    CHECK_NEAR(var, expect_var, 1e-9);
    CHECK(var > 1e-3); /* the probe is not a sample: the check above is not trivial */
    texopt_gp_destroy(gp);
}

TEST(incremental_cholesky_equals_full_factorisation)
{
    enum { N = 30 };
    double xs[2 * N], ys[N];
    texopt_gp *gp = gp_with_samples(N, 0.25, 1e-6, xs, ys, 3);
    CHECK(gp != NULL);
    int ld = 0;
    const double *L = texopt_gp_cholesky(gp, &ld);
    static double incremental[64 * 64];
    memcpy(incremental, L, sizeof(double) * (size_t)ld * N);
    CHECK_OK(texopt_gp_set_hyper(gp, 0.25, 1e-6), "refactor");
    L = texopt_gp_cholesky(gp, &ld);
    for (int j = 0; j < N; j++)
        for (int i = j; i < N; i++)
            CHECK_NEAR(incremental[i + j * ld], L[i + j * ld], 1e-9);
    texopt_gp_destroy(gp);
}

TEST(prediction_in_chunks_equals_one_at_a_time_and_far_points_see_the_prior)
{
    double xs[2 * 12], ys[12];
    texopt_gp *gp = gp_with_samples(12, 0.2, 1e-6, xs, ys, 4);
    CHECK(gp != NULL);
    enum { M = 50 }; /* max_batch is 16: four chunks */
    double pts[2 * M], mean[M], var[M];
    for (int j = 0; j < M; j++) {
        pts[2 * j] = j / (double)M;
        pts[2 * j + 1] = 1.0 - j / (double)M;
    }
    texopt_gp_predict(gp, M, pts, mean, var);
    for (int j = 0; j < M; j++) {
        double m1, v1;
        texopt_gp_predict(gp, 1, pts + 2 * j, &m1, &v1);
        CHECK_NEAR(mean[j], m1, 1e-12);
        CHECK_NEAR(var[j], v1, 1e-12);
    }
    double mu = 0.0, ss = 0.0;
    for (int i = 0; i < 12; i++)
        mu += ys[i] / 12;
    for (int i = 0; i < 12; i++)
        ss += (ys[i] - mu) * (ys[i] - mu);
    const double far[2] = {40.0, -40.0};
    double m, v;
    texopt_gp_predict(gp, 1, far, &m, &v);
    CHECK_NEAR(m, mu, 1e-9);
    CHECK_NEAR(v, ss / 11, 1e-9);
    texopt_gp_destroy(gp);
}

TEST(length_scale_fit_prefers_long_scales_for_smooth_data)
{
    const double grid[] = {0.02, 0.05, 0.1, 0.2, 0.4, 0.8, 1.6};
    texopt_gp *smooth_gp = texopt_gp_create(1, 40, 8), *rough_gp = texopt_gp_create(1, 40, 8);
    CHECK(smooth_gp && rough_gp);
    for (int i = 0; i < 40; i++) {
        double x = (i + 0.5) / 40.0;
        CHECK_OK(texopt_gp_add(smooth_gp, &x, 2.0 * x + 0.3 * x * x), "add");
        CHECK_OK(texopt_gp_add(rough_gp, &x, sin(60.0 * x)), "add");
    }
    CHECK_OK(texopt_gp_fit_length_scale(smooth_gp, grid, 7), "fit");
    CHECK_OK(texopt_gp_fit_length_scale(rough_gp, grid, 7), "fit");
    CHECK(texopt_gp_length_scale(smooth_gp) >= 0.4);
    CHECK(texopt_gp_length_scale(rough_gp) <= 0.1);
    CHECK(texopt_gp_log_likelihood(smooth_gp) > texopt_gp_log_likelihood(rough_gp));
    texopt_gp_destroy(smooth_gp);
    texopt_gp_destroy(rough_gp);
}

TEST(gp_limits_and_bad_values)
{
    texopt_gp *gp = texopt_gp_create(1, 2, 1);
    CHECK(gp != NULL);
    double x = 0.1, y = 0.9;
    CHECK(texopt_gp_add(gp, &x, NAN) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK_OK(texopt_gp_add(gp, &x, 1.0), "add");
    CHECK_OK(texopt_gp_add(gp, &y, 2.0), "add");
    CHECK(texopt_gp_add(gp, &y, 2.0) == TEXOPT_E_LIMIT);
    CHECK(texopt_gp_set_hyper(gp, 0.0, 1e-6) == TEXOPT_E_INVALID_ARGUMENT);
    /* A duplicate with zero jitter has no positive pivot. */
    texopt_gp_clear(gp);
    CHECK_OK(texopt_gp_set_hyper(gp, 0.3, 0.0), "hyper");
    CHECK_OK(texopt_gp_add(gp, &x, 1.0), "add");
    CHECK(texopt_gp_add(gp, &x, 1.0) == TEXOPT_E_NUMERIC);
    texopt_gp_destroy(gp);
    texopt_gp_destroy(NULL);
    CHECK(texopt_gp_create(0, 5, 5) == NULL);
}
