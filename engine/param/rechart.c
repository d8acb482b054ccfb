/* rechart.c - region growing into disk charts and their layout by a parameterization method
 * (rechart.h). */
#include "rechart.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "param_abf.h"
#include "param_ears.h"
#include "param_lscm.h"
#include "param_square.h"
#include "param_tutte.h"
#include "sort_keys.h"
#include "vec3.h"

void texopt_rechart_destroy(texopt_rechart *rechart)
{
    if (!rechart)
        return;
    free(rechart->chart_of);
    free(rechart->corner_uv);
    free(rechart);
}

typedef struct context {
    const texopt_mesh *mesh;
    texopt_rechart_options opt;
    texopt_rechart *out;
    uint32_t *across;   /* 3 per triangle: the triangle across edge k, UINT32_MAX when none */
    double *normal;     /* 3 per triangle */
    uint32_t *local_of; /* per point: its chart-local vertex, UINT32_MAX outside the chart */
    double *position;   /* scratch: 3 per local vertex */
    uint32_t *triangle; /* scratch: 3 per chart triangle */
    uint32_t *point_of_local;
    double *uv;     /* scratch: 2 per local vertex */
    uint32_t *mark; /* per triangle: mark_serial while in the set being split (components) */
    uint32_t mark_serial;
} context;

static int is_degenerate(const context *c, size_t t)
{
    return (c->mesh->flags[t] & TEXOPT_TRI_DEGENERATE_3D) != 0;
}

/* Triangles across each manifold 3D edge (an edge of exactly two triangles). Half-edges are
 * sorted as (edge key, half-edge index) pairs; qsort compares the key, the first word. */
static int find_neighbours(context *c)
{
    const texopt_mesh *m = c->mesh;
    size_t nh = 3 * m->triangle_count;
    uint64_t *pair = malloc(2 * nh * sizeof *pair);
    if (!pair)
        return -1;
    for (size_t h = 0; h < nh; h++) {
        uint32_t a = m->point_of[m->triangle[h]], b = m->point_of[m->triangle[h - h % 3 + (h % 3 + 1) % 3]];
        pair[2 * h] = texopt_edge_key(a, b);
        pair[2 * h + 1] = h;
        c->across[h] = UINT32_MAX;
    }
    qsort(pair, nh, 2 * sizeof *pair, texopt_compare_u64);
    for (size_t i = 0; i < nh;) {
        size_t j = i;
        while (j < nh && pair[2 * j] == pair[2 * i])
            j++;
        if (j - i == 2) {
            size_t h0 = (size_t)pair[2 * i + 1], h1 = (size_t)pair[2 * i + 3];
            c->across[h0] = (uint32_t)(h1 / 3);
            c->across[h1] = (uint32_t)(h0 / 3);
        }
        i = j;
    }
    free(pair);
    return 0;
}

static void triangle_normals(context *c)
{
    const texopt_mesh *m = c->mesh;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        const double *a = texopt_mesh_vertex_point(m, v[0]), *b = texopt_mesh_vertex_point(m, v[1]),
                     *p = texopt_mesh_vertex_point(m, v[2]);
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        texopt_cross3(e1, e2, c->normal + 3 * t);
        texopt_normalize3(c->normal + 3 * t);
    }
}

/* Layers of ears the square method peels (param_ears.h): grown charts' boundaries are
 * jagged, an ear often sits on the next one. */
#define RECHART_EAR_LAYERS 3

static texopt_status square_layout(const texopt_param_chart *chart, void *params, double *uv, char *err, size_t err_len)
{
    return texopt_param_square(chart, params, uv, NULL, err, err_len);
}

static texopt_status run_method(texopt_parameterizer method, const texopt_param_chart *chart, double *uv)
{
    char err[256];
    switch (method) {
    case TEXOPT_PARAMETERIZER_LSCM: return texopt_param_lscm(chart, uv, err, sizeof err);
    case TEXOPT_PARAMETERIZER_ABF: return texopt_param_abf(chart, uv, NULL, err, sizeof err);
    case TEXOPT_PARAMETERIZER_TUTTE: return texopt_param_tutte(chart, uv, err, sizeof err);
    case TEXOPT_PARAMETERIZER_SQUARE: {
        texopt_square_params p;
        texopt_square_params_default(&p);
        return texopt_param_without_ears(chart, square_layout, &p, RECHART_EAR_LAYERS, uv, NULL, err, sizeof err);
    }
    case TEXOPT_PARAMETERIZER_COUNT: break;
    }
    return TEXOPT_E_INVALID_ARGUMENT;
}

/* The chart-local copy of triangles tris[0..n) (vertices welded by 3D point). */
static texopt_param_chart local_chart(context *c, const uint32_t *tris, size_t n)
{
    const texopt_mesh *m = c->mesh;
    size_t nv = 0;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t p = m->point_of[m->triangle[3 * (size_t)tris[i] + k]];
            if (c->local_of[p] == UINT32_MAX) {
                c->local_of[p] = (uint32_t)nv;
                c->point_of_local[nv] = p;
                memcpy(c->position + 3 * nv, m->position + 3 * (size_t)p, 3 * sizeof(double));
                nv++;
            }
            c->triangle[3 * i + (size_t)k] = c->local_of[p];
        }
    return (texopt_param_chart){nv, c->position, n, c->triangle};
}

static void forget_local(context *c, size_t nv)
{
    for (size_t v = 0; v < nv; v++)
        c->local_of[c->point_of_local[v]] = UINT32_MAX;
}

/* Writes the layout of one chart, its box moved to start at (0, 0). */
static void store_chart(context *c, const uint32_t *tris, const texopt_param_chart *chart)
{
    double lo[2] = {INFINITY, INFINITY};
    for (size_t v = 0; v < chart->vertex_count; v++)
        for (int k = 0; k < 2; k++)
            lo[k] = fmin(lo[k], c->uv[2 * v + k]);
    uint32_t id = (uint32_t)c->out->chart_count++;
    for (size_t i = 0; i < chart->triangle_count; i++) {
        c->out->chart_of[tris[i]] = id;
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++)
                c->out->corner_uv[6 * (size_t)tris[i] + 2 * (size_t)k + (size_t)a] =
                    c->uv[2 * (size_t)chart->triangle[3 * i + (size_t)k] + (size_t)a] - lo[a];
    }
}

/* The chart's layout by the method, by Tutte when the method fails or flips a triangle.
 * *overlaps: the method's layout overlaps itself (not checked for Tutte's, a bijection). */
static texopt_status layout_chart(context *c, const texopt_param_chart *chart, const texopt_param_boundary *b,
                                  int *overlaps)
{
    char err[256];
    *overlaps = 0;
    texopt_status st = run_method(c->opt.method, chart, c->uv);
    if (st == TEXOPT_E_NOMEM)
        return st;
    if (st != TEXOPT_OK || texopt_param_flips(chart, c->uv) > 0) {
        c->out->fallback_charts++;
        return texopt_param_tutte(chart, c->uv, err, sizeof err);
    }
    *overlaps = texopt_param_boundary_crosses(b, c->uv);
    return TEXOPT_OK;
}

static texopt_status layout_region(context *c, uint32_t *tris, size_t n);

/* Lays out tris[0..n) one connected component (through shared edges) at a time, each
 * reordered breadth first, so that its halves stay connected if it must be split again. */
static texopt_status layout_components(context *c, uint32_t *tris, size_t n)
{
    uint32_t *bfs = malloc(n * sizeof *bfs), serial = ++c->mark_serial;
    size_t *end = malloc(n * sizeof *end), components = 0, m = 0;
    if (!bfs || !end) {
        free(bfs);
        free(end);
        return TEXOPT_E_NOMEM;
    }
    for (size_t i = 0; i < n; i++)
        c->mark[tris[i]] = serial;
    for (size_t i = 0; i < n; i++) {
        if (c->mark[tris[i]] != serial)
            continue;
        size_t head = m;
        bfs[m++] = tris[i];
        c->mark[tris[i]] = 0;
        while (head < m) {
            uint32_t t = bfs[head++];
            for (int k = 0; k < 3; k++) {
                uint32_t u = c->across[3 * (size_t)t + (size_t)k];
                if (u != UINT32_MAX && c->mark[u] == serial) {
                    c->mark[u] = 0;
                    bfs[m++] = u;
                }
            }
        }
        end[components++] = m;
    }
    memcpy(tris, bfs, n * sizeof *tris);
    free(bfs);
    texopt_status st = TEXOPT_OK;
    for (size_t k = 0, from = 0; k < components && st == TEXOPT_OK; from = end[k++])
        st = layout_region(c, tris + from, end[k] - from);
    free(end);
    return st;
}

/* Lays out triangles tris[0..n) as one chart, or as two halves (recursively) when they are
 * not a disk or their layout overlaps itself: the first half (a prefix of the breadth-first
 * growth, connected) and the rest one connected component at a time. A single
 * non-degenerate triangle is always a disk laid out without overlap. */
static texopt_status layout_region(context *c, uint32_t *tris, size_t n)
{
    texopt_param_chart chart = local_chart(c, tris, n);
    texopt_param_boundary *b = NULL;
    char err[256];
    int overlaps = 0;
    texopt_status st = texopt_param_boundary_create(&b, &chart, err, sizeof err);
    if (st == TEXOPT_OK)
        st = layout_chart(c, &chart, b, &overlaps);
    texopt_param_boundary_destroy(b);
    if ((st == TEXOPT_E_INVALID_ARGUMENT || overlaps) && n > 1) {
        c->out->overlap_splits += overlaps;
        forget_local(c, chart.vertex_count);
        st = layout_region(c, tris, n / 2);
        return st == TEXOPT_OK ? layout_components(c, tris + n / 2, n - n / 2) : st;
    }
    if (st == TEXOPT_OK)
        store_chart(c, tris, &chart);
    forget_local(c, chart.vertex_count);
    return st;
}

/* The region bookkeeping of one growth: which triangles and how many of its triangles use
 * each point (both reset after the region). */
typedef struct region {
    uint32_t *region_of;  /* per triangle: the serial of the region holding it, 0 = none */
    uint32_t *point_uses; /* per point: triangles of the current region using it */
    uint32_t serial;
} region;

static uint32_t point_at(const context *c, uint32_t t, int k)
{
    return c->mesh->point_of[c->mesh->triangle[3 * (size_t)t + (size_t)k]];
}

/* Adding triangle u keeps the region a disk when its vertex off the shared edge is new to
 * the region, or when u fills a notch (two of its edges shared, that vertex already in). A
 * vertex touched a second time through one edge would pinch the boundary. */
static int keeps_disk(const context *c, const region *g, uint32_t u)
{
    int shared = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t w = c->across[3 * (size_t)u + (size_t)k];
        shared += w != UINT32_MAX && g->region_of[w] == g->serial;
    }
    int new_points = 0;
    for (int k = 0; k < 3; k++)
        new_points += g->point_uses[point_at(c, u, k)] == 0;
    return (shared == 1 && new_points == 1) || (shared == 2 && new_points == 0);
}

static void add_to_region(const context *c, region *g, uint32_t t, uint32_t *order, size_t *n)
{
    g->region_of[t] = g->serial;
    for (int k = 0; k < 3; k++)
        g->point_uses[point_at(c, t, k)]++;
    order[(*n)++] = t;
}

/* The input layout's linear texel density of triangle t (texels per world unit), 0 when it
 * has no texel area: new charts keep the input's resolution only where it is even. */
static double input_density(const context *c, uint32_t t)
{
    const texopt_mesh *m = c->mesh;
    return (m->flags[t] & TEXOPT_TRI_DEGENERATE_UV) ? 0 : sqrt(fabs(m->area_texel[t]) / m->area_3d[t]);
}

/* Whether u's input density is within the ratio of the seed's (either without one joins). */
static int density_fits(const context *c, double seed_density, uint32_t u)
{
    double r = c->opt.density_ratio, d = input_density(c, u);
    return !(r > 0) || !(d > 0) || !(seed_density > 0) || (d <= r * seed_density && seed_density <= r * d);
}

/* Whether the region may grow from t into its 3D neighbour u: always where they share the
 * edge's texel corners, across an input seam where the caller's test allows it. */
static int may_cross_seam(const context *c, uint32_t t, uint32_t u)
{
    if (!c->opt.may_cross)
        return 1;
    int shared = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            shared += c->mesh->triangle[3 * (size_t)t + (size_t)a] == c->mesh->triangle[3 * (size_t)u + (size_t)b];
    return shared >= 2 || c->opt.may_cross(c->opt.cross_context, t, u);
}

/* Grows one region from `seed` breadth first into order[]; returns its size. */
static size_t grow(const context *c, region *g, uint32_t seed, uint32_t *order)
{
    const double to_rad = 3.14159265358979323846 / 180.0;
    double cos_crease = cos(c->opt.crease_degrees * to_rad), cos_cone = cos(c->opt.cone_degrees * to_rad);
    const double *seed_normal = c->normal + 3 * (size_t)seed;
    double seed_density = input_density(c, seed);
    size_t n = 0, head = 0;
    g->serial++;
    add_to_region(c, g, seed, order, &n);
    while (head < n && n < c->opt.max_triangles) {
        uint32_t t = order[head++];
        for (int k = 0; k < 3 && n < c->opt.max_triangles; k++) {
            uint32_t u = c->across[3 * (size_t)t + (size_t)k];
            if (u == UINT32_MAX || g->region_of[u] || is_degenerate(c, u) ||
                texopt_dot3(c->normal + 3 * (size_t)t, c->normal + 3 * (size_t)u) < cos_crease ||
                texopt_dot3(seed_normal, c->normal + 3 * (size_t)u) < cos_cone || !density_fits(c, seed_density, u) ||
                !may_cross_seam(c, t, u) || !keeps_disk(c, g, u))
                continue;
            add_to_region(c, g, u, order, &n);
        }
    }
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            g->point_uses[point_at(c, order[i], k)] = 0;
    return n;
}

static texopt_status check_options(texopt_rechart_options *opt, char *err, size_t err_len)
{
    if (opt->crease_degrees == 0.0)
        opt->crease_degrees = 60.0;
    if (opt->cone_degrees == 0.0)
        opt->cone_degrees = 75.0;
    if (opt->max_triangles == 0)
        opt->max_triangles = 5000;
    if (!texopt_parameterizer_name(opt->method) || !(opt->crease_degrees > 0.0 && opt->crease_degrees <= 180.0) ||
        !(opt->cone_degrees > 0.0 && opt->cone_degrees <= 180.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rechart: options out of range");
    return TEXOPT_OK;
}

static void context_free(context *c)
{
    free(c->across);
    free(c->normal);
    free(c->local_of);
    free(c->position);
    free(c->triangle);
    free(c->point_of_local);
    free(c->uv);
    free(c->mark);
}

static int context_alloc(context *c)
{
    size_t nt = c->mesh->triangle_count, cap = c->opt.max_triangles < nt ? c->opt.max_triangles : nt;
    c->across = malloc(3 * nt * sizeof *c->across);
    c->normal = malloc(3 * nt * sizeof *c->normal);
    c->local_of = malloc((c->mesh->point_count ? c->mesh->point_count : 1) * sizeof *c->local_of);
    c->position = malloc(9 * cap * sizeof *c->position);
    c->triangle = malloc(3 * cap * sizeof *c->triangle);
    c->point_of_local = malloc(3 * cap * sizeof *c->point_of_local);
    c->uv = malloc(6 * cap * sizeof *c->uv);
    c->mark = calloc(nt, sizeof *c->mark);
    if (!c->mark || !c->across || !c->normal || !c->local_of || !c->position || !c->triangle || !c->point_of_local ||
        !c->uv)
        return -1;
    for (size_t p = 0; p < c->mesh->point_count; p++)
        c->local_of[p] = UINT32_MAX;
    return 0;
}

static texopt_status make_charts(context *c, char *err, size_t err_len)
{
    size_t nt = c->mesh->triangle_count;
    region g = {.region_of = calloc(nt, sizeof *g.region_of),
                .point_uses = calloc(c->mesh->point_count ? c->mesh->point_count : 1, sizeof *g.point_uses)};
    uint32_t *order = malloc((c->opt.max_triangles < nt ? c->opt.max_triangles : nt) * sizeof *order);
    texopt_status st = TEXOPT_OK;
    if (!g.region_of || !g.point_uses || !order || find_neighbours(c) != 0)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rechart: out of memory");
    if (st == TEXOPT_OK)
        triangle_normals(c);
    for (size_t t = 0; t < nt && st == TEXOPT_OK; t++) {
        if (is_degenerate(c, t)) {
            c->out->chart_of[t] = (uint32_t)c->out->chart_count++; /* corners stay at (0, 0) */
            continue;
        }
        if (g.region_of[t])
            continue;
        size_t n = grow(c, &g, (uint32_t)t, order);
        st = layout_region(c, order, n);
        if (st != TEXOPT_OK)
            st = texopt_fail(err, err_len, st, "rechart: chart %zu could not be laid out", c->out->chart_count);
    }
    free(g.region_of);
    free(g.point_uses);
    free(order);
    return st;
}

texopt_status texopt_rechart_create(texopt_rechart **out, const texopt_mesh *mesh,
                                    const texopt_rechart_options *options, char *err, size_t err_len)
{
    if (!out || !mesh || !options)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rechart: NULL argument");
    *out = NULL;
    context c = {.mesh = mesh, .opt = *options};
    texopt_status st = check_options(&c.opt, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_rechart *r = calloc(1, sizeof *r);
    size_t nt = mesh->triangle_count;
    if (r) {
        r->triangle_count = nt;
        r->chart_of = calloc(nt ? nt : 1, sizeof *r->chart_of);
        r->corner_uv = calloc(6 * (nt ? nt : 1), sizeof *r->corner_uv);
    }
    c.out = r;
    if (!r || !r->chart_of || !r->corner_uv || (nt > 0 && context_alloc(&c) != 0))
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rechart: out of memory");
    if (st == TEXOPT_OK && nt > 0)
        st = make_charts(&c, err, err_len);
    context_free(&c);
    if (st != TEXOPT_OK) {
        texopt_rechart_destroy(r);
        return st;
    }
    *out = r;
    return TEXOPT_OK;
}
