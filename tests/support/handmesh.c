/* handmesh.c - see handmesh.h. */
#include "handmesh.h"

#include <math.h>
#include <stdlib.h>

texopt_mesh *handmesh_alloc(size_t nv, size_t nt)
{
    texopt_mesh *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->vertex_count = m->point_count = nv;
    m->triangle_count = nt;
    m->width = m->height = 256;
    m->chart_count = 1;
    m->texel = calloc(2 * nv, sizeof(double));
    m->point_of = calloc(nv, sizeof(uint32_t));
    m->position = calloc(3 * nv, sizeof(double));
    m->triangle = calloc(3 * nt, sizeof(uint32_t));
    m->area_3d = calloc(nt, sizeof(double));
    m->area_texel = calloc(nt, sizeof(double));
    m->flags = calloc(nt, 1);
    m->chart_of = calloc(nt, sizeof(uint32_t));
    if (!m->texel || !m->point_of || !m->position || !m->triangle || !m->area_3d || !m->area_texel || !m->flags ||
        !m->chart_of) {
        texopt_mesh_destroy(m);
        return NULL;
    }
    for (size_t v = 0; v < nv; v++)
        m->point_of[v] = (uint32_t)v;
    return m;
}

double handmesh_doubled_area(const double *p, const uint32_t *t, int stride)
{
    const double *a = p + stride * t[0], *b = p + stride * t[1], *c = p + stride * t[2];
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

static double area_3d(const double *p, const uint32_t *t)
{
    const double *a = p + 3 * t[0], *b = p + 3 * t[1], *c = p + 3 * t[2];
    double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, f[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double x = e[1] * f[2] - e[2] * f[1], y = e[2] * f[0] - e[0] * f[2], z = e[0] * f[1] - e[1] * f[0];
    return 0.5 * sqrt(x * x + y * y + z * z);
}

void handmesh_finish(texopt_mesh *m)
{
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangle + 3 * t;
        double a3 = area_3d(m->position, tri);
        double at = 0.5 * handmesh_doubled_area(m->texel, tri, 2);
        m->area_3d[t] = a3;
        m->area_texel[t] = at;
        m->flags[t] = (uint8_t)((a3 < 1e-14 ? TEXOPT_TRI_DEGENERATE_3D : 0) |
                                (fabs(at) < 1e-12 ? TEXOPT_TRI_DEGENERATE_UV : 0) | (at < 0 ? TEXOPT_TRI_FLIPPED : 0));
    }
}

int handmesh_barycentric(const texopt_mesh *m, size_t t, const double p[2], double w[3])
{
    const uint32_t *tri = m->triangle + 3 * t;
    const double *a = m->texel + 2 * tri[0], *b = m->texel + 2 * tri[1], *c = m->texel + 2 * tri[2];
    double det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    w[1] = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / det;
    w[2] = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / det;
    w[0] = 1.0 - w[1] - w[2];
    return w[0] >= -1e-9 && w[1] >= -1e-9 && w[2] >= -1e-9;
}
