/* bayesopt.h - box-constrained Bayesian optimisation of an expensive black box.
 *
 * Jones, Schonlau, Welch 1998 ("Efficient Global Optimization of Expensive Black-Box
 * Functions": expected improvement on a GP surrogate); Snoek, Larochelle, Adams 2012 (Matern
 * 5/2). Used by the triangle-wise stage of Sun et al. 2022 (section 4.1.2, eq. 14) to find
 * each triangle's Jacobian in few evaluations.
 *
 * The search works in the unit box [0,1]^dim (callers map to their domain). Order of
 * evaluations: the caller's initial points (e.g. J = I and neighbours' optima), then a
 * Latin-hypercube design from the seeded generator, then one evaluation per iteration at
 * the maximiser of the acquisition: expected improvement (default) or a lower confidence
 * bound, taken over a batch of candidates (uniform points plus Gaussian perturbations of
 * the best samples, predicted in one BLAS batch) and polished locally with NLopt BOBYQA.
 * The GP's length scales are refitted by marginal likelihood every few samples: one global
 * scale from a grid, then per-dimension factors (ARD; `isotropic` turns that off).
 *
 * Infeasible points. The objective may return +INFINITY where it is undefined; any other
 * non-finite value (NaN, -INFINITY) is treated the same way and recorded as +INFINITY.
 * A GP cannot model that, so an infeasible sample is given the finite value
 *     penalty = fmax + (fmax - fmin)   (fmax, fmin over the feasible samples so far;
 *                                       when they are equal: fmax + max(|fmax|, 1);
 *                                       with no feasible sample yet: 1)
 * and every infeasible sample is re-valued whenever fmin or fmax changes. The surrogate
 * thus sees infeasible regions as clearly worse than anything feasible without the
 * unbounded jump. The history keeps the true values (+INFINITY).
 *
 * Deterministic: same seed, options and objective give the same evaluations, whatever the
 * thread. A texopt_bo is a reusable workspace for one thread. */
#ifndef TEXOPT_BAYESOPT_H
#define TEXOPT_BAYESOPT_H

#include <stdint.h>

#include "status.h"

/* The objective at x (dim coordinates in [0,1]); may return +INFINITY when infeasible. */
typedef double (*texopt_objective)(void *user, const double *x);

typedef enum texopt_acquisition {
    TEXOPT_ACQ_EI = 0, /* expected improvement (default) */
    TEXOPT_ACQ_LCB     /* lower confidence bound mean - beta * sd */
} texopt_acquisition;

/* Zero-initialised = defaults. */
typedef struct texopt_bo_options {
    int iterations;               /* model-guided evaluations after the design; 0 -> 100 */
    int initial_design;           /* Latin-hypercube points; 0 -> 2 * dim + 2, < 0 -> none */
    const double *initial_points; /* initial_point_count * dim, evaluated first; may be NULL */
    const double *initial_values; /* their objective values (+INFINITY: infeasible) when
                                     already known: they enter the surrogate without calling
                                     the objective; NULL: evaluate them */
    int initial_point_count;
    int candidates;         /* acquisition batch size; 0 -> 128 */
    int polish_evaluations; /* NLopt BOBYQA steps on the acquisition; 0 -> 10, < 0 -> off */
    int refit_every;        /* refit the length scales every max(k, n/8) samples; 0 -> 5 */
    texopt_acquisition acquisition;
    int isotropic;           /* non-zero: one length scale; 0 -> per-dimension (ARD) fit */
    double lcb_beta;         /* 0 -> 2.0 */
    double early_stop_ei;    /* stop when the best expected improvement is below this... */
    int early_stop_patience; /* ...for this many iterations in a row (the last of them is
                                not evaluated); 0 -> never stop early */
    int stall_patience;      /* stop after this many model-guided evaluations in a row that
                                lower the best value by less than stall_tolerance |best|;
                                0 -> never */
    double stall_tolerance;
    double target; /* stop as soon as a value <= target is found (when
                                has_target is non-zero) */
    int has_target;
    uint64_t seed;
} texopt_bo_options;

typedef struct texopt_bo texopt_bo;

/* A workspace for dim (1..16) dimensions and at most max_evaluations evaluations per
 * minimisation. NULL on bad arguments or out of memory. */
texopt_bo *texopt_bo_create(int dim, int max_evaluations);

/* Accepts NULL. */
void texopt_bo_destroy(texopt_bo *bo);

/* Minimises f over [0,1]^dim. Samples are capped at max_evaluations (initial points first;
 * those with known values count as samples, and `evaluations` reports all samples).
 * best_x (dim doubles), best_f and evaluations may be NULL. When no evaluated point
 * is feasible, best_f is +INFINITY and best_x the first point evaluated. Initial points
 * outside the box are clamped into it. Errors: TEXOPT_E_INVALID_ARGUMENT (bad options),
 * TEXOPT_E_NUMERIC (the surrogate failed even with raised jitter). */
texopt_status texopt_bo_minimize(texopt_bo *bo, const texopt_bo_options *opt, texopt_objective f, void *user,
                                 double *best_x, double *best_f, int *evaluations, char *err, size_t err_len);

/* The points and true objective values (+INFINITY for infeasible) of the last
 * minimisation, in evaluation order; returns their count. The pointers stay valid until
 * the next minimisation or destroy. */
int texopt_bo_history(const texopt_bo *bo, const double **x, const double **f);

#endif
