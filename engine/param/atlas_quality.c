/* atlas_quality.c - Liu et al. 2019's PE, BL and CN of a layout; see atlas_quality.h. */
#include "atlas_quality.h"

#include <cjson/cJSON.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "vec3.h"

/* One triangle edge: its 3D points and its layout vertices, each pair in increasing order. */
typedef struct half_edge {
    uint32_t p0, p1, v0, v1;
} half_edge;

static int compare_half_edges(const void *a, const void *b)
{
    const half_edge *x = a, *y = b;
    if (x->p0 != y->p0)
        return x->p0 < y->p0 ? -1 : 1;
    if (x->p1 != y->p1)
        return x->p1 < y->p1 ? -1 : 1;
    if (x->v0 != y->v0)
        return x->v0 < y->v0 ? -1 : 1;
    return x->v1 < y->v1 ? -1 : x->v1 > y->v1;
}

/* The 3D length of the edges whose triangles do not all share one layout edge. */
static texopt_status cut_length(const texopt_mesh *mesh, double *out, char *err, size_t err_len)
{
    size_t n = 3 * mesh->triangle_count;
    half_edge *e = malloc(n * sizeof *e);
    if (!e)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "out of memory for %zu edges", n);
    for (size_t t = 0; t < mesh->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = mesh->triangle[3 * t + k], b = mesh->triangle[3 * t + (k + 1) % 3];
            uint32_t pa = mesh->point_of[a], pb = mesh->point_of[b];
            e[3 * t + k] = (half_edge){pa < pb ? pa : pb, pa < pb ? pb : pa, a < b ? a : b, a < b ? b : a};
        }
    qsort(e, n, sizeof *e, compare_half_edges);
    double length = 0;
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && e[j].p0 == e[i].p0 && e[j].p1 == e[i].p1;)
            j++;
        if (e[i].v0 != e[j - 1].v0 || e[i].v1 != e[j - 1].v1)
            length += texopt_distance3(mesh->position + 3 * (size_t)e[i].p0, mesh->position + 3 * (size_t)e[i].p1);
    }
    free(e);
    *out = length;
    return TEXOPT_OK;
}

static double surface_diagonal(const texopt_mesh *mesh)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (size_t i = 0; i < 3 * mesh->triangle_count; i++) {
        const double *p = mesh->position + 3 * (size_t)mesh->point_of[mesh->triangle[i]];
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], p[c]);
            hi[c] = fmax(hi[c], p[c]);
        }
    }
    double d2 = 0;
    for (int c = 0; c < 3; c++)
        d2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    return mesh->triangle_count ? sqrt(d2) : 0;
}

static double box_area(const texopt_mesh *mesh, const double *texel)
{
    double lo[2] = {DBL_MAX, DBL_MAX}, hi[2] = {-DBL_MAX, -DBL_MAX};
    for (size_t i = 0; i < 3 * mesh->triangle_count; i++) {
        const double *p = texel + 2 * (size_t)mesh->triangle[i];
        for (int c = 0; c < 2; c++) {
            lo[c] = fmin(lo[c], p[c]);
            hi[c] = fmax(hi[c], p[c]);
        }
    }
    return mesh->triangle_count ? (hi[0] - lo[0]) * (hi[1] - lo[1]) : 0;
}

texopt_status texopt_atlas_quality_measure(const texopt_mesh *mesh, const double *texel, texopt_atlas_quality *out,
                                           char *err, size_t err_len)
{
    if (!texel)
        texel = mesh->texel;
    double box = box_area(mesh, texel), diagonal = surface_diagonal(mesh);
    if (!(box > 0) || !(diagonal > 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "the layout or the surface has no extent");
    double cut = 0;
    texopt_status st = cut_length(mesh, &cut, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    out->packing_efficiency = texopt_layout_area(mesh, texel, NULL) / box;
    out->boundary_length = cut / diagonal;
    out->charts = mesh->chart_count;
    return TEXOPT_OK;
}

cJSON *texopt_atlas_quality_json(const texopt_atlas_quality *q)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddNumberToObject(o, "packing_efficiency", q->packing_efficiency);
    cJSON_AddNumberToObject(o, "boundary_length", q->boundary_length);
    cJSON_AddNumberToObject(o, "charts", (double)q->charts);
    return o;
}
