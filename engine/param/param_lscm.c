/* param_lscm.c - least squares conformal map of a disk chart with two pinned vertices. Each
 * triangle, in an orthonormal frame of its plane, contributes the complex residual
 * sum_k W_k (u_k + i v_k) / sqrt(2 A) with W_k the opposite edge, which vanishes exactly
 * when the triangle's map is an orientation-preserving similarity. The real and imaginary
 * parts are two least-squares rows (sparse_spd.h); pinned vertices move to the right side. */
#include "param_lscm.h"

#include <math.h>

#include "sparse_spd.h"
#include "vec3.h"

static const double *point(const texopt_param_chart *chart, uint32_t v)
{
    return chart->position + 3 * (size_t)v;
}

/* The boundary vertex farthest (in 3D) from boundary vertex `from`. */
static uint32_t farthest_on_boundary(const texopt_param_chart *chart, const texopt_param_boundary *b, uint32_t from)
{
    uint32_t best = b->vertex[0];
    double best_d = -1.0;
    for (size_t i = 0; i < b->count; i++) {
        double d = texopt_distance3(point(chart, from), point(chart, b->vertex[i]));
        if (d > best_d) {
            best_d = d;
            best = b->vertex[i];
        }
    }
    return best;
}

/* Adds the real and imaginary rows of triangle t. */
static texopt_status add_triangle(texopt_spd *spd, const void *context, size_t t, const int64_t *var, const double *uv)
{
    const texopt_param_chart *chart = context;
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
    return texopt_param_solve_pinned(chart, pin, add_triangle, chart, uv, err, err_len);
}
