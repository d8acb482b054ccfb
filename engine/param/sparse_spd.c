/* sparse_spd.c - a symmetric positive definite system assembled from triplets and solved by
 * a CHOLMOD Cholesky factorisation (the library meshwise.c uses). Only the upper triangle is
 * stored; CHOLMOD sums duplicate triplets when it converts them. */
#include "sparse_spd.h"

#include <cholmod.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct texopt_spd {
    size_t n;
    int rhs_count;
    size_t count, cap;
    int *row, *col;
    double *val;
    double *rhs; /* rhs_count blocks of n */
};

texopt_status texopt_spd_create(texopt_spd **out, size_t n, int rhs_count, char *err, size_t err_len)
{
    *out = NULL;
    if (n == 0 || n > (size_t)INT32_MAX || rhs_count < 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "sparse solve: bad size %zu with %d right-hand sides", n, rhs_count);
    texopt_spd *s = calloc(1, sizeof *s);
    if (!s || !(s->rhs = calloc(n * (size_t)rhs_count, sizeof *s->rhs))) {
        free(s);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "sparse solve: out of memory");
    }
    s->n = n;
    s->rhs_count = rhs_count;
    *out = s;
    return TEXOPT_OK;
}

void texopt_spd_destroy(texopt_spd *spd)
{
    if (!spd)
        return;
    free(spd->row);
    free(spd->col);
    free(spd->val);
    free(spd->rhs);
    free(spd);
}

static int grow(texopt_spd *s)
{
    size_t cap = s->cap ? 2 * s->cap : 1024;
    int *row = realloc(s->row, cap * sizeof *row);
    if (row)
        s->row = row;
    int *col = realloc(s->col, cap * sizeof *col);
    if (col)
        s->col = col;
    double *val = realloc(s->val, cap * sizeof *val);
    if (val)
        s->val = val;
    if (!row || !col || !val)
        return -1;
    s->cap = cap;
    return 0;
}

texopt_status texopt_spd_add(texopt_spd *spd, uint32_t r, uint32_t c, double value)
{
    if (r >= spd->n || c >= spd->n)
        return TEXOPT_E_INTERNAL;
    if (spd->count == spd->cap && grow(spd) != 0)
        return TEXOPT_E_NOMEM;
    /* Upper triangle: row <= column. */
    spd->row[spd->count] = (int)(r < c ? r : c);
    spd->col[spd->count] = (int)(r < c ? c : r);
    spd->val[spd->count] = value;
    spd->count++;
    return TEXOPT_OK;
}

void texopt_spd_add_rhs(texopt_spd *spd, uint32_t r, int k, double value)
{
    spd->rhs[(size_t)k * spd->n + r] += value;
}

texopt_status texopt_spd_add_row(texopt_spd *spd, const uint32_t *cols, const double *a, int n, const double *rhs,
                                 double weight)
{
    for (int i = 0; i < n; i++) {
        for (int j = i; j < n; j++) {
            /* An off-diagonal pair (i, j) appears once here; a repeated column is a diagonal
             * entry counted twice, as a a^T requires. */
            double v = weight * a[i] * a[j];
            if (j != i && cols[i] == cols[j])
                v *= 2.0;
            texopt_status st = texopt_spd_add(spd, cols[i], cols[j], v);
            if (st != TEXOPT_OK)
                return st;
        }
        for (int k = 0; k < spd->rhs_count; k++)
            texopt_spd_add_rhs(spd, cols[i], k, weight * a[i] * rhs[k]);
    }
    return TEXOPT_OK;
}

static texopt_status factor_and_solve(texopt_spd *s, cholmod_common *cm, double *x, char *err, size_t err_len)
{
    cholmod_triplet *t = cholmod_allocate_triplet(s->n, s->n, s->count, 1, CHOLMOD_REAL, cm);
    if (!t)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "sparse solve: out of memory");
    memcpy(t->i, s->row, s->count * sizeof *s->row);
    memcpy(t->j, s->col, s->count * sizeof *s->col);
    memcpy(t->x, s->val, s->count * sizeof *s->val);
    t->nnz = s->count;
    cholmod_sparse *A = cholmod_triplet_to_sparse(t, s->count, cm);
    cholmod_free_triplet(&t, cm);
    if (!A)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "sparse solve: out of memory");
    cholmod_factor *L = cholmod_analyze(A, cm);
    texopt_status st = TEXOPT_OK;
    if (!L || !cholmod_factorize(A, L, cm) || cm->status != CHOLMOD_OK) {
        st = texopt_fail(err, err_len, TEXOPT_E_NUMERIC,
                         "sparse solve: the %zu x %zu system is not positive definite (CHOLMOD status %d)", s->n, s->n,
                         cm->status);
    } else {
        cholmod_dense *b = cholmod_allocate_dense(s->n, (size_t)s->rhs_count, s->n, CHOLMOD_REAL, cm);
        cholmod_dense *sol = NULL;
        if (b) {
            memcpy(b->x, s->rhs, s->n * (size_t)s->rhs_count * sizeof *s->rhs);
            sol = cholmod_solve(CHOLMOD_A, L, b, cm);
        }
        if (!sol) {
            st = texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "sparse solve: CHOLMOD solve failed");
        } else {
            const double *sx = sol->x;
            for (size_t i = 0; i < s->n * (size_t)s->rhs_count; i++) {
                if (!isfinite(sx[i])) {
                    st = texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "sparse solve: the solution is not finite");
                    break;
                }
                x[i] = sx[i];
            }
        }
        cholmod_free_dense(&sol, cm);
        cholmod_free_dense(&b, cm);
    }
    cholmod_free_factor(&L, cm);
    cholmod_free_sparse(&A, cm);
    return st;
}

texopt_status texopt_spd_solve(texopt_spd *spd, double *x, char *err, size_t err_len)
{
    cholmod_common cm;
    cholmod_start(&cm);
    cm.print = 0; /* errors come back as values, not on stderr */
    texopt_status st = factor_and_solve(spd, &cm, x, err, err_len);
    cholmod_finish(&cm);
    return st;
}
