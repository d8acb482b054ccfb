/* bayesopt.c - Bayesian optimisation in the unit box (bayesopt.h): Latin-hypercube design,
 * Matern 5/2 GP surrogate (gp.c), expected improvement (Jones et al. 1998) or a lower
 * confidence bound maximised over a candidate batch and polished with NLopt BOBYQA
 * (Powell 2009). Serves the triangle-wise stage of Sun et al. 2022 (section 4.1.2).
 * Does not map the box to any problem's domain and does not run objectives in parallel. */
#include "bayesopt.h"

#include <math.h>
#include <nlopt.h>
#include <stdlib.h>
#include <string.h>

#include "gp.h"
#include "rng.h"

#define BO_MAX_DIM 16
#define BO_MAX_CANDIDATES 8192
#define BO_BATCH 512
#define BO_LENGTH_SCALES 7

struct texopt_bo {
    int dim, max_evaluations;
    texopt_gp *gp;
    nlopt_opt polish;
    double *x; /* max_evaluations * dim: evaluated points */
    double *f; /* true values (+INFINITY when infeasible) */
    int count;
    double *candidates, *mean, *var; /* BO_MAX_CANDIDATES */
    double *design;                  /* Latin hypercube scratch */
};

/* What the acquisition's polish needs to evaluate one point. */
typedef struct acquisition_context {
    texopt_gp *gp;
    texopt_acquisition kind;
    double incumbent, beta;
} acquisition_context;

texopt_bo *texopt_bo_create(int dim, int max_evaluations)
{
    if (dim < 1 || dim > BO_MAX_DIM || max_evaluations < 1 || max_evaluations > 10000)
        return NULL;
    texopt_bo *bo = calloc(1, sizeof *bo);
    if (!bo)
        return NULL;
    bo->dim = dim;
    bo->max_evaluations = max_evaluations;
    bo->gp = texopt_gp_create(dim, max_evaluations, BO_BATCH);
    bo->polish = nlopt_create(NLOPT_LN_BOBYQA, (unsigned)dim);
    bo->x = malloc((size_t)max_evaluations * dim * sizeof *bo->x);
    bo->f = malloc((size_t)max_evaluations * sizeof *bo->f);
    bo->candidates = malloc((size_t)BO_MAX_CANDIDATES * dim * sizeof *bo->candidates);
    bo->mean = malloc(BO_MAX_CANDIDATES * sizeof *bo->mean);
    bo->var = malloc(BO_MAX_CANDIDATES * sizeof *bo->var);
    bo->design = malloc((size_t)max_evaluations * dim * sizeof *bo->design);
    if (!bo->gp || !bo->polish || !bo->x || !bo->f || !bo->candidates || !bo->mean || !bo->var || !bo->design) {
        texopt_bo_destroy(bo);
        return NULL;
    }
    double lower[BO_MAX_DIM], upper[BO_MAX_DIM];
    for (int k = 0; k < dim; k++) {
        lower[k] = 0.0;
        upper[k] = 1.0;
    }
    nlopt_set_lower_bounds(bo->polish, lower);
    nlopt_set_upper_bounds(bo->polish, upper);
    nlopt_set_xtol_abs1(bo->polish, 1e-5);
    return bo;
}

void texopt_bo_destroy(texopt_bo *bo)
{
    if (!bo)
        return;
    texopt_gp_destroy(bo->gp);
    if (bo->polish)
        nlopt_destroy(bo->polish);
    free(bo->x);
    free(bo->f);
    free(bo->candidates);
    free(bo->mean);
    free(bo->var);
    free(bo->design);
    free(bo);
}

int texopt_bo_history(const texopt_bo *bo, const double **x, const double **f)
{
    if (x)
        *x = bo->x;
    if (f)
        *f = bo->f;
    return bo->count;
}

typedef struct resolved_options {
    int iterations, design, candidates, polish, refit_every, patience, has_target, ard;
    int stall_patience;
    double beta, early_stop_ei, target, stall_tolerance;
    texopt_acquisition kind;
} resolved_options;

static texopt_status resolve_options(const texopt_bo *bo, const texopt_bo_options *opt, resolved_options *r, char *err,
                                     size_t err_len)
{
    static const texopt_bo_options zero;
    if (!opt)
        opt = &zero;
    if (opt->iterations < 0 || opt->candidates < 0 || opt->candidates > BO_MAX_CANDIDATES || opt->refit_every < 0 ||
        opt->early_stop_patience < 0 || opt->initial_point_count < 0 || opt->stall_patience < 0 ||
        !(opt->stall_tolerance >= 0.0) || (opt->initial_point_count > 0 && !opt->initial_points) ||
        opt->lcb_beta < 0.0 || (opt->acquisition != TEXOPT_ACQ_EI && opt->acquisition != TEXOPT_ACQ_LCB))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "bayesopt: invalid options (iterations %d, candidates %d of at most "
                           "%d, initial points %d)",
                           opt->iterations, opt->candidates, BO_MAX_CANDIDATES, opt->initial_point_count);
    r->iterations = opt->iterations ? opt->iterations : 100;
    r->design = opt->initial_design == 0 ? 2 * bo->dim + 2 : (opt->initial_design < 0 ? 0 : opt->initial_design);
    r->candidates = opt->candidates ? opt->candidates : 128;
    r->polish = opt->polish_evaluations == 0 ? 10 : (opt->polish_evaluations < 0 ? 0 : opt->polish_evaluations);
    r->refit_every = opt->refit_every ? opt->refit_every : 5;
    r->patience = opt->early_stop_patience;
    r->early_stop_ei = opt->early_stop_ei;
    r->stall_patience = opt->stall_patience;
    r->stall_tolerance = opt->stall_tolerance;
    r->beta = opt->lcb_beta > 0.0 ? opt->lcb_beta : 2.0;
    r->kind = opt->acquisition;
    r->has_target = opt->has_target;
    r->ard = !opt->isotropic;
    r->target = opt->target;
    return TEXOPT_OK;
}

/* ---- surrogate values ----------------------------------------------------------------- */

typedef struct feasible_range {
    double fmin, fmax;
    int any;
} feasible_range;

static feasible_range feasible_values(const texopt_bo *bo)
{
    feasible_range r = {INFINITY, -INFINITY, 0};
    for (int i = 0; i < bo->count; i++) {
        if (isfinite(bo->f[i])) {
            r.fmin = bo->f[i] < r.fmin ? bo->f[i] : r.fmin;
            r.fmax = bo->f[i] > r.fmax ? bo->f[i] : r.fmax;
            r.any = 1;
        }
    }
    return r;
}

/* The finite stand-in for infeasible samples (rule documented in bayesopt.h). */
static double infeasible_penalty(feasible_range r)
{
    if (!r.any)
        return 1.0;
    double gap = r.fmax - r.fmin;
    if (!(gap > 0.0))
        gap = fabs(r.fmax) > 1.0 ? fabs(r.fmax) : 1.0;
    return r.fmax + gap;
}

static void revalue_infeasible(texopt_bo *bo, double penalty)
{
    for (int i = 0; i < texopt_gp_count(bo->gp); i++)
        if (!isfinite(bo->f[i]))
            texopt_gp_set_y(bo->gp, i, penalty);
}

static const double *length_scale_grid(int dim, double *grid)
{
    static const double base[BO_LENGTH_SCALES] = {0.04, 0.07, 0.12, 0.2, 0.35, 0.6, 1.0};
    double s = sqrt((double)dim);
    for (int i = 0; i < BO_LENGTH_SCALES; i++)
        grid[i] = base[i] * s;
    return grid;
}

/* Adds the latest evaluation to the GP; a near-duplicate point gets a larger jitter. */
static texopt_status add_to_surrogate(texopt_bo *bo, int i, double penalty)
{
    double y = isfinite(bo->f[i]) ? bo->f[i] : penalty;
    texopt_status s = texopt_gp_add(bo->gp, bo->x + (size_t)i * bo->dim, y);
    for (double jitter = 1e-5; s == TEXOPT_E_NUMERIC && jitter <= 1e-2; jitter *= 10.0) {
        s = texopt_gp_set_hyper(bo->gp, texopt_gp_length_scale(bo->gp), jitter);
        if (s == TEXOPT_OK)
            s = texopt_gp_add(bo->gp, bo->x + (size_t)i * bo->dim, y);
    }
    return s;
}

/* Evaluates x (or takes its known value when `known` is not NULL), records it in the history
 * and in the surrogate. */
static texopt_status evaluate(texopt_bo *bo, texopt_objective f, void *user, const double *x, const double *known)
{
    int i = bo->count;
    double *xi = bo->x + (size_t)i * bo->dim;
    for (int k = 0; k < bo->dim; k++)
        xi[k] = x[k] < 0.0 ? 0.0 : (x[k] > 1.0 ? 1.0 : (isnan(x[k]) ? 0.5 : x[k]));
    double value = known ? *known : f(user, xi);
    /* -INFINITY is no better than NaN: a broken evaluation, not a record minimum. */
    bo->f[i] = isfinite(value) ? value : INFINITY;
    double old_penalty = infeasible_penalty(feasible_values(bo));
    bo->count = i + 1;
    double penalty = infeasible_penalty(feasible_values(bo));
    if (penalty != old_penalty)
        revalue_infeasible(bo, penalty);
    return add_to_surrogate(bo, i, penalty);
}

/* ---- acquisition ---------------------------------------------------------------------- */

static double expected_improvement(double mean, double var, double incumbent)
{
    double sd = sqrt(var);
    double improvement = incumbent - mean;
    if (!(sd > 1e-12 * (1.0 + fabs(incumbent))))
        return improvement > 0.0 ? improvement : 0.0;
    double z = improvement / sd;
    double cdf = 0.5 * erfc(-z / sqrt(2.0));
    double pdf = exp(-0.5 * z * z) / sqrt(2.0 * 3.14159265358979323846);
    double ei = improvement * cdf + sd * pdf;
    return ei > 0.0 ? ei : 0.0;
}

/* Larger is better for both kinds. */
static double acquisition_value(const acquisition_context *c, double mean, double var)
{
    if (c->kind == TEXOPT_ACQ_LCB)
        return -(mean - c->beta * sqrt(var));
    return expected_improvement(mean, var, c->incumbent);
}

static double polish_objective(unsigned n, const double *x, double *grad, void *data)
{
    (void)n;
    (void)grad;
    const acquisition_context *c = data;
    double mean, var;
    texopt_gp_predict(c->gp, 1, x, &mean, &var);
    return -acquisition_value(c, mean, var);
}

/* A quarter uniform points, three quarters Gaussian steps around the best sample at three
 * scales (0.15, 0.04, 0.01): global exploration and local refinement from one batched
 * prediction. (Half uniform was ~0.8% worse at 20-30 evaluations on driver-like problems,
 * 200 of them; equal on Branin and Hartmann-6.) */
static void generate_candidates(texopt_bo *bo, texopt_rng *rng, int m, int best)
{
    int dim = bo->dim;
    const double *xb = bo->x + (size_t)best * dim;
    for (int j = 0; j < m; j++) {
        double *c = bo->candidates + (size_t)j * dim;
        int kind = j % 4 == 0 ? 0 : 1 + j % 3;
        double sigma = kind == 1 ? 0.15 : (kind == 2 ? 0.04 : 0.01);
        for (int k = 0; k < dim; k++) {
            double v = kind == 0 ? texopt_rng_uniform(rng) : xb[k] + sigma * texopt_rng_normal(rng);
            c[k] = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
        }
    }
}

static int best_surrogate_index(const texopt_bo *bo, double penalty)
{
    int best = 0;
    double value = INFINITY;
    for (int i = 0; i < bo->count; i++) {
        double v = isfinite(bo->f[i]) ? bo->f[i] : penalty;
        if (v < value) {
            value = v;
            best = i;
        }
    }
    return best;
}

/* Chooses the next point; returns the acquisition value there. */
static double next_point(texopt_bo *bo, const resolved_options *r, texopt_rng *rng, double *x)
{
    double penalty = infeasible_penalty(feasible_values(bo));
    int best = best_surrogate_index(bo, penalty);
    acquisition_context ctx = {bo->gp, r->kind, isfinite(bo->f[best]) ? bo->f[best] : penalty, r->beta};
    generate_candidates(bo, rng, r->candidates, best);
    texopt_gp_predict(bo->gp, r->candidates, bo->candidates, bo->mean, bo->var);
    int arg = 0;
    double top = -INFINITY;
    for (int j = 0; j < r->candidates; j++) {
        double a = acquisition_value(&ctx, bo->mean[j], bo->var[j]);
        if (a > top) {
            top = a;
            arg = j;
        }
    }
    memcpy(x, bo->candidates + (size_t)arg * bo->dim, (size_t)bo->dim * sizeof *x);
    if (r->polish > 0) {
        double polished[BO_MAX_DIM], value;
        memcpy(polished, x, (size_t)bo->dim * sizeof *x);
        nlopt_set_min_objective(bo->polish, polish_objective, &ctx);
        nlopt_set_maxeval(bo->polish, r->polish);
        nlopt_set_initial_step1(bo->polish, 0.02);
        if (nlopt_optimize(bo->polish, polished, &value) > 0 && -value > top) {
            memcpy(x, polished, (size_t)bo->dim * sizeof *x);
            top = -value;
        }
    }
    return top;
}

/* ---- driver --------------------------------------------------------------------------- */

static void latin_hypercube(texopt_bo *bo, texopt_rng *rng, int m)
{
    int dim = bo->dim;
    for (int k = 0; k < dim; k++) {
        /* A random permutation of the strata for this coordinate (Fisher-Yates). */
        for (int j = 0; j < m; j++)
            bo->design[(size_t)j * dim + k] = j;
        for (int j = m - 1; j > 0; j--) {
            int s = (int)texopt_rng_below(rng, (uint32_t)(j + 1));
            double t = bo->design[(size_t)j * dim + k];
            bo->design[(size_t)j * dim + k] = bo->design[(size_t)s * dim + k];
            bo->design[(size_t)s * dim + k] = t;
        }
        for (int j = 0; j < m; j++)
            bo->design[(size_t)j * dim + k] = (bo->design[(size_t)j * dim + k] + texopt_rng_uniform(rng)) / m;
    }
}

static int reached_target(const texopt_bo *bo, const resolved_options *r)
{
    return r->has_target && bo->count > 0 && bo->f[bo->count - 1] <= r->target;
}

static texopt_status numeric_failure(char *err, size_t err_len, int count)
{
    return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "bayesopt: surrogate factorisation failed at sample %d", count);
}

static double best_value(const texopt_bo *bo)
{
    double value = INFINITY;
    for (int i = 0; i < bo->count; i++)
        value = bo->f[i] < value ? bo->f[i] : value;
    return value;
}

static void report_best(const texopt_bo *bo, double *best_x, double *best_f, int *evaluations)
{
    int best = 0;
    double value = INFINITY;
    for (int i = 0; i < bo->count; i++) {
        if (bo->f[i] < value) {
            value = bo->f[i];
            best = i;
        }
    }
    if (best_x && bo->count > 0)
        memcpy(best_x, bo->x + (size_t)best * bo->dim, (size_t)bo->dim * sizeof *best_x);
    if (best_f)
        *best_f = value;
    if (evaluations)
        *evaluations = bo->count;
}

texopt_status texopt_bo_minimize(texopt_bo *bo, const texopt_bo_options *opt, texopt_objective f, void *user,
                                 double *best_x, double *best_f, int *evaluations, char *err, size_t err_len)
{
    if (!bo || !f)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "bayesopt: no workspace or objective");
    resolved_options r = {0};
    texopt_status s = resolve_options(bo, opt, &r, err, err_len);
    if (s != TEXOPT_OK)
        return s;
    texopt_rng rng;
    texopt_rng_seed(&rng, opt ? opt->seed : 0);
    bo->count = 0;
    texopt_gp_clear(bo->gp);
    double ones[BO_MAX_DIM];
    for (int k = 0; k < bo->dim; k++)
        ones[k] = 1.0;
    texopt_gp_set_dimension_scales(bo->gp, ones);
    double grid[BO_LENGTH_SCALES];
    length_scale_grid(bo->dim, grid);
    if (texopt_gp_set_hyper(bo->gp, grid[3], 1e-6) != TEXOPT_OK)
        return numeric_failure(err, err_len, 0);

    int budget = bo->max_evaluations;
    int given = opt ? opt->initial_point_count : 0;
    for (int i = 0; i < given && bo->count < budget && !reached_target(bo, &r); i++)
        if (evaluate(bo, f, user, opt->initial_points + (size_t)i * bo->dim,
                     opt->initial_values ? opt->initial_values + i : NULL) != TEXOPT_OK)
            return numeric_failure(err, err_len, bo->count);
    int design = r.design < budget - bo->count ? r.design : budget - bo->count;
    if (design > 0 && !reached_target(bo, &r)) {
        latin_hypercube(bo, &rng, design);
        for (int i = 0; i < design && !reached_target(bo, &r); i++)
            if (evaluate(bo, f, user, bo->design + (size_t)i * bo->dim, NULL) != TEXOPT_OK)
                return numeric_failure(err, err_len, bo->count);
    }

    int quiet = 0, stalled = 0, since_refit = r.refit_every;
    double best = best_value(bo);
    for (int it = 0; it < r.iterations && bo->count < budget && bo->count > 0; it++) {
        if (reached_target(bo, &r))
            break;
        /* Hyper-parameters settle as samples accumulate while a refit costs O(n^3): the
         * interval grows with n (every refit_every samples, at least every n / 8). */
        int interval = bo->count / 8 > r.refit_every ? bo->count / 8 : r.refit_every;
        if (since_refit >= interval) {
            if (texopt_gp_fit_length_scale(bo->gp, grid, BO_LENGTH_SCALES) != TEXOPT_OK ||
                (r.ard && texopt_gp_fit_dimension_scales(bo->gp) != TEXOPT_OK))
                return numeric_failure(err, err_len, bo->count);
            since_refit = 0;
        }
        double x[BO_MAX_DIM];
        double acquisition = next_point(bo, &r, &rng, x);
        /* The patience-th low expectation in a row is not worth its evaluation. */
        if (r.patience > 0 && r.kind == TEXOPT_ACQ_EI) {
            quiet = acquisition < r.early_stop_ei ? quiet + 1 : 0;
            if (quiet >= r.patience)
                break;
        }
        if (evaluate(bo, f, user, x, NULL) != TEXOPT_OK)
            return numeric_failure(err, err_len, bo->count);
        since_refit++;
        double now = best_value(bo);
        stalled = isfinite(best) && !(now < best - r.stall_tolerance * fabs(best)) ? stalled + 1 : 0;
        best = now;
        if (r.stall_patience > 0 && stalled >= r.stall_patience)
            break;
    }
    report_best(bo, best_x, best_f, evaluations);
    return TEXOPT_OK;
}
