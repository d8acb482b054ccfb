/* param_lscm.c - least squares conformal map of a disk chart with two pinned vertices. Each
 * triangle, in an orthonormal frame of its plane, contributes the complex residual
 * sum_k W_k (u_k + i v_k) / sqrt(2 A) with W_k the opposite edge, which vanishes exactly
 * when the triangle's map is an orientation-preserving similarity. The real and imaginary
 * parts are two least-squares rows (sparse_spd.h); pinned vertices move to the right side. */
#include "param_lscm.h"

#include <math.h>
#include <stdlib.h>

#include "sparse_spd.h"
#include "vec3.h"

static const double *point(const texopt_param_chart *chart, uint32_t v)
{
    return chart->position + 3 * (size_t)v;
}

static double distance3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(texopt_dot3(d, d));
}

/* The boundary vertex farthest (in 3D) from boundary vertex `from`. */
static uint32_t farthest_on_boundary(const texopt_param_chart *chart, const texopt_param_boundary *b, uint32_t from)
{
    uint32_t best = b->vertex[0];
    double best_d = -1.0;
    for (size_t i = 0; i < b->count; i++) {
        double d = distance3(point(chart, from), point(chart, b->vertex[i]));
        if (d > best_d) {
            best_d = d;
            best = b->vertex[i];
        }
    }
    return best;
}

/* Adds the real and imaginary rows of triangle t. */
static texopt_status add_triangle(texopt_spd *spd, const texopt_param_chart *chart, size_t t, const int64_t *var,
                                  const double *uv)
{
    const uint32_t *tri = chart->triangle + 3 * t;
    double P[2][2];
    texopt_plane_edges(point(chart, tri[0]), point(chart, tri[1]), point(chart, tri[2]), P);
    double x[3] = {0.0, P[0][0], P[0][1]}, y[3] = {0.0, P[1][0], P[1][1]};
    double scale = 1.0 / sqrt(P[0][0] * P[1][1]); /* 1 / sqrt(2 A) */
    /* With W_k = a_k + i b_k: real row sum a_k u_k - b_k v_k, imaginary row sum b_k u_k + a_k v_k. */
    uint32_t vertex[6];
    int axis[6];
    double re[6], im[6];
    for (int k = 0; k < 3; k++) {
        double a = scale * (x[(k + 2) % 3] - x[(k + 1) % 3]), b = scale * (y[(k + 2) % 3] - y[(k + 1) % 3]);
        vertex[2 * k] = vertex[2 * k + 1] = tri[k];
        axis[2 * k] = 0;
        axis[2 * k + 1] = 1;
        re[2 * k] = a;
        re[2 * k + 1] = -b;
        im[2 * k] = b;
        im[2 * k + 1] = a;
    }
    texopt_status st = texopt_param_add_layout_row(spd, var, uv, vertex, axis, re, 6);
    return st == TEXOPT_OK ? texopt_param_add_layout_row(spd, var, uv, vertex, axis, im, 6) : st;
}

static texopt_status solve(const texopt_param_chart *chart, const uint32_t pin[2], double *uv, char *err,
                           size_t err_len)
{
    size_t nv = chart->vertex_count, free_count = 0;
    int64_t *var = malloc(nv * sizeof *var);
    double *x = malloc(2 * nv * sizeof *x);
    if (!var || !x) {
        free(var);
        free(x);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "lscm: out of memory");
    }
    for (size_t v = 0; v < nv; v++)
        var[v] = (v == pin[0] || v == pin[1]) ? -1 : (int64_t)free_count++;
    uv[2 * (size_t)pin[0]] = uv[2 * (size_t)pin[0] + 1] = 0.0;
    uv[2 * (size_t)pin[1]] = distance3(point(chart, pin[0]), point(chart, pin[1]));
    uv[2 * (size_t)pin[1] + 1] = 0.0;
    texopt_spd *spd = NULL;
    texopt_status st = TEXOPT_OK;
    if (free_count > 0)
        st = texopt_spd_create(&spd, 2 * free_count, 1, err, err_len);
    for (size_t t = 0; t < chart->triangle_count && st == TEXOPT_OK && spd; t++)
        if ((st = add_triangle(spd, chart, t, var, uv)) != TEXOPT_OK)
            st = texopt_fail(err, err_len, st, "lscm: cannot assemble the system");
    if (st == TEXOPT_OK && spd)
        st = texopt_spd_solve(spd, x, err, err_len);
    for (size_t v = 0; v < nv && st == TEXOPT_OK; v++)
        if (var[v] >= 0) {
            uv[2 * v] = x[2 * var[v]];
            uv[2 * v + 1] = x[2 * var[v] + 1];
        }
    texopt_spd_destroy(spd);
    free(var);
    free(x);
    return st;
}

texopt_status texopt_param_lscm(const texopt_param_chart *chart, double *uv, char *err, size_t err_len)
{
    if (!uv)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "lscm: NULL output");
    texopt_param_boundary *b = NULL;
    texopt_status st = texopt_param_boundary_create(&b, chart, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    /* Two sweeps of "farthest from" approximate the boundary's diameter: pins far apart keep
     * the solve well conditioned. */
    uint32_t pin[2];
    pin[0] = farthest_on_boundary(chart, b, b->vertex[0]);
    pin[1] = farthest_on_boundary(chart, b, pin[0]);
    texopt_param_boundary_destroy(b);
    return solve(chart, pin, uv, err, err_len);
}
