/* chart_reshape.c - box fill per chart, outer boundaries, and the bounded pull of low-fill
 * charts toward their boxes through the stage-2 solve (see chart_reshape.h). */
#include "chart_reshape.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "meshwise.h"
#include "sort_keys.h"

#define PI 3.14159265358979323846
/* Pull weights tried, relative to the fitting stiffness around a vertex (meshwise.h):
 * FIRST_WEIGHT * LADDER^k for k < RUNGS. The first rung barely moves a chart, the last
 * nearly squares it. */
#define FIRST_WEIGHT 1e-4
#define LADDER 4.0
#define RUNGS 6
#define BISECTIONS 2 /* between the last rung short of the goal and the first reaching it */
#define SOLVE_ITERATIONS 30
/* w_rs of the solves: high, so that each triangle resists in proportion to its own rotation
 * and stretch weights (with w_rs = 1 every triangle is about equally stiff, w_rs w_S /
 * (w_rs + w_S) with w_S >= 1). Measured on spot's perceptual layout (c_r 0.5, charts pulled
 * to box fill 0.7, before the overlap check existed): q +131% with w_rs = 1, +20% with 100
 * (BENCHMARKS.md@9f788a8 "Packing efficiency"). */
#define FIT_WEIGHT 100.0
/* Self-overlap check: samples per chart (at most) and per triangle, and the share of
 * covered samples a reshape may add to those covered twice. */
#define OVERLAP_SAMPLES 65536
#define SAMPLES_PER_TRIANGLE 16
#define OVERLAP_SLACK 1e-3

typedef struct chart_shape {
    double area;         /* texel area of its triangles */
    double lo[2], hi[2]; /* axis-aligned box */
} chart_shape;

/* An edge of a triangle, directed as the triangle lists it, keyed by its two vertices. */
typedef struct tri_edge {
    uint64_t key; /* low vertex << 32 | high vertex */
    uint32_t from, to, tri;
} tri_edge;

typedef struct reshape {
    const texopt_mesh *mesh;
    size_t charts;
    uint32_t *chart_of_vertex; /* UINT32_MAX: no triangle */
    uint8_t *outer;            /* per vertex: on its chart's outer boundary */
    uint8_t *folded;           /* per chart: holds both input orientations */
    chart_shape *shape;        /* per chart, of the layout being measured */
    texopt_triangle_target *targets;
    tri_edge *edges; /* the boundary edges, directed as their triangle lists them */
    size_t edge_count;
    double *normal; /* per vertex: outward boundary normal (2) */
    double *anchor, *weight, *solved;
    double *pull;                       /* per chart: weight of the current solve */
    uint32_t *tri_start, *tri_of_chart; /* the triangles of each chart (CSR) */
    uint16_t *hits;                     /* OVERLAP_SAMPLES sample counters */
} reshape;

static void reshape_free(reshape *r)
{
    free(r->chart_of_vertex);
    free(r->outer);
    free(r->folded);
    free(r->shape);
    free(r->targets);
    free(r->edges);
    free(r->normal);
    free(r->tri_start);
    free(r->tri_of_chart);
    free(r->hits);
    free(r->pull);
    free(r->anchor);
    free(r->weight);
    free(r->solved);
}

static double fill_of(const chart_shape *s)
{
    double box = (s->hi[0] - s->lo[0]) * (s->hi[1] - s->lo[1]);
    return box > 0.0 ? s->area / box : 1.0;
}

/* Twice the signed area of triangle v under layout x. */
static double handed_area(const double *x, const uint32_t *v)
{
    const double *a = x + 2 * (size_t)v[0], *b = x + 2 * (size_t)v[1], *c = x + 2 * (size_t)v[2];
    return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
}

/* Area and box of every chart under layout x. */
static void measure_charts(reshape *r, const double *x)
{
    const texopt_mesh *m = r->mesh;
    for (size_t c = 0; c < r->charts; c++) {
        chart_shape *s = &r->shape[c];
        s->area = 0.0;
        s->lo[0] = s->lo[1] = INFINITY;
        s->hi[0] = s->hi[1] = -INFINITY;
    }
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        chart_shape *s = &r->shape[m->chart_of[t]];
        if (!(m->flags[t] & TEXOPT_TRI_DEGENERATE_UV))
            s->area += 0.5 * fabs(handed_area(x, v));
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 2; k++) {
                double p = x[2 * (size_t)v[j] + k];
                s->lo[k] = fmin(s->lo[k], p);
                s->hi[k] = fmax(s->hi[k], p);
            }
    }
}

static void total_fill(const reshape *r, double *fill)
{
    double area = 0.0, box = 0.0;
    for (size_t c = 0; c < r->charts; c++) {
        const chart_shape *s = &r->shape[c];
        if (!(s->hi[0] >= s->lo[0]))
            continue;
        area += s->area;
        box += (s->hi[0] - s->lo[0]) * (s->hi[1] - s->lo[1]);
    }
    *fill = box > 0.0 ? area / box : 1.0;
}

static int compare_edges(const void *a, const void *b)
{
    uint64_t x = ((const tri_edge *)a)->key, y = ((const tri_edge *)b)->key;
    return x < y ? -1 : x > y;
}

static uint32_t find_root(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

/* Every triangle's three edges, sorted by key: an edge used once is on a boundary. */
static tri_edge *sorted_edges(const texopt_mesh *m)
{
    tri_edge *e = malloc(3 * (m->triangle_count ? m->triangle_count : 1) * sizeof *e);
    if (!e)
        return NULL;
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int j = 0; j < 3; j++) {
            uint32_t a = m->triangle[3 * t + j], b = m->triangle[3 * t + (j + 1) % 3];
            tri_edge *k = &e[3 * t + j];
            k->key = texopt_edge_key(a, b);
            k->from = a;
            k->to = b;
            k->tri = (uint32_t)t;
        }
    qsort(e, 3 * m->triangle_count, sizeof *e, compare_edges);
    return e;
}

/* Keeps the boundary edges (used by one triangle) at the front of r->edges. */
static void keep_boundary_edges(reshape *r, size_t n)
{
    size_t kept = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && r->edges[j].key == r->edges[i].key)
            j++;
        if (j - i == 1)
            r->edges[kept++] = r->edges[i];
        i = j;
    }
    r->edge_count = kept;
}

/* Finds the boundary edges and marks the vertices of each chart's outer boundary: the
 * boundary loop (component of the boundary edges) through the chart's leftmost boundary
 * vertex under layout x. Holes are other loops and stay unmarked: pulled toward the box
 * they would tear the chart open. */
static texopt_status mark_outer_boundary(reshape *r, const double *x, char *err, size_t err_len)
{
    const texopt_mesh *m = r->mesh;
    size_t nv = m->vertex_count ? m->vertex_count : 1;
    r->edges = sorted_edges(m);
    uint32_t *parent = malloc(nv * sizeof *parent);
    uint32_t *leftmost = malloc((r->charts ? r->charts : 1) * sizeof *leftmost);
    uint8_t *on_boundary = calloc(nv, 1);
    if (!r->edges || !parent || !leftmost || !on_boundary) {
        free(parent);
        free(leftmost);
        free(on_boundary);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "reshape: no memory for the chart boundaries");
    }
    keep_boundary_edges(r, 3 * m->triangle_count);
    for (size_t v = 0; v < m->vertex_count; v++)
        parent[v] = (uint32_t)v;
    for (size_t i = 0; i < r->edge_count; i++) {
        uint32_t a = r->edges[i].from, b = r->edges[i].to;
        on_boundary[a] = on_boundary[b] = 1;
        parent[find_root(parent, a)] = find_root(parent, b);
    }
    for (size_t c = 0; c < r->charts; c++)
        leftmost[c] = UINT32_MAX;
    for (size_t v = 0; v < m->vertex_count; v++) {
        uint32_t c = r->chart_of_vertex[v];
        if (!on_boundary[v] || c == UINT32_MAX)
            continue;
        if (leftmost[c] == UINT32_MAX || x[2 * v] < x[2 * (size_t)leftmost[c]])
            leftmost[c] = (uint32_t)v;
    }
    for (size_t v = 0; v < m->vertex_count; v++) {
        uint32_t c = r->chart_of_vertex[v];
        r->outer[v] =
            on_boundary[v] && c != UINT32_MAX && find_root(parent, (uint32_t)v) == find_root(parent, leftmost[c]);
    }
    free(parent);
    free(leftmost);
    free(on_boundary);
    return TEXOPT_OK;
}

/* Chart of every vertex, and which charts are folded (triangles of both input
 * orientations). */
static void classify_charts(reshape *r)
{
    const texopt_mesh *m = r->mesh;
    uint8_t *seen = calloc(r->charts ? r->charts : 1, 1); /* bit 0: positive, bit 1: negative */
    for (size_t v = 0; v < m->vertex_count; v++)
        r->chart_of_vertex[v] = UINT32_MAX;
    for (size_t t = 0; t < m->triangle_count; t++) {
        uint32_t c = m->chart_of[t];
        for (int j = 0; j < 3; j++)
            r->chart_of_vertex[m->triangle[3 * t + j]] = c;
        if (seen && !(m->flags[t] & TEXOPT_TRI_DEGENERATE_UV))
            seen[c] |= (uint8_t)(m->area_texel[t] < 0 ? 2 : 1);
    }
    for (size_t c = 0; c < r->charts; c++)
        r->folded[c] = !seen || seen[c] == 3;
    free(seen);
}

/* Per triangle, a target equal to its Jacobian under layout x (so the solve starts at zero
 * fitting energy and only the pull moves it), with the caller's weights. */
static void targets_from_layout(reshape *r, const double *x, const texopt_triangle_target *given)
{
    const texopt_mesh *m = r->mesh;
    for (size_t t = 0; t < m->triangle_count; t++) {
        texopt_triangle_target *g = &r->targets[t];
        memset(g, 0, sizeof *g);
        g->lambda1 = g->lambda2 = 1.0;
        g->w_rotation = given ? given[t].w_rotation : 1.0;
        g->w_stretch = given ? given[t].w_stretch : 1.0;
        const uint32_t *v = m->triangle + 3 * t;
        const double *p0 = m->texel + 2 * (size_t)v[0], *p1 = m->texel + 2 * (size_t)v[1],
                     *p2 = m->texel + 2 * (size_t)v[2];
        const double *q0 = x + 2 * (size_t)v[0], *q1 = x + 2 * (size_t)v[1], *q2 = x + 2 * (size_t)v[2];
        double e[4] = {p1[0] - p0[0], p2[0] - p0[0], p1[1] - p0[1], p2[1] - p0[1]};
        double f[4] = {q1[0] - q0[0], q2[0] - q0[0], q1[1] - q0[1], q2[1] - q0[1]};
        double det = e[0] * e[3] - e[1] * e[2];
        if (!(fabs(det) > 0.0) || !isfinite(det))
            continue;
        /* G = F E^-1 */
        double ga = (f[0] * e[3] - f[1] * e[2]) / det, gb = (f[1] * e[0] - f[0] * e[1]) / det;
        double gc = (f[2] * e[3] - f[3] * e[2]) / det, gd = (f[3] * e[0] - f[2] * e[1]) / det;
        double angle = atan2(gc - gb, ga + gd);
        double cs = cos(angle), sn = sin(angle);
        /* S = sym(R^T G) */
        double s0 = cs * ga + sn * gc, s2 = -sn * gb + cs * gd;
        double s1 = 0.5 * ((cs * gb + sn * gd) + (-sn * ga + cs * gc));
        double mu1, mu2, theta, sm[3] = {s0, s1, s2};
        texopt_sym2_eigen(sm, &mu1, &mu2, &theta);
        if (!(mu2 > 0.0) || !(mu1 > 0.0))
            continue;
        g->alpha = fmod(fmod(angle, PI / 2) + PI / 2, PI / 2);
        texopt_target_set_stretch(g, theta, mu1, mu2);
    }
}

/* The factor (<= 1) by which a chart's box, shrunk about its centre, holds the chart's
 * area at the goal fill: pulling the boundary to that box rather than to the chart's own
 * keeps its area, where filling its own box would inflate it (and at a fixed cost every
 * other chart would pay for the inflation). */
static double shrink(const chart_shape *s, double goal)
{
    double f = fill_of(s);
    return f < goal ? sqrt(f / goal) : 1.0;
}

/* Per outer-boundary vertex, the sum of the outward normals (length-weighted) of its
 * boundary edges under layout x, into r->normal. The interior of a triangle lies left of
 * its edges when it is counter-clockwise in x, right of them otherwise. */
static void outward_normals(reshape *r, const double *x)
{
    const texopt_mesh *m = r->mesh;
    memset(r->normal, 0, 2 * m->vertex_count * sizeof *r->normal);
    for (size_t i = 0; i < r->edge_count; i++) {
        const tri_edge *e = &r->edges[i];
        if (!r->outer[e->from] || !r->outer[e->to])
            continue;
        const uint32_t *v = m->triangle + 3 * (size_t)e->tri;
        double side = handed_area(x, v) < 0 ? -1.0 : 1.0;
        double dx = x[2 * (size_t)e->to] - x[2 * (size_t)e->from];
        double dy = x[2 * (size_t)e->to + 1] - x[2 * (size_t)e->from + 1];
        for (int k = 0; k < 2; k++) {
            uint32_t p = k ? e->to : e->from;
            r->normal[2 * (size_t)p] += side * dy;
            r->normal[2 * (size_t)p + 1] -= side * dx;
        }
    }
}

/* Anchors pulling the outer boundary of every chart with pull[c] > 0 toward its box under
 * layout x: each vertex along the axis its outward normal mostly points in, to the box
 * side that way. Pulling along the boundary instead (the nearest side can lie that way,
 * e.g. inside a notch) would crush the boundary triangles. */
static void set_anchors(reshape *r, const double *x, const double *pull, double goal)
{
    const texopt_mesh *m = r->mesh;
    outward_normals(r, x);
    memset(r->weight, 0, 2 * m->vertex_count * sizeof *r->weight);
    memcpy(r->anchor, x, 2 * m->vertex_count * sizeof *r->anchor);
    for (size_t v = 0; v < m->vertex_count; v++) {
        uint32_t c = r->chart_of_vertex[v];
        if (c == UINT32_MAX || !r->outer[v] || !(pull[c] > 0.0))
            continue;
        const chart_shape *s = &r->shape[c];
        double nx = r->normal[2 * v], ny = r->normal[2 * v + 1];
        if (nx == 0.0 && ny == 0.0)
            continue;
        int axis = fabs(ny) > fabs(nx);
        double n = axis ? ny : nx;
        double mid = 0.5 * (s->lo[axis] + s->hi[axis]), half = 0.5 * (s->hi[axis] - s->lo[axis]);
        r->anchor[2 * v + axis] = mid + (n > 0 ? half : -half) * shrink(s, goal);
        r->weight[2 * v + axis] = pull[c];
    }
}

/* Triangles of each chart, in CSR form. */
static int index_chart_triangles(reshape *r)
{
    const texopt_mesh *m = r->mesh;
    r->tri_start = calloc(r->charts + 1, sizeof *r->tri_start);
    r->tri_of_chart = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *r->tri_of_chart);
    uint32_t *fill = malloc((r->charts ? r->charts : 1) * sizeof *fill);
    if (!r->tri_start || !r->tri_of_chart || !fill) {
        free(fill);
        return 0;
    }
    for (size_t t = 0; t < m->triangle_count; t++)
        r->tri_start[m->chart_of[t] + 1]++;
    for (size_t c = 0; c < r->charts; c++)
        r->tri_start[c + 1] += r->tri_start[c];
    memcpy(fill, r->tri_start, r->charts * sizeof *fill);
    for (size_t t = 0; t < m->triangle_count; t++)
        r->tri_of_chart[fill[m->chart_of[t]]++] = (uint32_t)t;
    free(fill);
    return 1;
}

/* Adds 1 to the counter of every sample (cell centre of the grid at lo, step h, nx
 * columns, ny rows) strictly inside triangle v under layout x. */
static void count_inside(uint16_t *hits, const double lo[2], double h, size_t nx, size_t ny, const double *x,
                         const uint32_t *v)
{
    const double *p[3] = {x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]};
    double area2 = handed_area(x, v);
    if (!(fabs(area2) > 0.0))
        return;
    double bl[2], bh[2];
    for (int k = 0; k < 2; k++) {
        bl[k] = fmin(fmin(p[0][k], p[1][k]), p[2][k]);
        bh[k] = fmax(fmax(p[0][k], p[1][k]), p[2][k]);
    }
    size_t n[2] = {nx, ny}, first[2], last[2];
    for (int k = 0; k < 2; k++) {
        double f = ceil((bl[k] - lo[k]) / h - 0.5), l = floor((bh[k] - lo[k]) / h - 0.5);
        first[k] = f < 0 ? 0 : (size_t)f;
        last[k] = l < 0 ? 0 : l >= (double)n[k] ? n[k] - 1 : (size_t)l;
        if (l < 0 || f > l)
            return;
    }
    double sign = area2 > 0 ? 1.0 : -1.0;
    for (size_t j = first[1]; j <= last[1]; j++)
        for (size_t i = first[0]; i <= last[0]; i++) {
            double q[2] = {lo[0] + (i + 0.5) * h, lo[1] + (j + 0.5) * h};
            int inside = 1;
            for (int e = 0; e < 3 && inside; e++) {
                const double *a = p[e], *b = p[(e + 1) % 3];
                inside = sign * ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) > 0.0;
            }
            if (inside && hits[j * nx + i] < UINT16_MAX)
                hits[j * nx + i]++;
        }
}

/* Share of the covered samples of chart c under layout x that two of its triangles cover:
 * how much the chart overlaps itself (stage 2 prevents flips, not a boundary pulled across
 * another part of the chart). */
static double overlap_share(reshape *r, uint32_t c, const double *x)
{
    const texopt_mesh *m = r->mesh;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    size_t tris = r->tri_start[c + 1] - r->tri_start[c];
    for (uint32_t k = r->tri_start[c]; k < r->tri_start[c + 1]; k++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 2; a++) {
                double p = x[2 * (size_t)m->triangle[3 * (size_t)r->tri_of_chart[k] + j] + a];
                lo[a] = fmin(lo[a], p);
                hi[a] = fmax(hi[a], p);
            }
    double samples = fmin(OVERLAP_SAMPLES, SAMPLES_PER_TRIANGLE * (double)tris);
    double h = sqrt((hi[0] - lo[0]) * (hi[1] - lo[1]) / samples);
    if (!(h > 0.0))
        return 0.0;
    size_t nx = (size_t)ceil((hi[0] - lo[0]) / h), ny = (size_t)ceil((hi[1] - lo[1]) / h);
    while (nx * ny > OVERLAP_SAMPLES) {
        h *= 1.05;
        nx = (size_t)ceil((hi[0] - lo[0]) / h);
        ny = (size_t)ceil((hi[1] - lo[1]) / h);
    }
    nx += nx == 0;
    ny += ny == 0;
    memset(r->hits, 0, nx * ny * sizeof *r->hits);
    for (uint32_t k = r->tri_start[c]; k < r->tri_start[c + 1]; k++)
        count_inside(r->hits, lo, h, nx, ny, x, m->triangle + 3 * (size_t)r->tri_of_chart[k]);
    size_t covered = 0, twice = 0;
    for (size_t i = 0; i < nx * ny; i++) {
        covered += r->hits[i] > 0;
        twice += r->hits[i] > 1;
    }
    return covered ? (double)twice / (double)covered : 0.0;
}

static texopt_status reshape_init(reshape *r, const texopt_mesh *m, const double *texel,
                                  const texopt_triangle_target *targets, char *err, size_t err_len)
{
    memset(r, 0, sizeof *r);
    r->mesh = m;
    r->charts = m->chart_count;
    size_t nv = m->vertex_count ? m->vertex_count : 1, nc = r->charts ? r->charts : 1;
    r->chart_of_vertex = malloc(nv * sizeof *r->chart_of_vertex);
    r->outer = calloc(nv, 1);
    r->folded = calloc(nc, 1);
    r->shape = calloc(nc, sizeof *r->shape);
    r->targets = calloc(m->triangle_count ? m->triangle_count : 1, sizeof *r->targets);
    r->anchor = malloc(2 * nv * sizeof *r->anchor);
    r->weight = malloc(2 * nv * sizeof *r->weight);
    r->solved = malloc(2 * nv * sizeof *r->solved);
    r->normal = malloc(2 * nv * sizeof *r->normal);
    r->hits = malloc(OVERLAP_SAMPLES * sizeof *r->hits);
    r->pull = calloc(nc, sizeof *r->pull);
    if (!r->pull || !r->chart_of_vertex || !r->outer || !r->folded || !r->shape || !r->targets || !r->anchor ||
        !r->weight || !r->solved || !r->normal || !r->hits)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "reshape: no memory for %zu vertices", m->vertex_count);
    for (size_t t = 0; t < m->triangle_count; t++)
        if (m->chart_of[t] >= r->charts)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "reshape: triangle %zu in chart %u past chart count %zu", t, m->chart_of[t], r->charts);
    if (!index_chart_triangles(r))
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "reshape: no memory for %zu charts", r->charts);
    classify_charts(r);
    targets_from_layout(r, texel, targets);
    measure_charts(r, texel);
    return mark_outer_boundary(r, texel, err, err_len);
}

/* Copies chart c's vertices from `from` to `to`. */
static void copy_chart(const reshape *r, uint32_t c, const double *from, double *to)
{
    for (size_t v = 0; v < r->mesh->vertex_count; v++)
        if (r->chart_of_vertex[v] == c) {
            to[2 * v] = from[2 * v];
            to[2 * v + 1] = from[2 * v + 1];
        }
}

/* Where a chart is on its ladder: the weight to solve with next (0: done), the strongest
 * weight known to fall short and the weakest known to reach the goal (0: none yet). */
typedef struct rung_state {
    double pull, short_of, reaching;
    double overlap;   /* its self-overlap share before the reshape */
    chart_shape best; /* of the result kept so far */
    int bisections;   /* done since the goal was first reached */
} rung_state;

/* After a solve: keeps chart c's result in texel_out when it is the best so far (the
 * weakest pull reaching the goal, else the highest fill) and picks its next weight: up the
 * ladder until the goal is reached, then BISECTIONS geometric bisections between the last
 * weight short of it and the first reaching it. A pull that folds the chart over itself
 * ends the chart's climb at the result kept. Returns 1 when the chart goes on. */
static int next_rung(reshape *r, uint32_t c, rung_state *g, double goal, double *texel_out, texopt_reshape_report *rep)
{
    if (overlap_share(r, c, r->solved) > g->overlap + OVERLAP_SLACK) {
        rep->charts_overlapping++;
        g->pull = 0.0;
        return 0;
    }
    double fill = fill_of(&r->shape[c]);
    int reaches = fill >= goal;
    if (reaches ? !(g->reaching > 0.0) || g->pull < g->reaching
                : !(g->reaching > 0.0) && fill > fill_of(&g->best)) { /* a weak pull can lose fill */
        copy_chart(r, c, r->solved, texel_out);
        g->best = r->shape[c];
    }
    if (reaches)
        g->reaching = g->reaching > 0.0 ? fmin(g->reaching, g->pull) : g->pull;
    else
        g->short_of = fmax(g->short_of, g->pull);
    if (!(g->reaching > 0.0)) {
        g->pull *= LADDER;
        return 1;
    }
    if (g->bisections == BISECTIONS || !(g->short_of > 0.0)) {
        rep->charts_reaching++;
        g->pull = 0.0;
        return 0;
    }
    g->bisections++;
    g->pull = sqrt(g->short_of * g->reaching);
    return 1;
}

/* The ladder (next_rung) for every chart below the goal at once: charts are independent
 * in the solve, so one solve serves every chart's current weight. */
static texopt_status climb(reshape *r, const double *texel, double goal, int threads, const uint8_t *keep,
                           double *texel_out, texopt_reshape_report *rep, char *err, size_t err_len)
{
    rung_state *g = calloc(r->charts ? r->charts : 1, sizeof *g);
    if (!g)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "reshape: no memory");
    int pending = 0;
    for (uint32_t c = 0; c < r->charts; c++) {
        g[c].best = r->shape[c];
        int below = fill_of(&r->shape[c]) < goal && r->shape[c].area > 0.0;
        rep->charts_below += below;
        if (below && !r->folded[c] && !(keep && keep[c])) {
            g[c].pull = FIRST_WEIGHT;
            g[c].overlap = overlap_share(r, c, texel);
            rep->charts_reshaped++;
            pending++;
        }
    }
    texopt_status st = TEXOPT_OK;
    for (int solve = 0; solve < RUNGS + BISECTIONS && pending > 0; solve++) {
        for (uint32_t c = 0; c < r->charts; c++)
            r->pull[c] = g[c].pull;
        measure_charts(r, texel); /* anchors are set on the starting boxes */
        set_anchors(r, texel, r->pull, goal);
        texopt_meshwise_options o = {.max_iterations = SOLVE_ITERATIONS,
                                     .threads = threads,
                                     .fit_weight = FIT_WEIGHT,
                                     .anchor = r->anchor,
                                     .anchor_weight = r->weight};
        st = texopt_meshwise_solve(r->mesh, r->targets, texel, &o, r->solved, NULL, NULL, err, err_len);
        if (st != TEXOPT_OK)
            break;
        rep->solves++;
        measure_charts(r, r->solved);
        pending = 0;
        for (uint32_t c = 0; c < r->charts; c++)
            if (g[c].pull > 0.0)
                pending += next_rung(r, c, &g[c], goal, texel_out, rep);
    }
    free(g);
    return st;
}

texopt_status texopt_chart_reshape(const texopt_mesh *mesh, const double *texel, const texopt_triangle_target *targets,
                                   const texopt_reshape_options *opt, double *texel_out, texopt_reshape_report *report,
                                   char *err, size_t err_len)
{
    if (!mesh || !texel || !opt || !texel_out || texel == texel_out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "reshape: NULL mesh, layout, options or output, or the output aliases the layout");
    if (!(opt->box_fill > 0.0 && opt->box_fill <= 1.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "reshape: goal box fill %g is not in (0, 1]",
                           opt->box_fill);
    texopt_reshape_report rep;
    memset(&rep, 0, sizeof rep);
    reshape r;
    texopt_status st = reshape_init(&r, mesh, texel, targets, err, err_len);
    if (st == TEXOPT_OK) {
        total_fill(&r, &rep.fill_before);
        memcpy(texel_out, texel, 2 * mesh->vertex_count * sizeof *texel_out);
        st = climb(&r, texel, opt->box_fill, opt->threads, opt->keep, texel_out, &rep, err, err_len);
    }
    if (st == TEXOPT_OK) {
        measure_charts(&r, texel_out);
        total_fill(&r, &rep.fill_after);
        if (report)
            *report = rep;
    }
    reshape_free(&r);
    return st;
}
