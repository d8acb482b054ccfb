/* gp.c - Gaussian-process regression, Matern 5/2 kernel, incremental Cholesky (gp.h).
 * Rasmussen and Williams 2006, algorithm 2.1 and eq. 4.17. Does not choose where to sample
 * (bayesopt.c does) and does not fit anything but one isotropic length scale. */
#include "gp.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GP_SQRT5 2.23606797749978969641

struct texopt_gp {
    int dim, capacity, max_batch, n;
    double length_scale, jitter;
    double *weight;     /* dim: 1 / (length_scale * multiplier_k), the ARD metric */
    double *multiplier; /* dim: per-dimension length-scale factors (1 = isotropic) */
    double *x;          /* capacity * dim */
    double *y;          /* capacity: targets as given */
    double *L;          /* capacity x capacity, column-major lower Cholesky factor */
    double *alpha;      /* K^-1 (standardised y) */
    double *scratch;    /* capacity */
    double *kstar;      /* capacity x max_batch, column-major: one column per point */
    double y_mean, y_scale;
    int alpha_valid;
};

texopt_gp *texopt_gp_create(int dim, int max_samples, int max_batch)
{
    if (dim < 1 || dim > 64 || max_samples < 1 || max_samples > 20000 || max_batch < 1 || max_batch > 1 << 20)
        return NULL;
    texopt_gp *gp = calloc(1, sizeof *gp);
    if (!gp)
        return NULL;
    size_t cap = (size_t)max_samples;
    gp->dim = dim;
    gp->capacity = max_samples;
    gp->max_batch = max_batch;
    gp->length_scale = 0.3;
    gp->jitter = 1e-6;
    gp->x = malloc(cap * (size_t)dim * sizeof *gp->x);
    gp->y = malloc(cap * sizeof *gp->y);
    gp->L = malloc(cap * cap * sizeof *gp->L);
    gp->alpha = malloc(cap * sizeof *gp->alpha);
    gp->scratch = malloc(cap * sizeof *gp->scratch);
    gp->weight = malloc((size_t)dim * sizeof *gp->weight);
    gp->multiplier = malloc((size_t)dim * sizeof *gp->multiplier);
    gp->kstar = malloc(cap * (size_t)max_batch * sizeof *gp->kstar);
    if (!gp->x || !gp->y || !gp->L || !gp->alpha || !gp->scratch || !gp->kstar || !gp->weight || !gp->multiplier) {
        texopt_gp_destroy(gp);
        return NULL;
    }
    for (int k = 0; k < dim; k++) {
        gp->multiplier[k] = 1.0;
        gp->weight[k] = 1.0 / gp->length_scale;
    }
    return gp;
}

void texopt_gp_destroy(texopt_gp *gp)
{
    if (!gp)
        return;
    free(gp->x);
    free(gp->y);
    free(gp->L);
    free(gp->alpha);
    free(gp->scratch);
    free(gp->kstar);
    free(gp->weight);
    free(gp->multiplier);
    free(gp);
}

void texopt_gp_clear(texopt_gp *gp)
{
    gp->n = 0;
    gp->alpha_valid = 0;
}

int texopt_gp_count(const texopt_gp *gp)
{
    return gp->n;
}

double texopt_gp_length_scale(const texopt_gp *gp)
{
    return gp->length_scale;
}

const double *texopt_gp_cholesky(const texopt_gp *gp, int *leading_dimension)
{
    if (leading_dimension)
        *leading_dimension = gp->capacity;
    return gp->L;
}

static double matern52(const texopt_gp *gp, const double *a, const double *b)
{
    double d2 = 0.0;
    for (int k = 0; k < gp->dim; k++) {
        double d = (a[k] - b[k]) * gp->weight[k];
        d2 += d * d;
    }
    double r = GP_SQRT5 * sqrt(d2);
    return (1.0 + r + r * r / 3.0) * exp(-r);
}

/* Full factorisation of K + jitter I into L (lower). Returns 0 when not positive definite. */
static int factor_all(texopt_gp *gp)
{
    int n = gp->n, ld = gp->capacity;
    for (int j = 0; j < n; j++) {
        const double *xj = gp->x + (size_t)j * gp->dim;
        gp->L[(size_t)j + (size_t)j * ld] = 1.0 + gp->jitter;
        for (int i = j + 1; i < n; i++)
            gp->L[(size_t)i + (size_t)j * ld] = matern52(gp, gp->x + (size_t)i * gp->dim, xj);
    }
    gp->alpha_valid = 0;
    return n == 0 || LAPACKE_dpotrf_work(LAPACK_COL_MAJOR, 'L', n, gp->L, ld) == 0;
}

/* Refactors, raising the jitter up to 100-fold when the matrix is numerically singular. */
static texopt_status refactor(texopt_gp *gp)
{
    double base = gp->jitter;
    for (int attempt = 0; attempt < 3; attempt++) {
        if (factor_all(gp))
            return TEXOPT_OK;
        gp->jitter = (base > 0.0 ? base : 1e-10) * pow(10.0, attempt + 1);
    }
    gp->jitter = base;
    return TEXOPT_E_NUMERIC;
}

texopt_status texopt_gp_set_hyper(texopt_gp *gp, double length_scale, double jitter)
{
    if (!(length_scale > 0.0) || !isfinite(length_scale) || !(jitter >= 0.0) || !isfinite(jitter))
        return TEXOPT_E_INVALID_ARGUMENT;
    gp->length_scale = length_scale;
    gp->jitter = jitter;
    for (int k = 0; k < gp->dim; k++)
        gp->weight[k] = 1.0 / (length_scale * gp->multiplier[k]);
    return refactor(gp);
}

texopt_status texopt_gp_set_dimension_scales(texopt_gp *gp, const double *multipliers)
{
    for (int k = 0; k < gp->dim; k++)
        if (!(multipliers[k] > 0.0) || !isfinite(multipliers[k]))
            return TEXOPT_E_INVALID_ARGUMENT;
    memcpy(gp->multiplier, multipliers, (size_t)gp->dim * sizeof *multipliers);
    return texopt_gp_set_hyper(gp, gp->length_scale, gp->jitter);
}

texopt_status texopt_gp_fit_dimension_scales(texopt_gp *gp)
{
    static const double factors[2] = {0.5, 2.0};
    double current[64];
    memcpy(current, gp->multiplier, (size_t)gp->dim * sizeof *current);
    double best = texopt_gp_log_likelihood(gp);
    for (int k = 0; k < gp->dim; k++) {
        double keep = current[k];
        double chosen = keep;
        for (int f = 0; f < 2; f++) {
            double m = keep * factors[f];
            /* Bounded so that an irrelevant dimension cannot run away to infinity. */
            if (m < 1.0 / 16.0 || m > 16.0)
                continue;
            current[k] = m;
            if (texopt_gp_set_dimension_scales(gp, current) != TEXOPT_OK)
                continue;
            double ll = texopt_gp_log_likelihood(gp);
            if (ll > best) {
                best = ll;
                chosen = m;
            }
        }
        current[k] = chosen;
    }
    return texopt_gp_set_dimension_scales(gp, current);
}

texopt_status texopt_gp_add(texopt_gp *gp, const double *x, double y)
{
    if (gp->n >= gp->capacity)
        return TEXOPT_E_LIMIT;
    if (!isfinite(y))
        return TEXOPT_E_INVALID_ARGUMENT;
    int n = gp->n, ld = gp->capacity;
    double *row = gp->scratch;
    for (int i = 0; i < n; i++)
        row[i] = matern52(gp, gp->x + (size_t)i * gp->dim, x);
    /* New row l of L solves L l = k; the new pivot is sqrt(k(x,x) - l.l). */
    if (n > 0)
        cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, n, gp->L, ld, row, 1);
    double pivot = 1.0 + gp->jitter;
    for (int i = 0; i < n; i++)
        pivot -= row[i] * row[i];
    if (!(pivot > 0.0))
        return TEXOPT_E_NUMERIC;
    memcpy(gp->x + (size_t)n * gp->dim, x, (size_t)gp->dim * sizeof *x);
    gp->y[n] = y;
    for (int i = 0; i < n; i++)
        gp->L[(size_t)n + (size_t)i * ld] = row[i];
    gp->L[(size_t)n + (size_t)n * ld] = sqrt(pivot);
    gp->n = n + 1;
    gp->alpha_valid = 0;
    return TEXOPT_OK;
}

void texopt_gp_set_y(texopt_gp *gp, int i, double y)
{
    if (i >= 0 && i < gp->n && isfinite(y)) {
        gp->y[i] = y;
        gp->alpha_valid = 0;
    }
}

/* Standardises the targets and solves K alpha = y_std with the factor (O(n^2)). */
static void update_alpha(texopt_gp *gp)
{
    if (gp->alpha_valid)
        return;
    int n = gp->n;
    double mean = 0.0, ss = 0.0;
    for (int i = 0; i < n; i++)
        mean += gp->y[i];
    mean = n > 0 ? mean / n : 0.0;
    for (int i = 0; i < n; i++)
        ss += (gp->y[i] - mean) * (gp->y[i] - mean);
    double scale = n > 1 ? sqrt(ss / (n - 1)) : 1.0;
    /* Several equal targets: the data say the function is flat, so the posterior spread
     * should be negligible (a unit scale would keep promising improvement forever). */
    double floor_scale = 1e-9 * (fabs(mean) > 1.0 ? fabs(mean) : 1.0);
    gp->y_mean = mean;
    gp->y_scale = scale > floor_scale ? scale : floor_scale;
    for (int i = 0; i < n; i++)
        gp->alpha[i] = (gp->y[i] - mean) / gp->y_scale;
    if (n > 0) {
        cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, n, gp->L, gp->capacity, gp->alpha, 1);
        cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasNonUnit, n, gp->L, gp->capacity, gp->alpha, 1);
    }
    gp->alpha_valid = 1;
}

double texopt_gp_log_likelihood(texopt_gp *gp)
{
    update_alpha(gp);
    int n = gp->n;
    double fit = 0.0, logdet = 0.0;
    for (int i = 0; i < n; i++) {
        fit += gp->alpha[i] * (gp->y[i] - gp->y_mean) / gp->y_scale;
        logdet += log(gp->L[(size_t)i + (size_t)i * gp->capacity]);
    }
    return -0.5 * fit - logdet - 0.5 * n * log(2.0 * 3.14159265358979323846);
}

texopt_status texopt_gp_fit_length_scale(texopt_gp *gp, const double *candidates, int count)
{
    if (!candidates || count < 1)
        return TEXOPT_E_INVALID_ARGUMENT;
    double jitter = gp->jitter, best_scale = gp->length_scale, best = -INFINITY;
    for (int c = 0; c < count; c++) {
        if (texopt_gp_set_hyper(gp, candidates[c], jitter) != TEXOPT_OK)
            continue;
        double ll = texopt_gp_log_likelihood(gp);
        if (ll > best) {
            best = ll;
            best_scale = candidates[c];
        }
    }
    return texopt_gp_set_hyper(gp, best_scale, jitter);
}

static void predict_batch(texopt_gp *gp, int m, const double *x, double *mean, double *var)
{
    int n = gp->n, ld = gp->capacity;
    double *ks = gp->kstar;
    for (int j = 0; j < m; j++) {
        const double *xj = x + (size_t)j * gp->dim;
        double *col = ks + (size_t)j * ld;
        for (int i = 0; i < n; i++)
            col[i] = matern52(gp, gp->x + (size_t)i * gp->dim, xj);
    }
    cblas_dgemv(CblasColMajor, CblasTrans, n, m, 1.0, ks, ld, gp->alpha, 1, 0.0, mean, 1);
    for (int j = 0; j < m; j++)
        mean[j] = gp->y_mean + gp->y_scale * mean[j];
    if (!var)
        return;
    /* V = L^-1 K*: the explained part of the prior variance is the column norm of V. */
    cblas_dtrsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasNonUnit, n, m, 1.0, gp->L, ld, ks, ld);
    double s2 = gp->y_scale * gp->y_scale;
    for (int j = 0; j < m; j++) {
        const double *col = ks + (size_t)j * ld;
        double explained = cblas_ddot(n, col, 1, col, 1);
        double v = 1.0 - explained;
        var[j] = s2 * (v > 0.0 ? v : 0.0);
    }
}

void texopt_gp_predict(texopt_gp *gp, int m, const double *x, double *mean, double *var)
{
    if (gp->n == 0) {
        for (int j = 0; j < m; j++) {
            mean[j] = 0.0;
            if (var)
                var[j] = 1.0;
        }
        return;
    }
    update_alpha(gp);
    for (int start = 0; start < m; start += gp->max_batch) {
        int count = m - start < gp->max_batch ? m - start : gp->max_batch;
        predict_batch(gp, count, x + (size_t)start * gp->dim, mean + start, var ? var + start : NULL);
    }
}
