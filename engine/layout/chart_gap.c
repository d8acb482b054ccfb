/* chart_gap.c - the smallest distance between two charts of a layout; see chart_gap.h. */
#include "chart_gap.h"

#include <math.h>
#include <stdlib.h>

typedef struct keyed_edge {
    uint64_t key; /* smaller vertex, larger vertex */
    texopt_boundary_edge e;
} keyed_edge;

static int compare_keys(const void *pa, const void *pb)
{
    uint64_t p = ((const keyed_edge *)pa)->key, q = ((const keyed_edge *)pb)->key;
    return p < q ? -1 : p > q;
}

size_t texopt_boundary_edges(const texopt_mesh *mesh, texopt_boundary_edge **out)
{
    size_t n = 3 * mesh->triangle_count, kept = 0;
    keyed_edge *k = malloc((n ? n : 1) * sizeof *k);
    *out = malloc((n ? n : 1) * sizeof **out);
    if (!k || !*out) {
        free(k);
        free(*out);
        *out = NULL;
        return 0;
    }
    for (size_t t = 0; t < mesh->triangle_count; t++)
        for (int j = 0; j < 3; j++) {
            uint32_t p = mesh->triangle[3 * t + j], q = mesh->triangle[3 * t + (j + 1) % 3];
            k[3 * t + j].key = p < q ? (uint64_t)p << 32 | q : (uint64_t)q << 32 | p;
            k[3 * t + j].e = (texopt_boundary_edge){p, q, (uint32_t)t};
        }
    qsort(k, n, sizeof *k, compare_keys);
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && k[j].key == k[i].key)
            j++;
        if (j == i + 1)
            (*out)[kept++] = k[i].e;
        i = j;
    }
    free(k);
    return kept;
}

static double cross(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static double point_segment(const double *p, const double *a, const double *b)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
    double u = len2 > 0.0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0.0;
    u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
    return hypot(p[0] - a[0] - u * dx, p[1] - a[1] - u * dy);
}

/* 0 when the segments cross or touch, else the smallest of the four end-to-segment
 * distances. */
static double segment_distance(const double *a, const double *b, const double *c, const double *d)
{
    double d1 = cross(a, b, c), d2 = cross(a, b, d), d3 = cross(c, d, a), d4 = cross(c, d, b);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return 0.0;
    return fmin(fmin(point_segment(a, c, d), point_segment(b, c, d)),
                fmin(point_segment(c, a, b), point_segment(d, a, b)));
}

texopt_status texopt_chart_gap(const texopt_mesh *mesh, const double *x, const uint8_t *skip, double *gap, char *err,
                               size_t err_len)
{
    texopt_boundary_edge *e = NULL;
    size_t n = texopt_boundary_edges(mesh, &e), kept = 0;
    if (!e)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart gap: no memory");
    for (size_t i = 0; i < n; i++)
        if (!skip || !skip[mesh->chart_of[e[i].triangle]])
            e[kept++] = e[i];
    double best = INFINITY;
    for (size_t i = 0; i < kept; i++)
        for (size_t j = i + 1; j < kept; j++)
            if (mesh->chart_of[e[i].triangle] != mesh->chart_of[e[j].triangle])
                best = fmin(best, segment_distance(x + 2 * (size_t)e[i].from, x + 2 * (size_t)e[i].to,
                                                   x + 2 * (size_t)e[j].from, x + 2 * (size_t)e[j].to));
    free(e);
    *gap = best;
    return TEXOPT_OK;
}
