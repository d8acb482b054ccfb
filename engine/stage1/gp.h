/* gp.h - Gaussian-process regression with a Matern 5/2 kernel, for Bayesian optimisation.
 *
 * Rasmussen and Williams 2006, "Gaussian Processes for Machine Learning", algorithm 2.1
 * (Cholesky-based prediction) and eq. 4.17 (Matern nu = 5/2). Inputs live in the unit box.
 * The kernel is k(r) = (1 + sqrt5 r + 5r^2/3) exp(-sqrt5 r), r the distance scaled by the
 * length scale l (isotropic, or per dimension l * m_k with ARD), unit signal variance, plus a small relative noise (jitter) on the diagonal; the
 * targets are standardised internally (mean 0, variance 1) and predictions are returned on
 * the original scale, so the kernel matrix depends only on the inputs and l.
 *
 * Incremental: adding a sample appends one row to the Cholesky factor (O(n^2));
 * changing l or the jitter refactors (O(n^3)); changing a target value (infeasible samples
 * re-evaluated by bayesopt) only recomputes the weights (O(n^2)). Prediction is batched over
 * many candidates with BLAS (dgemv/dtrsm). One GP is for one thread at a time.
 *
 * Not here: the acquisition function and the search (bayesopt.h). */
#ifndef TEXOPT_GP_H
#define TEXOPT_GP_H

#include "status.h"

typedef struct texopt_gp texopt_gp;

/* A GP in dim dimensions holding up to max_samples samples and predicting up to
 * max_batch points per call. NULL on bad arguments or out of memory. Starts empty with
 * length scale 0.3 and jitter 1e-6. */
texopt_gp *texopt_gp_create(int dim, int max_samples, int max_batch);

/* Accepts NULL. */
void texopt_gp_destroy(texopt_gp *gp);

/* Forgets every sample (keeps the hyper-parameters). */
void texopt_gp_clear(texopt_gp *gp);

int texopt_gp_count(const texopt_gp *gp);
double texopt_gp_length_scale(const texopt_gp *gp);

/* Sets the length scale (> 0) and jitter (>= 0, relative to the unit signal variance) and
 * refactors. TEXOPT_E_NUMERIC when the kernel matrix is not positive definite even with
 * the jitter raised 100-fold. */
texopt_status texopt_gp_set_hyper(texopt_gp *gp, double length_scale, double jitter);

/* Appends a sample (x in dim coordinates, y finite). Incremental Cholesky update.
 * TEXOPT_E_LIMIT when full; TEXOPT_E_INVALID_ARGUMENT for a non-finite y;
 * TEXOPT_E_NUMERIC when the new pivot is not positive (a duplicate point with zero jitter). */
texopt_status texopt_gp_add(texopt_gp *gp, const double *x, double y);

/* Changes the target of sample i (finite). */
void texopt_gp_set_y(texopt_gp *gp, int i, double y);

/* Log marginal likelihood of the standardised targets under the current hyper-parameters. */
double texopt_gp_log_likelihood(texopt_gp *gp);

/* Tries each candidate length scale and keeps the one with the largest marginal
 * likelihood (a cheap, robust stand-in for gradient-based fitting). */
texopt_status texopt_gp_fit_length_scale(texopt_gp *gp, const double *candidates, int count);

/* Automatic relevance determination: per-dimension length-scale multipliers m_k (the
 * effective length scale of dimension k is length_scale * m_k; 1 = isotropic, the start).
 * Refactors. */
texopt_status texopt_gp_set_dimension_scales(texopt_gp *gp, const double *multipliers);

/* One coordinate pass: each multiplier is halved or doubled (within [1/16, 16]) when that
 * raises the marginal likelihood. 2 * dim refactorisations. */
texopt_status texopt_gp_fit_dimension_scales(texopt_gp *gp);

/* Posterior mean and variance at m points (x is m * dim, row-major), computed in chunks
 * of max_batch.
 * var may be NULL. With no samples: the prior (mean 0, variance 1). */
void texopt_gp_predict(texopt_gp *gp, int m, const double *x, double *mean, double *var);

/* The lower Cholesky factor, n x n column-major with leading dimension max_samples
 * (tests compare it with a full factorisation). */
const double *texopt_gp_cholesky(const texopt_gp *gp, int *leading_dimension);

#endif
