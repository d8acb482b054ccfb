/* chart_gap.c - the smallest distance between two charts of a layout; see chart_gap.h. */
#include "chart_gap.h"

#include <math.h>
#include <stdlib.h>

typedef struct edge {
    uint32_t a, b; /* a < b */
    uint32_t chart;
} edge;

static int compare_edges(const void *pa, const void *pb)
{
    const edge *p = pa, *q = pb;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

/* The boundary edges of the charts not skipped, into *out (caller frees); their count. */
static size_t boundary_edges(const texopt_mesh *mesh, const uint8_t *skip, edge **out)
{
    size_t n = 0, kept = 0;
    edge *e = malloc((3 * mesh->triangle_count + 1) * sizeof *e);
    *out = e;
    if (!e)
        return 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (skip && skip[mesh->chart_of[t]])
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t p = mesh->triangle[3 * t + k], q = mesh->triangle[3 * t + (k + 1) % 3];
            e[n++] = (edge){p < q ? p : q, p < q ? q : p, mesh->chart_of[t]};
        }
    }
    qsort(e, n, sizeof *e, compare_edges);
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && compare_edges(&e[i], &e[j]) == 0)
            j++;
        if (j == i + 1)
            e[kept++] = e[i];
        i = j;
    }
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
    edge *e = NULL;
    size_t n = boundary_edges(mesh, skip, &e);
    if (!e)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart gap: no memory");
    double best = INFINITY;
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++)
            if (e[i].chart != e[j].chart)
                best = fmin(best, segment_distance(x + 2 * (size_t)e[i].a, x + 2 * (size_t)e[i].b,
                                                   x + 2 * (size_t)e[j].a, x + 2 * (size_t)e[j].b));
    free(e);
    *gap = best;
    return TEXOPT_OK;
}
