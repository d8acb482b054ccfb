/* sparse_spd.h - assemble and solve one sparse symmetric positive definite system.
 *
 * The parameterization methods (param_*.c) reduce to small linear problems: least squares
 * through their normal equations, or the Lagrange system of linear ABF. This builder sums
 * entries (duplicates add up), then factorises once with CHOLMOD and solves for one or more
 * right-hand sides. It does not iterate, regularise or reorder anything itself. */
#ifndef TEXOPT_SPARSE_SPD_H
#define TEXOPT_SPARSE_SPD_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

typedef struct texopt_spd texopt_spd;

/* An n x n system with `rhs_count` right-hand sides, all zero. */
texopt_status texopt_spd_create(texopt_spd **out, size_t n, int rhs_count, char *err, size_t err_len);
void texopt_spd_destroy(texopt_spd *spd);

/* A[r][c] += value and A[c][r] += value when r != c (the matrix stays symmetric). */
texopt_status texopt_spd_add(texopt_spd *spd, uint32_t r, uint32_t c, double value);

/* b_k[r] += value. */
void texopt_spd_add_rhs(texopt_spd *spd, uint32_t r, int k, double value);

/* Adds weight * (a.x - rhs_k)^2 to the least-squares energy for every right-hand side k: the
 * normal equations get weight * a a^T and weight * a * rhs_k. a has n entries at cols[];
 * rhs has rhs_count entries. */
texopt_status texopt_spd_add_row(texopt_spd *spd, const uint32_t *cols, const double *a, int n, const double *rhs,
                                 double weight);

/* Solves A x_k = b_k; x holds rhs_count consecutive blocks of n. Fails with
 * TEXOPT_E_NUMERIC when A is not positive definite or the solution is not finite. */
texopt_status texopt_spd_solve(texopt_spd *spd, double *x, char *err, size_t err_len);

#endif
