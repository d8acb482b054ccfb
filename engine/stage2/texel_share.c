/* texel_share.c - sharing groups of charts from their texel footprints, the ties of the
 * secondaries' vertices to their primaries, and the grouped view of the mesh (see
 * texel_share.h). Does not solve or pack. */
#include "texel_share.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sort_keys.h"
#include "tri_bins.h"

#define NONE UINT32_MAX

/* The unwrapped texel grid over every usable triangle: cell (i, j) has its centre at
 * (x0 + i + 0.5, y0 + j + 0.5). */
typedef struct texel_grid {
    double x0, y0;
    size_t nx, ny;
} texel_grid;

typedef struct work {
    const texopt_mesh *m;
    texel_grid g;
    uint32_t *tri_start, *tri_of_chart; /* usable triangles of each chart (CSR) */
    uint32_t *stamp;                    /* per cell: the last visit that counted it */
    uint32_t *owner;                    /* per cell: the primary that claimed it, or NONE */
    uint32_t *texels;                   /* per chart: its covered texels, each counted once */
    uint32_t *hits;                     /* per chart: texels of the chart being placed that it owns */
    uint32_t *touched;                  /* charts with hits, to reset them */
    size_t touched_count;
} work;

static void work_free(work *w)
{
    free(w->tri_start);
    free(w->tri_of_chart);
    free(w->stamp);
    free(w->owner);
    free(w->texels);
    free(w->hits);
    free(w->touched);
}

static const double *corner(const texopt_mesh *m, uint32_t t, int j)
{
    return m->texel + 2 * (size_t)m->triangle[3 * (size_t)t + j];
}

/* A triangle with an input texel area and finite corners: the ones that read texels. */
static int usable(const texopt_mesh *m, size_t t)
{
    if ((m->flags[t] & TEXOPT_TRI_DEGENERATE_UV) || !(m->area_texel[t] != 0.0))
        return 0;
    for (int j = 0; j < 3; j++)
        if (!isfinite(corner(m, (uint32_t)t, j)[0]) || !isfinite(corner(m, (uint32_t)t, j)[1]))
            return 0;
    return 1;
}

/* The grid over the usable triangles; 0 when it would exceed TEXOPT_TEXEL_SHARE_MAX_CELLS
 * (or there is nothing to cover). */
static int grid_over(const texopt_mesh *m, texel_grid *g)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t t = 0; t < m->triangle_count; t++)
        if (usable(m, t))
            for (int j = 0; j < 3; j++)
                for (int a = 0; a < 2; a++) {
                    lo[a] = fmin(lo[a], corner(m, (uint32_t)t, j)[a]);
                    hi[a] = fmax(hi[a], corner(m, (uint32_t)t, j)[a]);
                }
    if (!(lo[0] <= hi[0]))
        return 0;
    double nx = ceil(hi[0]) - floor(lo[0]) + 1.0, ny = ceil(hi[1]) - floor(lo[1]) + 1.0;
    if (nx * ny > (double)TEXOPT_TEXEL_SHARE_MAX_CELLS)
        return 0;
    g->x0 = floor(lo[0]);
    g->y0 = floor(lo[1]);
    g->nx = (size_t)nx;
    g->ny = (size_t)ny;
    return 1;
}

/* Columns [*first, *last] of the cell centres of row j inside triangle t (convex: one
 * span). Returns 0 when the row has none. */
static int row_span(const texopt_mesh *m, const texel_grid *g, uint32_t t, size_t j, size_t *first, size_t *last)
{
    double y = g->y0 + (double)j + 0.5, lo = INFINITY, hi = -INFINITY;
    for (int e = 0; e < 3; e++) {
        const double *a = corner(m, t, e), *b = corner(m, t, (e + 1) % 3);
        if (a[1] == b[1] || (y < a[1] && y < b[1]) || (y > a[1] && y > b[1]))
            continue;
        double x = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
        lo = fmin(lo, x);
        hi = fmax(hi, x);
    }
    double f = fmax(ceil(lo - g->x0 - 0.5), 0.0), l = fmin(floor(hi - g->x0 - 0.5), (double)g->nx - 1.0);
    if (!(f <= l))
        return 0;
    *first = (size_t)f;
    *last = (size_t)l;
    return 1;
}

/* Rows [*first, *last] whose centres triangle t may hold. Returns 0 when none. */
static int row_range(const texopt_mesh *m, const texel_grid *g, uint32_t t, size_t *first, size_t *last)
{
    double lo = fmin(fmin(corner(m, t, 0)[1], corner(m, t, 1)[1]), corner(m, t, 2)[1]);
    double hi = fmax(fmax(corner(m, t, 0)[1], corner(m, t, 1)[1]), corner(m, t, 2)[1]);
    double f = fmax(ceil(lo - g->y0 - 0.5), 0.0), l = fmin(floor(hi - g->y0 - 0.5), (double)g->ny - 1.0);
    if (!(f <= l))
        return 0;
    *first = (size_t)f;
    *last = (size_t)l;
    return 1;
}

typedef void (*cell_visit)(work *w, uint32_t chart, size_t cell);

/* Calls visit once for every cell whose centre a usable triangle of `chart` holds;
 * `visit_id` (unique per chart and pass) marks the cells already visited. */
static void visit_chart(work *w, uint32_t chart, uint32_t visit_id, cell_visit visit)
{
    for (uint32_t k = w->tri_start[chart]; k < w->tri_start[chart + 1]; k++) {
        uint32_t t = w->tri_of_chart[k];
        size_t j0, j1, i0, i1;
        if (!row_range(w->m, &w->g, t, &j0, &j1))
            continue;
        for (size_t j = j0; j <= j1; j++) {
            if (!row_span(w->m, &w->g, t, j, &i0, &i1))
                continue;
            for (size_t i = i0; i <= i1; i++) {
                size_t cell = j * w->g.nx + i;
                if (w->stamp[cell] == visit_id)
                    continue;
                w->stamp[cell] = visit_id;
                visit(w, chart, cell);
            }
        }
    }
}

static void count_texel(work *w, uint32_t chart, size_t cell)
{
    (void)cell;
    w->texels[chart]++;
}

static void count_owner(work *w, uint32_t chart, size_t cell)
{
    (void)chart;
    uint32_t o = w->owner[cell];
    if (o != NONE && w->hits[o]++ == 0)
        w->touched[w->touched_count++] = o;
}

static void claim(work *w, uint32_t chart, size_t cell)
{
    if (w->owner[cell] == NONE)
        w->owner[cell] = chart;
}

static texopt_status index_charts(work *w, char *err, size_t err_len)
{
    const texopt_mesh *m = w->m;
    size_t nc = m->chart_count;
    w->tri_start = calloc(nc + 1, sizeof *w->tri_start);
    w->tri_of_chart = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *w->tri_of_chart);
    uint32_t *fill = calloc(nc + 1, sizeof *fill);
    if (!w->tri_start || !w->tri_of_chart || !fill) {
        free(fill);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory for %zu charts", nc);
    }
    for (size_t t = 0; t < m->triangle_count; t++)
        if (usable(m, t))
            w->tri_start[m->chart_of[t] + 1]++;
    for (size_t c = 0; c < nc; c++)
        fill[c + 1] = w->tri_start[c + 1] += w->tri_start[c];
    for (size_t t = 0; t < m->triangle_count; t++)
        if (usable(m, t))
            w->tri_of_chart[fill[m->chart_of[t]]++] = (uint32_t)t;
    free(fill);
    return TEXOPT_OK;
}

/* Charts from the most covered texels down (ties by index). */
static uint32_t *charts_by_texels(const work *w)
{
    size_t nc = w->m->chart_count;
    uint64_t *key = malloc((nc ? nc : 1) * sizeof *key);
    uint32_t *order = malloc((nc ? nc : 1) * sizeof *order);
    if (!key || !order) {
        free(key);
        free(order);
        return NULL;
    }
    for (size_t c = 0; c < nc; c++)
        key[c] = (uint64_t)(UINT32_MAX - w->texels[c]) << 32 | c;
    qsort(key, nc, sizeof *key, texopt_compare_u64);
    for (size_t c = 0; c < nc; c++)
        order[c] = (uint32_t)key[c];
    free(key);
    return order;
}

/* primary_of for every chart (see texel_share.h). */
static texopt_status find_groups(work *w, texopt_texel_share *s, char *err, size_t err_len)
{
    size_t nc = w->m->chart_count, cells = w->g.nx * w->g.ny;
    w->stamp = calloc(cells, sizeof *w->stamp);
    w->owner = malloc(cells * sizeof *w->owner);
    w->texels = calloc(nc, sizeof *w->texels);
    w->hits = calloc(nc, sizeof *w->hits);
    w->touched = malloc(nc * sizeof *w->touched);
    if (!w->stamp || !w->owner || !w->texels || !w->hits || !w->touched)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory for %zu texels", cells);
    for (size_t i = 0; i < cells; i++)
        w->owner[i] = NONE;
    for (uint32_t c = 0; c < nc; c++)
        visit_chart(w, c, c + 1, count_texel);
    uint32_t *order = charts_by_texels(w);
    if (!order)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory for %zu charts", nc);
    for (size_t k = 0; k < nc; k++) {
        uint32_t c = order[k], best = NONE;
        w->touched_count = 0;
        visit_chart(w, c, (uint32_t)(nc + c + 1), count_owner);
        for (size_t i = 0; i < w->touched_count; i++) {
            uint32_t o = w->touched[i];
            if (best == NONE || w->hits[o] > w->hits[best])
                best = o;
        }
        if (best != NONE && w->texels[c] > 0 &&
            (double)w->hits[best] >= TEXOPT_TEXEL_SHARE_FRACTION * (double)w->texels[c]) {
            s->primary_of[c] = best;
            s->secondary_count++;
        } else {
            visit_chart(w, c, (uint32_t)(2 * nc + c + 1), claim);
        }
        for (size_t i = 0; i < w->touched_count; i++)
            w->hits[w->touched[i]] = 0;
    }
    free(order);
    return TEXOPT_OK;
}

/* ---- ties ----------------------------------------------------------------------------- */

static double cross(const double o[2], const double a[2], const double b[2])
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Distance from p to triangle t (0 inside) and the barycentric weights of its closest
 * point. */
static double closest_point(const texopt_mesh *m, uint32_t t, const double p[2], double w[3])
{
    const double *c[3] = {corner(m, t, 0), corner(m, t, 1), corner(m, t, 2)};
    double area = cross(c[0], c[1], c[2]);
    w[1] = cross(c[0], p, c[2]) / area;
    w[2] = cross(c[0], c[1], p) / area;
    w[0] = 1.0 - w[1] - w[2];
    if (w[0] >= 0.0 && w[1] >= 0.0 && w[2] >= 0.0)
        return 0.0;
    double best = INFINITY;
    for (int e = 0; e < 3; e++) {
        const double *a = c[e], *b = c[(e + 1) % 3];
        double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
        double s = len2 > 0.0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0.0;
        s = fmin(fmax(s, 0.0), 1.0);
        double d = hypot(a[0] + s * dx - p[0], a[1] + s * dy - p[1]);
        if (d < best) {
            best = d;
            w[e] = 1.0 - s;
            w[(e + 1) % 3] = s;
            w[(e + 2) % 3] = 0.0;
        }
    }
    return best;
}

/* Whether p is a corner of triangle t, with w its weights then. */
static int on_corner(const texopt_mesh *m, uint32_t t, const double p[2], double w[3])
{
    for (int j = 0; j < 3; j++)
        if (corner(m, t, j)[0] == p[0] && corner(m, t, j)[1] == p[1]) {
            w[0] = w[1] = w[2] = 0.0;
            w[j] = 1.0;
            return 1;
        }
    return 0;
}

/* The tie of vertex v to the nearest triangle of chart `primary` within the tolerance;
 * 0 when there is none. A vertex on a corner of the primary is tied to that corner before
 * any triangle it lies in: where the primary overlaps itself, a mirrored or repeated twin's
 * vertex lies in triangles of both layers, and its twin corner is the one that follows it
 * when the primary is laid out anew (chart_unfold.h texopt_unfold_groups). */
static int locate(const texopt_mesh *m, const texopt_tri_bins *b, uint32_t primary, uint32_t v, texopt_texel_tie *tie)
{
    const double *p = m->texel + 2 * (size_t)v;
    const double tol = TEXOPT_TEXEL_SHARE_TOLERANCE;
    double best = INFINITY;
    if (!b->start)
        return 0;
    for (size_t j = texopt_tri_bins_index(b, p[1] - tol, 1); j <= texopt_tri_bins_index(b, p[1] + tol, 1); j++)
        for (size_t i = texopt_tri_bins_index(b, p[0] - tol, 0); i <= texopt_tri_bins_index(b, p[0] + tol, 0); i++)
            for (uint32_t k = b->start[j * b->nx + i]; k < b->start[j * b->nx + i + 1]; k++) {
                uint32_t t = b->tri[k];
                double w[3], d;
                if (m->chart_of[t] != primary)
                    continue;
                d = on_corner(m, t, p, w) ? -1.0 : closest_point(m, t, p, w);
                if (!(d < best))
                    continue;
                best = d;
                for (int c = 0; c < 3; c++) {
                    tie->corner[c] = m->triangle[3 * (size_t)t + c];
                    tie->weight[c] = w[c];
                }
            }
    tie->vertex = v;
    return best <= tol;
}

static texopt_status find_ties(const work *w, texopt_texel_share *s, char *err, size_t err_len)
{
    const texopt_mesh *m = w->m;
    size_t nc = m->chart_count, nv = m->vertex_count ? m->vertex_count : 1;
    uint8_t *has_secondary = calloc(nc ? nc : 1, 1), *seen = calloc(nv, 1);
    unsigned char *primary_tri = calloc(m->triangle_count ? m->triangle_count : 1, 1);
    texopt_tri_bins b = {0};
    texopt_status st = TEXOPT_OK;
    size_t cap = 0;
    if (!has_secondary || !seen || !primary_tri)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory for %zu vertices", nv);
    for (size_t c = 0; c < nc && st == TEXOPT_OK; c++)
        if (s->primary_of[c] != c)
            has_secondary[s->primary_of[c]] = 1;
    for (size_t t = 0; t < m->triangle_count && st == TEXOPT_OK; t++)
        primary_tri[t] = has_secondary[m->chart_of[t]] && usable(m, t);
    if (st == TEXOPT_OK)
        st = texopt_tri_bins_build(&b, m, primary_tri, err, err_len);
    for (uint32_t c = 0; c < nc && st == TEXOPT_OK; c++) {
        if (s->primary_of[c] == c)
            continue;
        for (uint32_t k = w->tri_start[c]; k < w->tri_start[c + 1] && st == TEXOPT_OK; k++)
            for (int j = 0; j < 3; j++) {
                uint32_t v = m->triangle[3 * (size_t)w->tri_of_chart[k] + j];
                texopt_texel_tie tie;
                if (seen[v])
                    continue;
                seen[v] = 1;
                if (!locate(m, &b, s->primary_of[c], v, &tie))
                    continue;
                if (s->tie_count == cap) {
                    cap = cap ? 2 * cap : 64;
                    texopt_texel_tie *grown = realloc(s->ties, cap * sizeof *grown);
                    if (!grown) {
                        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory for the ties");
                        break;
                    }
                    s->ties = grown;
                }
                s->ties[s->tie_count++] = tie;
            }
    }
    free(has_secondary);
    free(seen);
    free(primary_tri);
    texopt_tri_bins_free(&b);
    return st;
}

/* ---- the grouped view ----------------------------------------------------------------- */

/* Groups numbered in the order of their primaries' chart indices (with no secondary the
 * view's charts are the mesh's). */
static texopt_status build_view(const texopt_mesh *m, texopt_texel_share *s, char *err, size_t err_len)
{
    size_t nc = m->chart_count;
    uint32_t *label = malloc((nc ? nc : 1) * sizeof *label);
    s->view = *m;
    s->view.chart_of = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *s->view.chart_of);
    s->view.chart_sign = malloc(nc ? nc : 1);
    s->grouped = calloc(nc ? nc : 1, 1);
    if (!label || !s->view.chart_of || !s->view.chart_sign || !s->grouped) {
        free(label);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory for the grouped view");
    }
    size_t groups = 0;
    for (size_t c = 0; c < nc; c++)
        if (s->primary_of[c] == c) {
            s->view.chart_sign[groups] = m->chart_sign ? m->chart_sign[c] : 1;
            label[c] = (uint32_t)groups++;
        }
    for (size_t t = 0; t < m->triangle_count; t++)
        s->view.chart_of[t] = label[s->primary_of[m->chart_of[t]]];
    for (size_t c = 0; c < nc; c++)
        if (s->primary_of[c] != c)
            s->grouped[label[s->primary_of[c]]] = 1;
    s->view.chart_count = groups;
    free(label);
    return TEXOPT_OK;
}

texopt_status texopt_texel_share_create(texopt_texel_share **out, const texopt_mesh *mesh, char *err, size_t err_len)
{
    if (!out || !mesh)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "texel share: NULL output or mesh");
    *out = NULL;
    if (mesh->triangle_count &&
        (!mesh->texel || !mesh->triangle || !mesh->flags || !mesh->area_texel || !mesh->chart_of))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "texel share: the mesh lacks texels, triangles, flags, areas or charts");
    if (mesh->chart_count >= NONE / 4)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "texel share: %zu charts", mesh->chart_count);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (mesh->chart_of[t] >= mesh->chart_count)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "texel share: triangle %zu in chart %u past chart count %zu", t, mesh->chart_of[t],
                               mesh->chart_count);
        for (int j = 0; j < 3; j++)
            if (mesh->triangle[3 * t + j] >= mesh->vertex_count)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                   "texel share: triangle %zu uses vertex %u past vertex count %zu", t,
                                   mesh->triangle[3 * t + j], mesh->vertex_count);
    }
    texopt_texel_share *s = calloc(1, sizeof *s);
    work w = {.m = mesh};
    if (!s || !(s->primary_of = malloc((mesh->chart_count ? mesh->chart_count : 1) * sizeof *s->primary_of))) {
        free(s);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory");
    }
    s->chart_count = mesh->chart_count;
    for (size_t c = 0; c < mesh->chart_count; c++)
        s->primary_of[c] = (uint32_t)c;
    texopt_status st = TEXOPT_OK;
    if (grid_over(mesh, &w.g)) {
        st = index_charts(&w, err, err_len);
        if (st == TEXOPT_OK)
            st = find_groups(&w, s, err, err_len);
        if (st == TEXOPT_OK && s->secondary_count > 0)
            st = find_ties(&w, s, err, err_len);
    }
    if (st == TEXOPT_OK)
        st = build_view(mesh, s, err, err_len);
    work_free(&w);
    if (st != TEXOPT_OK) {
        texopt_texel_share_destroy(s);
        return st;
    }
    *out = s;
    return TEXOPT_OK;
}

void texopt_texel_share_destroy(texopt_texel_share *share)
{
    if (!share)
        return;
    free(share->primary_of);
    free(share->ties);
    free(share->view.chart_of);
    free(share->view.chart_sign);
    free(share->grouped);
    free(share);
}

texopt_status texopt_texel_share_release(texopt_texel_share *share, const texopt_mesh *mesh, uint32_t chart, char *err,
                                         size_t err_len)
{
    if (!share || !mesh || share->chart_count != mesh->chart_count || chart >= mesh->chart_count ||
        share->primary_of[chart] == chart)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "texel share: chart %u is no secondary", chart);
    uint8_t *in_chart = calloc(mesh->vertex_count ? mesh->vertex_count : 1, 1);
    if (!in_chart)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "texel share: no memory to release chart %u", chart);
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (mesh->chart_of[t] == chart)
            for (int j = 0; j < 3; j++)
                in_chart[mesh->triangle[3 * t + j]] = 1;
    size_t kept = 0;
    for (size_t k = 0; k < share->tie_count; k++)
        if (!in_chart[share->ties[k].vertex])
            share->ties[kept++] = share->ties[k];
    share->tie_count = kept;
    free(in_chart);
    share->primary_of[chart] = chart;
    share->secondary_count--;
    free(share->view.chart_of);
    free(share->view.chart_sign);
    free(share->grouped);
    return build_view(mesh, share, err, err_len);
}

void texopt_texel_share_rebase(texopt_texel_share *share, const texopt_mesh *layout)
{
    texopt_mesh view = *layout;
    view.chart_count = share->view.chart_count;
    view.chart_of = share->view.chart_of;
    view.chart_sign = share->view.chart_sign;
    share->view = view;
}

size_t texopt_texel_share_paid(const texopt_texel_share *share, const texopt_mesh *mesh, double *paid)
{
    size_t free_riders = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint32_t c = mesh->chart_of[t];
        int secondary = share->primary_of[c] != c;
        int minority = mesh->chart_sign && mesh->area_texel[t] != 0.0 &&
                       (mesh->area_texel[t] > 0.0 ? 1 : -1) != mesh->chart_sign[c];
        paid[t] = secondary || minority ? 0.0 : 1.0;
        free_riders += secondary || minority;
    }
    return free_riders;
}
