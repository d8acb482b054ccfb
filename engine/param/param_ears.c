/* param_ears.c - ears peeled, the rest laid out, the ears put back (param_ears.h). */
#include "param_ears.h"

#include <stdint.h>
#include <stdlib.h>

#include "vec3.h"

static const double *point(const texopt_param_chart *chart, uint32_t v)
{
    return chart->position + 3 * (size_t)v;
}

/* The corner (0, 1, 2) of triangle t that makes it a peelable ear, else -1: all three
 * vertices on the boundary and exactly one of them, the apex, in no other triangle. */
static int ear_apex(const texopt_param_chart *chart, const texopt_param_boundary *b, const uint32_t *uses, size_t t)
{
    const uint32_t *v = chart->triangle + 3 * t;
    int apex = -1;
    for (int k = 0; k < 3; k++) {
        if (!b->on_boundary[v[k]])
            return -1;
        if (uses[v[k]] == 1) {
            if (apex >= 0)
                return -1;
            apex = k;
        }
    }
    return apex;
}

/* Marks the chart's peelable ears (apex[t] >= 0); returns how many. */
static texopt_status find_ears(const texopt_param_chart *chart, int8_t *apex, size_t *ears, char *err, size_t err_len)
{
    texopt_param_boundary *b = NULL;
    texopt_status st = texopt_param_boundary_create(&b, chart, err, err_len);
    uint32_t *uses = st == TEXOPT_OK ? calloc(chart->vertex_count, sizeof *uses) : NULL;
    if (st == TEXOPT_OK && !uses)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "ears: out of memory");
    *ears = 0;
    for (size_t i = 0; st == TEXOPT_OK && i < 3 * chart->triangle_count; i++)
        uses[chart->triangle[i]]++;
    for (size_t t = 0; st == TEXOPT_OK && t < chart->triangle_count; t++) {
        apex[t] = (int8_t)ear_apex(chart, b, uses, t);
        *ears += apex[t] >= 0;
    }
    free(uses);
    texopt_param_boundary_destroy(b);
    return st;
}

/* Signed doubled area of the layout's triangles: its orientation. */
static double layout_orientation(const texopt_param_chart *chart, const double *uv)
{
    double sum = 0.0;
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *c = uv + 2 * (size_t)v[2];
        sum += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    }
    return sum;
}

/* Puts the apex (corner k of triangle v) by the triangle's 3D shape onto its base edge's
 * layout, turned like the layout (sign +1: counter-clockwise), so it lies across the base
 * edge from the rest of the chart. */
static void put_apex(const texopt_param_chart *chart, const uint32_t *v, int k, double sign, double *uv)
{
    uint32_t a = v[(k + 1) % 3], b = v[(k + 2) % 3], p = v[k];
    double P[2][2];
    const double *ua = uv + 2 * (size_t)a, *ub = uv + 2 * (size_t)b;
    double *up = uv + 2 * (size_t)p;
    if (texopt_plane_edges(point(chart, a), point(chart, b), point(chart, p), P) != 0 || !(P[0][0] > 0.0)) {
        up[0] = 0.5 * (ua[0] + ub[0]); /* no 3D shape to keep */
        up[1] = 0.5 * (ua[1] + ub[1]);
        return;
    }
    double du = (ub[0] - ua[0]) / P[0][0], dv = (ub[1] - ua[1]) / P[0][0];
    double along = P[0][1], across = sign * P[1][1];
    up[0] = ua[0] + along * du - across * dv;
    up[1] = ua[1] + along * dv + across * du;
}

/* The chart without its ears (marked in apex): vertices renumbered through local. */
static texopt_param_chart core_of(const texopt_param_chart *chart, const int8_t *apex, uint32_t *local,
                                  double *position, uint32_t *triangle)
{
    for (size_t v = 0; v < chart->vertex_count; v++)
        local[v] = 0;
    for (size_t t = 0; t < chart->triangle_count; t++)
        if (apex[t] >= 0)
            local[chart->triangle[3 * t + (size_t)apex[t]]] = UINT32_MAX;
    size_t nv = 0, nt = 0;
    for (size_t v = 0; v < chart->vertex_count; v++)
        if (local[v] != UINT32_MAX) {
            for (int d = 0; d < 3; d++)
                position[3 * nv + (size_t)d] = chart->position[3 * v + (size_t)d];
            local[v] = (uint32_t)nv++;
        }
    for (size_t t = 0; t < chart->triangle_count; t++)
        if (apex[t] < 0) {
            for (int k = 0; k < 3; k++)
                triangle[3 * nt + (size_t)k] = local[chart->triangle[3 * t + (size_t)k]];
            nt++;
        }
    return (texopt_param_chart){nv, position, nt, triangle};
}

texopt_status texopt_param_without_ears(const texopt_param_chart *chart, texopt_param_layout_fn layout, void *context,
                                        int max_layers, double *uv, size_t *peeled, char *err, size_t err_len)
{
    if (peeled)
        *peeled = 0;
    size_t nt = chart->triangle_count, nv = chart->vertex_count, ears = 0;
    int8_t *apex = malloc(nt ? nt : 1);
    if (!apex)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "ears: out of memory");
    texopt_status st = find_ears(chart, apex, &ears, err, err_len);
    if (st != TEXOPT_OK || max_layers <= 0 || ears == 0 || nt - ears < 2) {
        free(apex);
        return st == TEXOPT_OK ? layout(chart, context, uv, err, err_len) : st;
    }
    uint32_t *local = malloc(nv * sizeof *local), *triangle = malloc(3 * (nt - ears) * sizeof *triangle);
    double *position = malloc(3 * nv * sizeof *position), *core_uv = malloc(2 * nv * sizeof *core_uv);
    if (!local || !triangle || !position || !core_uv)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "ears: out of memory");
    size_t deeper = 0;
    if (st == TEXOPT_OK) {
        texopt_param_chart core = core_of(chart, apex, local, position, triangle);
        st = texopt_param_without_ears(&core, layout, context, max_layers - 1, core_uv, &deeper, err, err_len);
        for (size_t v = 0; st == TEXOPT_OK && v < nv; v++)
            if (local[v] != UINT32_MAX) {
                uv[2 * v] = core_uv[2 * (size_t)local[v]];
                uv[2 * v + 1] = core_uv[2 * (size_t)local[v] + 1];
            }
        double sign = st == TEXOPT_OK && layout_orientation(&core, core_uv) < 0.0 ? -1.0 : 1.0;
        for (size_t t = 0; st == TEXOPT_OK && t < nt; t++)
            if (apex[t] >= 0)
                put_apex(chart, chart->triangle + 3 * t, apex[t], sign, uv);
    }
    if (st == TEXOPT_OK && peeled)
        *peeled = ears + deeper;
    free(apex);
    free(local);
    free(triangle);
    free(position);
    free(core_uv);
    return st;
}
