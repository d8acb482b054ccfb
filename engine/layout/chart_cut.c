/* chart_cut.c - an axis-aligned chart cut into pieces along mesh edges; see chart_cut.h. */
#include "chart_cut.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rect_decompose.h"
#include "vec2.h"

#define PATH_OFF_TRAIL 4.0 /* per mean edge length of distance from the trail */
#define PATH_END_MISS 4.0  /* per unit of distance from the trail's stop point */
#define NO_TRIANGLE UINT32_MAX

/* The chart's edges: each once (a < b), with the one or two triangles using it, and per
 * vertex its edges (CSR). */
typedef struct edges {
    size_t count;
    uint32_t *a, *b, *t0, *t1;
    uint32_t *of_corner; /* 3 per triangle: the edge from corner k to corner k + 1 */
    uint32_t *start, *adjacent;
} edges;

typedef struct edge_key {
    uint32_t a, b, corner;
} edge_key;

static int by_vertices(const void *pa, const void *pb)
{
    const edge_key *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->corner > y->corner) - (x->corner < y->corner);
}

static void edges_free(edges *e)
{
    free(e->a);
    free(e->b);
    free(e->t0);
    free(e->t1);
    free(e->of_corner);
    free(e->start);
    free(e->adjacent);
    memset(e, 0, sizeof *e);
}

static int edges_build(edges *e, size_t nv, size_t nt, const uint32_t *tri)
{
    memset(e, 0, sizeof *e);
    size_t nc = nt ? 3 * nt : 1;
    edge_key *key = malloc(nc * sizeof *key);
    e->a = malloc(nc * sizeof *e->a);
    e->b = malloc(nc * sizeof *e->b);
    e->t0 = malloc(nc * sizeof *e->t0);
    e->t1 = malloc(nc * sizeof *e->t1);
    e->of_corner = malloc(nc * sizeof *e->of_corner);
    e->start = calloc(nv + 1, sizeof *e->start);
    e->adjacent = malloc(2 * nc * sizeof *e->adjacent);
    if (!key || !e->a || !e->b || !e->t0 || !e->t1 || !e->of_corner || !e->start || !e->adjacent) {
        free(key);
        edges_free(e);
        return 0;
    }
    for (size_t c = 0; c < 3 * nt; c++) {
        uint32_t u = tri[c], v = tri[c - c % 3 + (c + 1) % 3];
        key[c] = (edge_key){u < v ? u : v, u < v ? v : u, (uint32_t)c};
    }
    qsort(key, 3 * nt, sizeof *key, by_vertices);
    for (size_t i = 0; i < 3 * nt; i++) {
        if (i == 0 || key[i].a != key[i - 1].a || key[i].b != key[i - 1].b) {
            e->a[e->count] = key[i].a;
            e->b[e->count] = key[i].b;
            e->t0[e->count] = key[i].corner / 3;
            e->t1[e->count] = NO_TRIANGLE;
            e->count++;
        } else {
            e->t1[e->count - 1] = key[i].corner / 3;
        }
        e->of_corner[key[i].corner] = (uint32_t)(e->count - 1);
    }
    free(key);
    for (size_t i = 0; i < e->count; i++) {
        e->start[e->a[i] + 1]++;
        e->start[e->b[i] + 1]++;
    }
    for (size_t v = 0; v < nv; v++)
        e->start[v + 1] += e->start[v];
    uint32_t *fill = malloc((nv ? nv : 1) * sizeof *fill);
    if (!fill) {
        edges_free(e);
        return 0;
    }
    memcpy(fill, e->start, nv * sizeof *fill);
    for (size_t i = 0; i < e->count; i++) {
        e->adjacent[fill[e->a[i]]++] = (uint32_t)i;
        e->adjacent[fill[e->b[i]]++] = (uint32_t)i;
    }
    free(fill);
    return 1;
}

static int direction_of(int theta)
{
    return ((theta % 4) + 4) % 4;
}

/* Step 1: the polygon (2 per corner, *m corners) and each corner's loop vertex. Returns 0
 * when the runs do not alternate between the axes. */
static int axis_polygon(const double *xy, const uint32_t *loop, const int *theta, size_t n, double *poly,
                        uint32_t *corner_vertex, size_t *m)
{
    size_t s = 0;
    while (s < n && direction_of(theta[s]) == direction_of(theta[(s + n - 1) % n]))
        s++;
    if (s == n)
        return 0;
    double *coord = malloc(n * sizeof *coord);
    int *dir = malloc(n * sizeof *dir);
    if (!coord || !dir) {
        free(coord);
        free(dir);
        return 0;
    }
    size_t runs = 0;
    double weight = 0;
    for (size_t k = 0; k < n; k++) {
        size_t i = (s + k) % n;
        int d = direction_of(theta[i]);
        if (k == 0 || d != dir[runs - 1]) {
            if (runs > 0)
                coord[runs - 1] /= weight;
            dir[runs] = d;
            coord[runs] = 0;
            corner_vertex[runs] = loop[i];
            weight = 0;
            runs++;
        }
        const double *p = xy + 2 * (size_t)loop[i], *q = xy + 2 * (size_t)loop[(i + 1) % n];
        double len = hypot(q[0] - p[0], q[1] - p[1]) + 1e-12;
        size_t axis = d % 2 == 0 ? 1 : 0; /* a horizontal side's coordinate is its y */
        coord[runs - 1] += len * 0.5 * (p[axis] + q[axis]);
        weight += len;
    }
    coord[runs - 1] /= weight;
    int ok = runs >= 4;
    for (size_t k = 0; ok && k < runs; k++) {
        size_t before = (k + runs - 1) % runs;
        ok = (dir[k] - dir[before]) % 2 != 0;
        int horizontal = dir[k] % 2 == 0;
        poly[2 * k] = horizontal ? coord[before] : coord[k];
        poly[2 * k + 1] = horizontal ? coord[k] : coord[before];
    }
    *m = runs;
    free(coord);
    free(dir);
    return ok;
}

static double polygon_area(const double *p, size_t n)
{
    double a = 0;
    for (size_t i = 0; i < n; i++)
        a += p[2 * i] * p[2 * ((i + 1) % n) + 1] - p[2 * ((i + 1) % n)] * p[2 * i + 1];
    return 0.5 * a;
}

static double segment_distance(const double *p, const texopt_rect_trail *t)
{
    double dx = t->x1 - t->x0, dy = t->y1 - t->y0, l2 = dx * dx + dy * dy;
    double s = l2 > 0 ? ((p[0] - t->x0) * dx + (p[1] - t->y0) * dy) / l2 : 0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    return hypot(p[0] - (t->x0 + s * dx), p[1] - (t->y0 + s * dy));
}

/* Whether trail a stops on trail b (b's segment, not at b's corner). */
static int stops_on(const texopt_rect_trail *a, const texopt_rect_trail *b)
{
    if (a == b || (a->x1 == b->x0 && a->y1 == b->y0))
        return 0;
    if (b->x0 == b->x1)
        return a->x1 == b->x0 && a->y1 >= fmin(b->y0, b->y1) && a->y1 <= fmax(b->y0, b->y1);
    return a->y1 == b->y0 && a->x1 >= fmin(b->x0, b->x1) && a->x1 <= fmax(b->x0, b->x1);
}

/* The order trails are cut in: a trail after those it stops on (a cycle, two head-on
 * motorcycles, broken in index order). */
static void trail_order(const texopt_rect_trail *t, size_t count, size_t *order, uint8_t *done)
{
    memset(done, 0, count);
    for (size_t placed = 0; placed < count; placed++) {
        size_t pick = count;
        for (size_t i = 0; i < count && pick == count; i++) {
            int ready = !done[i];
            for (size_t j = 0; ready && j < count; j++)
                ready = done[j] || !stops_on(&t[i], &t[j]);
            if (ready)
                pick = i;
        }
        for (size_t i = 0; i < count && pick == count; i++)
            if (!done[i])
                pick = i;
        done[pick] = 1;
        order[placed] = pick;
    }
}

typedef struct heap_item {
    double cost;
    uint32_t state;
} heap_item;

static void heap_push(heap_item *h, size_t *n, heap_item x)
{
    size_t i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].cost > x.cost) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = x;
}

static heap_item heap_pop(heap_item *h, size_t *n)
{
    heap_item top = h[0], last = h[--(*n)];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= *n)
            break;
        if (c + 1 < *n && h[c + 1].cost < h[c].cost)
            c++;
        if (!(h[c].cost < last.cost))
            break;
        h[i] = h[c];
        i = c;
    }
    h[i] = last;
    return top;
}

typedef struct path_search {
    const double *xy;
    size_t nv;
    const edges *e;
    double mean_edge;
    uint8_t *terminal, *cut; /* per vertex, per edge */
    double *dist;            /* 2 nv states: vertex v, or "ended at v" (nv + v) */
    uint32_t *prev;
    heap_item *heap;
} path_search;

static double edge_cost(const path_search *ps, uint32_t u, uint32_t w, const texopt_rect_trail *t)
{
    const double *p = ps->xy + 2 * (size_t)u, *q = ps->xy + 2 * (size_t)w;
    double mid[2] = {0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])};
    return hypot(q[0] - p[0], q[1] - p[1]) * (1.0 + PATH_OFF_TRAIL * segment_distance(mid, t) / ps->mean_edge);
}

/* Step 3 for one trail: the cheapest path from vertex s over uncut interior edges to a
 * terminal vertex; marks its edges cut and its vertices terminal. Returns its edge count
 * (0: none found). */
static size_t cut_trail(path_search *ps, uint32_t s, const texopt_rect_trail *t)
{
    size_t nv = ps->nv, nh = 0, cap = 2 * (ps->e->count + nv) + 1;
    for (size_t i = 0; i < 2 * nv; i++)
        ps->dist[i] = INFINITY;
    ps->dist[s] = 0;
    heap_push(ps->heap, &nh, (heap_item){0, s});
    uint32_t end = UINT32_MAX;
    while (nh > 0) {
        heap_item it = heap_pop(ps->heap, &nh);
        if (it.cost > ps->dist[it.state])
            continue;
        if (it.state >= nv) {
            end = it.state;
            break;
        }
        uint32_t u = it.state;
        for (uint32_t k = ps->e->start[u]; k < ps->e->start[u + 1]; k++) {
            uint32_t e = ps->e->adjacent[k], w = ps->e->a[e] == u ? ps->e->b[e] : ps->e->a[e];
            if (ps->e->t1[e] == NO_TRIANGLE || ps->cut[e] || w == s)
                continue;
            double c = it.cost + edge_cost(ps, u, w, t);
            uint32_t state = w;
            if (ps->terminal[w]) {
                const double *q = ps->xy + 2 * (size_t)w;
                c += PATH_END_MISS * hypot(q[0] - t->x1, q[1] - t->y1);
                state = (uint32_t)(nv + w);
            }
            if (c < ps->dist[state] && nh < cap) {
                ps->dist[state] = c;
                ps->prev[state] = u;
                heap_push(ps->heap, &nh, (heap_item){c, state});
            }
        }
    }
    if (end == UINT32_MAX)
        return 0;
    size_t count = 0;
    uint32_t w = (uint32_t)(end - nv), u = ps->prev[end];
    for (;;) {
        for (uint32_t k = ps->e->start[u]; k < ps->e->start[u + 1]; k++) {
            uint32_t e = ps->e->adjacent[k];
            if (ps->e->a[e] == (u < w ? u : w) && ps->e->b[e] == (u < w ? w : u))
                ps->cut[e] = 1;
        }
        ps->terminal[w] = 1;
        count++;
        if (u == s)
            break;
        w = u;
        u = ps->prev[u];
    }
    return count;
}

/* Pieces: triangles joined across uncut edges. */
static size_t flood_pieces(const edges *e, const uint8_t *cut, size_t nt, uint32_t *piece, uint32_t *stack)
{
    for (size_t t = 0; t < nt; t++)
        piece[t] = UINT32_MAX;
    size_t pieces = 0;
    for (size_t seed = 0; seed < nt; seed++) {
        if (piece[seed] != UINT32_MAX)
            continue;
        size_t top = 0;
        piece[seed] = (uint32_t)pieces;
        stack[top++] = (uint32_t)seed;
        while (top > 0) {
            uint32_t t = stack[--top];
            for (int k = 0; k < 3; k++) {
                uint32_t ed = e->of_corner[3 * (size_t)t + (size_t)k];
                uint32_t other = e->t0[ed] == t ? e->t1[ed] : e->t0[ed];
                if (!cut[ed] && other != NO_TRIANGLE && piece[other] == UINT32_MAX) {
                    piece[other] = (uint32_t)pieces;
                    stack[top++] = other;
                }
            }
        }
        pieces++;
    }
    return pieces;
}

/* Step 2: the chosen decomposition's trails, *count 0 for a rectangle. */
static texopt_status choose_trails(const double *poly, size_t m, const texopt_chart_cut_options *o,
                                   texopt_chart_cut *out, texopt_rect_trail **trails, size_t *count, char *err,
                                   size_t err_len)
{
    size_t reflex = texopt_rect_reflex_corners(poly, m);
    *trails = NULL;
    *count = 0;
    out->rect_count = 1;
    out->rect_efficiency = 1;
    if (reflex == 0)
        return TEXOPT_OK;
    uint8_t *choice = malloc(reflex);
    if (!choice)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart cut: no memory");
    texopt_rect_choice rc;
    texopt_status st =
        texopt_rect_choose(poly, m, o->candidates, o->seed, o->padding, o->efficiency_bound, choice, &rc, err, err_len);
    if (st == TEXOPT_E_INVALID_ARGUMENT)
        st = texopt_rect_choose(poly, m, o->candidates, o->seed, o->padding, 0, choice, &rc, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_rect_trails(poly, m, choice, trails, count, err, err_len);
    if (st == TEXOPT_OK) {
        out->rect_count = rc.rect_count;
        out->rect_efficiency = rc.efficiency;
    }
    free(choice);
    return st;
}

static double mean_edge_length(const edges *e, const double *xy)
{
    double sum = 0;
    for (size_t i = 0; i < e->count; i++)
        sum += hypot(xy[2 * (size_t)e->b[i]] - xy[2 * (size_t)e->a[i]],
                     xy[2 * (size_t)e->b[i] + 1] - xy[2 * (size_t)e->a[i] + 1]);
    return e->count && sum > 0 ? sum / (double)e->count : 1;
}

/* Step 3: every trail cut, the pieces found. */
static texopt_status cut_along_trails(size_t nv, const double *xy, size_t nt, const edges *e, const uint32_t *loop,
                                      size_t n, const uint32_t *corner_vertex, const texopt_rect_trail *trails,
                                      size_t count, texopt_chart_cut *out, char *err, size_t err_len)
{
    path_search ps = {xy, nv, e, mean_edge_length(e, xy), NULL, NULL, NULL, NULL, NULL};
    ps.terminal = calloc(nv ? nv : 1, 1);
    ps.cut = calloc(e->count ? e->count : 1, 1);
    ps.dist = malloc(2 * (nv ? nv : 1) * sizeof *ps.dist);
    ps.prev = malloc(2 * (nv ? nv : 1) * sizeof *ps.prev);
    ps.heap = malloc((2 * (e->count + nv) + 1) * sizeof *ps.heap);
    size_t *order = malloc((count ? count : 1) * sizeof *order);
    uint8_t *done = malloc(count ? count : 1);
    uint32_t *stack = malloc((nt ? nt : 1) * sizeof *stack);
    out->piece_of = malloc((nt ? nt : 1) * sizeof *out->piece_of);
    texopt_status st = TEXOPT_OK;
    if (!ps.terminal || !ps.cut || !ps.dist || !ps.prev || !ps.heap || !order || !done || !stack || !out->piece_of)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart cut: no memory");
    if (st == TEXOPT_OK) {
        for (size_t i = 0; i < n; i++)
            ps.terminal[loop[i]] = 1;
        trail_order(trails, count, order, done);
        for (size_t k = 0; k < count; k++) {
            size_t edges_cut = cut_trail(&ps, corner_vertex[trails[order[k]].corner], &trails[order[k]]);
            out->path_edges += edges_cut;
            out->trail_count += edges_cut > 0;
        }
        out->piece_count = flood_pieces(e, ps.cut, nt, out->piece_of, stack);
    }
    free(ps.terminal);
    free(ps.cut);
    free(ps.dist);
    free(ps.prev);
    free(ps.heap);
    free(order);
    free(done);
    free(stack);
    return st;
}

texopt_status texopt_chart_cut_compute(size_t vertex_count, const double *xy, size_t triangle_count,
                                       const uint32_t *triangle, const uint32_t *loop, const int *theta, size_t n,
                                       const texopt_chart_cut_options *opt, texopt_chart_cut *out, char *err,
                                       size_t err_len)
{
    texopt_chart_cut_options o = opt ? *opt : (texopt_chart_cut_options){0};
    o.candidates = o.candidates > 0 ? o.candidates : TEXOPT_CHART_CUT_CANDIDATES;
    o.efficiency_bound = o.efficiency_bound > 0 ? o.efficiency_bound : TEXOPT_CHART_CUT_BOUND;
    memset(out, 0, sizeof *out);
    if (!xy || !triangle || !loop || !theta || n < 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "chart cut: need a chart with a boundary loop");
    double *poly = malloc(2 * n * sizeof *poly);
    uint32_t *corner_vertex = malloc(n * sizeof *corner_vertex);
    edges e = {0};
    texopt_status st = poly && corner_vertex && edges_build(&e, vertex_count, triangle_count, triangle)
                           ? TEXOPT_OK
                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart cut: no memory");
    size_t m = 0;
    if (st == TEXOPT_OK && !axis_polygon(xy, loop, theta, n, poly, corner_vertex, &m))
        st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "chart cut: boundary runs do not alternate axes");
    texopt_rect_trail *trails = NULL;
    size_t count = 0;
    if (st == TEXOPT_OK) {
        double area = 0;
        for (size_t t = 0; t < triangle_count; t++) {
            const double *a = xy + 2 * (size_t)triangle[3 * t], *b = xy + 2 * (size_t)triangle[3 * t + 1],
                         *c = xy + 2 * (size_t)triangle[3 * t + 2];
            area += texopt_signed_area(a, b, c);
        }
        out->corner_count = m;
        out->polygon_area_ratio = area > 0 ? polygon_area(poly, m) / area : 0;
        st = choose_trails(poly, m, &o, out, &trails, &count, err, err_len);
    }
    if (st == TEXOPT_OK)
        st = cut_along_trails(vertex_count, xy, triangle_count, &e, loop, n, corner_vertex, trails, count, out, err,
                              err_len);
    free(trails);
    free(poly);
    free(corner_vertex);
    edges_free(&e);
    if (st != TEXOPT_OK)
        texopt_chart_cut_destroy(out);
    return st;
}

void texopt_chart_cut_destroy(texopt_chart_cut *cut)
{
    if (!cut)
        return;
    free(cut->piece_of);
    memset(cut, 0, sizeof *cut);
}

/* Per corner, the vertex of the cut mesh: a vertex keeps its index in the piece of its
 * first triangle, each further piece gets the next index from nv on. Returns the vertex
 * count, 0 on no memory. */
static size_t split_corners(const texopt_mesh *mesh, const uint32_t *piece_of, uint32_t *corner, uint32_t *source)
{
    size_t nv = mesh->vertex_count, nc = 3 * mesh->triangle_count, added = 0;
    uint32_t *owner = malloc((nv ? nv : 1) * sizeof *owner);
    /* copies as linked lists per vertex: piece, index, next */
    uint32_t *head = malloc((nv ? nv : 1) * sizeof *head), *piece = malloc((nc ? nc : 1) * sizeof *piece);
    uint32_t *index = malloc((nc ? nc : 1) * sizeof *index), *next = malloc((nc ? nc : 1) * sizeof *next);
    if (!owner || !head || !piece || !index || !next)
        nv = 0;
    for (size_t v = 0; v < nv; v++) {
        owner[v] = UINT32_MAX;
        head[v] = UINT32_MAX;
        source[v] = (uint32_t)v;
    }
    for (size_t c = 0; nv && c < nc; c++) {
        uint32_t v = mesh->triangle[c], p = piece_of[c / 3];
        if (owner[v] == UINT32_MAX)
            owner[v] = p;
        if (owner[v] == p) {
            corner[c] = v;
            continue;
        }
        uint32_t k = head[v];
        while (k != UINT32_MAX && piece[k] != p)
            k = next[k];
        if (k == UINT32_MAX) {
            k = (uint32_t)added;
            piece[k] = p;
            index[k] = (uint32_t)(nv + added);
            next[k] = head[v];
            head[v] = k;
            source[nv + added] = v;
            added++;
        }
        corner[c] = index[k];
    }
    free(owner);
    free(head);
    free(piece);
    free(index);
    free(next);
    return nv ? nv + added : 0;
}

/* A copy of p (bytes), NULL when p is; *ok cleared on no memory. */
static void *copy_of(const void *p, size_t bytes, int *ok)
{
    if (!p)
        return NULL;
    void *q = malloc(bytes ? bytes : 1);
    if (q && bytes)
        memcpy(q, p, bytes);
    *ok &= q != NULL;
    return q;
}

/* vertex_on_boundary of the cut mesh: on an edge used by one triangle. */
static int mark_boundary(texopt_mesh *m)
{
    edges e;
    if (!edges_build(&e, m->vertex_count, m->triangle_count, m->triangle))
        return 0;
    memset(m->vertex_on_boundary, 0, m->vertex_count ? m->vertex_count : 1);
    for (size_t i = 0; i < e.count; i++)
        if (e.t1[i] == NO_TRIANGLE)
            m->vertex_on_boundary[e.a[i]] = m->vertex_on_boundary[e.b[i]] = 1;
    edges_free(&e);
    return 1;
}

/* The cut mesh's per-vertex arrays from its sources; mesh arrays absent stay absent. */
static int copy_vertices(const texopt_mesh *mesh, const uint32_t *src, texopt_mesh *m)
{
    size_t nv = m->vertex_count ? m->vertex_count : 1;
    m->texel = malloc(2 * nv * sizeof *m->texel);
    m->point_of = mesh->point_of ? malloc(nv * sizeof *m->point_of) : NULL;
    m->model_vertex = mesh->model_vertex ? malloc(nv * sizeof *m->model_vertex) : NULL;
    m->vertex_on_boundary = malloc(nv);
    if (!m->texel || (mesh->point_of && !m->point_of) || (mesh->model_vertex && !m->model_vertex) ||
        !m->vertex_on_boundary)
        return 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        m->texel[2 * v] = mesh->texel[2 * (size_t)src[v]];
        m->texel[2 * v + 1] = mesh->texel[2 * (size_t)src[v] + 1];
        if (m->point_of)
            m->point_of[v] = mesh->point_of[src[v]];
        if (m->model_vertex)
            m->model_vertex[v] = mesh->model_vertex[src[v]];
    }
    return 1;
}

texopt_status texopt_mesh_cut_create(const texopt_mesh *mesh, const uint32_t *piece_of, size_t piece_count,
                                     texopt_mesh **out, uint32_t **source, char *err, size_t err_len)
{
    size_t nt = mesh->triangle_count, nv_max = mesh->vertex_count + 3 * nt;
    uint32_t *src = malloc((nv_max ? nv_max : 1) * sizeof *src);
    texopt_mesh *m = calloc(1, sizeof *m);
    int ok = m && src;
    if (ok) {
        *m = *mesh; /* the scalars; every array is replaced below */
        m->triangle = malloc((nt ? 3 * nt : 1) * sizeof *m->triangle);
        m->vertex_count = m->triangle ? split_corners(mesh, piece_of, m->triangle, src) : 0;
        ok = m->triangle && (m->vertex_count || !mesh->vertex_count);
        ok = copy_vertices(mesh, src, m) && ok;
        size_t pt = mesh->point_triangle_start ? mesh->point_triangle_start[mesh->point_count] : 0;
        m->vertex_of_model_vertex =
            copy_of(mesh->vertex_of_model_vertex, mesh->model_vertex_count * sizeof *m->vertex_of_model_vertex, &ok);
        m->position = copy_of(mesh->position, 3 * mesh->point_count * sizeof *m->position, &ok);
        m->model_triangle = copy_of(mesh->model_triangle, nt * sizeof *m->model_triangle, &ok);
        m->area_3d = copy_of(mesh->area_3d, nt * sizeof *m->area_3d, &ok);
        m->area_texel = copy_of(mesh->area_texel, nt * sizeof *m->area_texel, &ok);
        m->flags = copy_of(mesh->flags, nt * sizeof *m->flags, &ok);
        m->chart_of = copy_of(piece_of, nt * sizeof *m->chart_of, &ok);
        m->point_triangle_start =
            copy_of(mesh->point_triangle_start, (mesh->point_count + 1) * sizeof *m->point_triangle_start, &ok);
        m->point_triangle = copy_of(mesh->point_triangle, pt * sizeof *m->point_triangle, &ok);
        m->chart_count = piece_count;
        m->chart_sign = malloc(piece_count ? piece_count : 1);
        ok = ok && m->chart_sign;
        for (size_t t = 0; ok && t < nt; t++)
            m->chart_sign[piece_of[t]] = mesh->chart_sign ? mesh->chart_sign[mesh->chart_of[t]] : 1;
        ok = ok && mark_boundary(m);
    }
    if (!ok) {
        texopt_mesh_destroy(m);
        free(src);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart cut: no memory for the cut mesh");
    }
    *out = m;
    if (source)
        *source = src;
    else
        free(src);
    return TEXOPT_OK;
}
