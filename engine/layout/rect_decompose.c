/* rect_decompose.c - motorcycle-graph rectangles of an axis-aligned chart, packing, eq. 11.
 *
 * Everything lives on the grid of the polygon's distinct x and y coordinates: every trail
 * runs along a grid line from a corner, so it crosses other trails and the boundary only
 * at grid nodes, and the motorcycles can be simulated node by node (arrival times are true
 * distances). The faces are the connected sets of inside grid cells not separated by a
 * boundary or trail segment; each must fill its bounding box. */
#include "rect_decompose.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"

#define MAX_ASPECT 20.0     /* paper */
#define BOUNDARY_WEIGHT 0.1 /* omega of eq. 11 (paper) */

typedef struct grid {
    double *xs, *ys;
    size_t nx, ny;
    uint8_t *hwall;   /* (i, j)-(i + 1, j): j * (nx - 1) + i */
    uint8_t *vwall;   /* (i, j)-(i, j + 1): j * nx + i */
    uint8_t *visited; /* nodes: on the boundary or a trail */
    uint8_t *inside;  /* cells: j * (nx - 1) + i */
} grid;

static int compare_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : a > b;
}

static size_t unique_sorted(const double *xy, size_t n, int axis, double *out)
{
    for (size_t i = 0; i < n; i++)
        out[i] = xy[2 * i + axis];
    qsort(out, n, sizeof *out, compare_double);
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (m == 0 || out[i] != out[m - 1])
            out[m++] = out[i];
    return m;
}

static size_t index_of(const double *v, size_t n, double x)
{
    const double *p = bsearch(&x, v, n, sizeof *v, compare_double);
    return (size_t)(p - v);
}

static double cross_turn(const double *xy, size_t n, size_t i)
{
    const double *a = xy + 2 * ((i + n - 1) % n), *b = xy + 2 * i, *c = xy + 2 * ((i + 1) % n);
    return (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
}

size_t texopt_rect_reflex_corners(const double *xy, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        k += cross_turn(xy, n, i) < 0.0;
    return k;
}

static int point_inside(const double *xy, size_t n, double px, double py)
{
    int in = 0;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * j;
        if ((a[1] > py) != (b[1] > py) && px < (b[0] - a[0]) * (py - a[1]) / (b[1] - a[1]) + a[0])
            in = !in;
    }
    return in;
}

static void grid_free(grid *g)
{
    free(g->xs);
    free(g->ys);
    free(g->hwall);
    free(g->vwall);
    free(g->visited);
    free(g->inside);
}

static texopt_status grid_build(grid *g, const double *xy, size_t n, char *err, size_t err_len)
{
    memset(g, 0, sizeof *g);
    double area = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        if ((a[0] != b[0]) == (a[1] != b[1]) || !isfinite(a[0]) || !isfinite(a[1]))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "rectangles: edge %zu is not axis-aligned or has no length", i);
        area += a[0] * b[1] - a[1] * b[0];
    }
    if (!(area > 0.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rectangles: the polygon is not counter-clockwise");
    g->xs = malloc(n * sizeof *g->xs);
    g->ys = malloc(n * sizeof *g->ys);
    if (!g->xs || !g->ys)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rectangles: out of memory");
    g->nx = unique_sorted(xy, n, 0, g->xs);
    g->ny = unique_sorted(xy, n, 1, g->ys);
    size_t cells = (g->nx - 1) * (g->ny - 1);
    g->hwall = calloc((g->nx - 1) * g->ny, 1);
    g->vwall = calloc(g->nx * (g->ny - 1), 1);
    g->visited = calloc(g->nx * g->ny, 1);
    g->inside = calloc(cells ? cells : 1, 1);
    if (!g->hwall || !g->vwall || !g->visited || !g->inside)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rectangles: out of memory");
    for (size_t i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        size_t ia = index_of(g->xs, g->nx, a[0]), ib = index_of(g->xs, g->nx, b[0]);
        size_t ja = index_of(g->ys, g->ny, a[1]), jb = index_of(g->ys, g->ny, b[1]);
        size_t lo = ia == ib ? (ja < jb ? ja : jb) : (ia < ib ? ia : ib),
               hi = ia == ib ? (ja < jb ? jb : ja) : (ia < ib ? ib : ia);
        for (size_t k = lo; k <= hi; k++) {
            g->visited[ia == ib ? k * g->nx + ia : ja * g->nx + k] = 1;
            if (k < hi) {
                if (ia == ib)
                    g->vwall[k * g->nx + ia] = 1;
                else
                    g->hwall[ja * (g->nx - 1) + k] = 1;
            }
        }
    }
    for (size_t j = 0; j + 1 < g->ny; j++)
        for (size_t i = 0; i + 1 < g->nx; i++)
            g->inside[j * (g->nx - 1) + i] =
                (uint8_t)point_inside(xy, n, 0.5 * (g->xs[i] + g->xs[i + 1]), 0.5 * (g->ys[j] + g->ys[j + 1]));
    return TEXOPT_OK;
}

typedef struct motorcycle {
    long i, j;   /* current node */
    int di, dj;  /* direction in grid steps */
    double time; /* distance travelled */
    int active;
} motorcycle;

static double next_length(const grid *g, const motorcycle *m)
{
    long ni = m->i + m->di, nj = m->j + m->dj;
    if (ni < 0 || nj < 0 || ni >= (long)g->nx || nj >= (long)g->ny)
        return INFINITY;
    return m->di ? fabs(g->xs[ni] - g->xs[m->i]) : fabs(g->ys[nj] - g->ys[m->j]);
}

/* Runs the motorcycles to their stops, leaving their trails as walls. */
static void race(grid *g, motorcycle *bikes, size_t count)
{
    for (;;) {
        size_t best = count;
        double best_t = INFINITY;
        for (size_t k = 0; k < count; k++)
            if (bikes[k].active && bikes[k].time + next_length(g, &bikes[k]) < best_t) {
                best_t = bikes[k].time + next_length(g, &bikes[k]);
                best = k;
            }
        if (best == count)
            return;
        motorcycle *m = &bikes[best];
        long ni = m->i + m->di, nj = m->j + m->dj;
        if (m->di)
            g->hwall[(size_t)m->j * (g->nx - 1) + (size_t)(m->di > 0 ? m->i : ni)] = 1;
        else
            g->vwall[(size_t)(m->dj > 0 ? m->j : nj) * g->nx + (size_t)m->i] = 1;
        m->i = ni;
        m->j = nj;
        m->time = best_t;
        size_t node = (size_t)nj * g->nx + (size_t)ni;
        if (g->visited[node])
            m->active = 0;
        g->visited[node] = 1;
    }
}

/* The faces of the inside cells, each checked to be a rectangle. */
static texopt_status collect_faces(const grid *g, texopt_rect **rects, size_t *count, char *err, size_t err_len)
{
    size_t w = g->nx - 1, cells = w * (g->ny - 1);
    long *label = malloc((cells ? cells : 1) * sizeof *label);
    size_t *stack = malloc((cells ? cells : 1) * sizeof *stack);
    texopt_rect *out = malloc((cells ? cells : 1) * sizeof *out);
    if (!label || !stack || !out) {
        free(label);
        free(stack);
        free(out);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rectangles: out of memory");
    }
    for (size_t c = 0; c < cells; c++)
        label[c] = -1;
    size_t faces = 0;
    texopt_status st = TEXOPT_OK;
    for (size_t seed = 0; seed < cells && st == TEXOPT_OK; seed++) {
        if (!g->inside[seed] || label[seed] >= 0)
            continue;
        size_t top = 0, members = 0, i0 = SIZE_MAX, i1 = 0, j0 = SIZE_MAX, j1 = 0;
        label[seed] = (long)faces;
        stack[top++] = seed;
        while (top > 0) {
            size_t c = stack[--top], i = c % w, j = c / w;
            members++;
            i0 = i < i0 ? i : i0;
            i1 = i > i1 ? i : i1;
            j0 = j < j0 ? j : j0;
            j1 = j > j1 ? j : j1;
            size_t next[4];
            int open[4] = {i + 1 < w && !g->vwall[j * g->nx + i + 1], i > 0 && !g->vwall[j * g->nx + i],
                           j + 2 < g->ny && !g->hwall[(j + 1) * w + i], j > 0 && !g->hwall[j * w + i]};
            next[0] = c + 1;
            next[1] = c - 1;
            next[2] = c + w;
            next[3] = c - w;
            for (int k = 0; k < 4; k++)
                if (open[k] && g->inside[next[k]] && label[next[k]] < 0) {
                    label[next[k]] = (long)faces;
                    stack[top++] = next[k];
                }
        }
        if (members != (i1 - i0 + 1) * (j1 - j0 + 1))
            st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                             "rectangles: a face is not a rectangle (polygon not simple?)");
        texopt_rect r = {g->xs[i0], g->ys[j0], g->xs[i1 + 1], g->ys[j1 + 1]};
        out[faces++] = r;
    }
    free(label);
    free(stack);
    if (st != TEXOPT_OK) {
        free(out);
        return st;
    }
    *rects = out;
    *count = faces;
    return TEXOPT_OK;
}

static int sign_of(double v)
{
    return v > 0.0 ? 1 : v < 0.0 ? -1 : 0;
}

/* A polygon's grid after its motorcycles ran: each bike at its stop, corner[k] the polygon
 * point bike k left from. */
typedef struct race_result {
    grid g;
    motorcycle *bikes;
    size_t *corner, count;
} race_result;

static void race_free(race_result *r)
{
    free(r->bikes);
    free(r->corner);
    grid_free(&r->g);
}

/* Builds the grid of the polygon and runs its motorcycles (choice as in the header); r is
 * the caller's to free (race_free) whatever the status. */
static texopt_status race_run(race_result *r, const double *xy, size_t n, const uint8_t *choice, char *err,
                              size_t err_len)
{
    memset(r, 0, sizeof *r);
    if (!xy || n < 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rectangles: need a polygon of 4 points or more");
    texopt_status st = grid_build(&r->g, xy, n, err, err_len);
    r->bikes = malloc(2 * n * sizeof *r->bikes);
    r->corner = malloc(2 * n * sizeof *r->corner);
    if (st == TEXOPT_OK && (!r->bikes || !r->corner))
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rectangles: out of memory");
    size_t reflex = 0;
    for (size_t v = 0; v < n && st == TEXOPT_OK; v++) {
        if (!(cross_turn(xy, n, v) < 0.0))
            continue;
        uint8_t c = choice ? choice[reflex] & 3 : 3;
        reflex++;
        const double *a = xy + 2 * ((v + n - 1) % n), *b = xy + 2 * v, *d = xy + 2 * ((v + 1) % n);
        long i = (long)index_of(r->g.xs, r->g.nx, b[0]), j = (long)index_of(r->g.ys, r->g.ny, b[1]);
        int dirs[2][2] = {{sign_of(b[0] - a[0]), sign_of(b[1] - a[1])}, {sign_of(b[0] - d[0]), sign_of(b[1] - d[1])}};
        for (int k = 0; k < 2; k++)
            if (c == 0 || (c >> k) & 1) {
                motorcycle m = {i, j, dirs[k][0], dirs[k][1], 0.0, 1};
                r->corner[r->count] = v;
                r->bikes[r->count++] = m;
            }
    }
    if (st == TEXOPT_OK)
        race(&r->g, r->bikes, r->count);
    return st;
}

texopt_status texopt_rect_decompose(const double *xy, size_t n, const uint8_t *choice, texopt_rect **rects,
                                    size_t *count, char *err, size_t err_len)
{
    race_result r;
    texopt_status st = race_run(&r, xy, n, choice, err, err_len);
    if (st == TEXOPT_OK && (!rects || !count))
        st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rectangles: no output");
    if (st == TEXOPT_OK)
        st = collect_faces(&r.g, rects, count, err, err_len);
    race_free(&r);
    return st;
}

texopt_status texopt_rect_trails(const double *xy, size_t n, const uint8_t *choice, texopt_rect_trail **trails,
                                 size_t *count, char *err, size_t err_len)
{
    race_result r;
    texopt_status st = race_run(&r, xy, n, choice, err, err_len);
    if (st == TEXOPT_OK && (!trails || !count))
        st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "rectangles: no output");
    texopt_rect_trail *out = st == TEXOPT_OK ? malloc((r.count ? r.count : 1) * sizeof *out) : NULL;
    if (st == TEXOPT_OK && !out)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "rectangles: out of memory");
    for (size_t k = 0; out && k < r.count; k++) {
        const double *c = xy + 2 * r.corner[k];
        const motorcycle *m = &r.bikes[k];
        texopt_rect_trail t = {r.corner[k], c[0], c[1], r.g.xs[m->i], r.g.ys[m->j], m->time};
        out[k] = t;
    }
    if (st == TEXOPT_OK) {
        *trails = out;
        *count = r.count;
    }
    race_free(&r);
    return st;
}

typedef struct skyline_seg {
    double x, w, y;
} skyline_seg;

/* Bottom-left skyline packing into a strip of width W; returns the height, or INFINITY when
 * a rectangle is wider than the strip or memory runs out. */
static double skyline(const double *w, const double *h, const size_t *order, size_t n, double W, double *x, double *y)
{
    skyline_seg *s = malloc((2 * n + 2) * sizeof *s), *t = malloc((2 * n + 2) * sizeof *t);
    if (!s || !t) {
        free(s);
        free(t);
        return INFINITY;
    }
    size_t ns = 1;
    s[0] = (skyline_seg){0.0, W, 0.0};
    double height = 0.0;
    for (size_t k = 0; k < n && isfinite(height); k++) {
        size_t r = order[k];
        double best_y = INFINITY, best_x = 0.0;
        for (size_t a = 0; a < ns; a++) {
            double x0 = s[a].x, top = 0.0;
            if (x0 + w[r] > W + 1e-9)
                break;
            for (size_t b = a; b < ns && s[b].x < x0 + w[r] - 1e-12; b++)
                top = fmax(top, s[b].y);
            if (top < best_y) {
                best_y = top;
                best_x = x0;
            }
        }
        if (!isfinite(best_y)) {
            height = INFINITY;
            break;
        }
        x[r] = best_x;
        y[r] = best_y;
        height = fmax(height, best_y + h[r]);
        /* new skyline: the parts left of the rectangle, its top, the parts right of it */
        size_t nt = 0;
        double x1 = best_x + w[r];
        for (size_t a = 0; a < ns; a++)
            if (s[a].x < best_x)
                t[nt++] = (skyline_seg){s[a].x, fmin(s[a].x + s[a].w, best_x) - s[a].x, s[a].y};
        t[nt++] = (skyline_seg){best_x, w[r], best_y + h[r]};
        for (size_t a = 0; a < ns; a++)
            if (s[a].x + s[a].w > x1)
                t[nt++] = (skyline_seg){fmax(s[a].x, x1), s[a].x + s[a].w - fmax(s[a].x, x1), s[a].y};
        skyline_seg *swap = s;
        s = t;
        t = swap;
        ns = nt;
    }
    free(s);
    free(t);
    return height;
}

typedef struct keyed {
    double key;
    size_t index;
} keyed;

static int by_key_desc(const void *pa, const void *pb)
{
    double a = ((const keyed *)pa)->key, b = ((const keyed *)pb)->key;
    return a > b ? -1 : a < b;
}

double texopt_rect_pack(const double *w, const double *h, size_t n, double padding, double *x, double *y, double *width,
                        double *height)
{
    double *pw = malloc((n + 1) * sizeof *pw), *ph = malloc((n + 1) * sizeof *ph);
    double *tx = malloc((n + 1) * sizeof *tx), *ty = malloc((n + 1) * sizeof *ty);
    size_t *order = malloc((n + 1) * sizeof *order);
    double area = 0.0, padded = 0.0, widest = 0.0, best = INFINITY;
    *width = *height = 0.0;
    if (!pw || !ph || !tx || !ty || !order || n == 0) {
        free(pw);
        free(ph);
        free(tx);
        free(ty);
        free(order);
        return 0.0;
    }
    for (size_t i = 0; i < n; i++) {
        pw[i] = w[i] + padding;
        ph[i] = h[i] + padding;
        area += w[i] * h[i];
        padded += pw[i] * ph[i];
        widest = fmax(widest, pw[i]);
        order[i] = i;
    }
    keyed *k = malloc(n * sizeof *k);
    for (size_t i = 0; k && i < n; i++)
        k[i] = (keyed){ph[i], i};
    if (k)
        qsort(k, n, sizeof *k, by_key_desc);
    for (size_t i = 0; k && i < n; i++)
        order[i] = k[i].index;
    free(k);
    for (int f = 0; f <= 10; f++) {
        double W = fmax(widest, sqrt(padded) * (1.0 + 0.1 * f));
        double H = skyline(pw, ph, order, n, W, tx, ty);
        double used = 0.0;
        for (size_t i = 0; i < n; i++)
            used = fmax(used, tx[i] + pw[i]);
        if (used * H < best) {
            best = used * H;
            *width = used;
            *height = H;
            memcpy(x, tx, n * sizeof *x);
            memcpy(y, ty, n * sizeof *y);
        }
    }
    free(pw);
    free(ph);
    free(tx);
    free(ty);
    free(order);
    return best > 0.0 && isfinite(best) ? area / best : 0.0;
}

static double perimeter(const double *xy, size_t n)
{
    double l = 0.0;
    for (size_t i = 0; i < n; i++)
        l += fabs(xy[2 * ((i + 1) % n)] - xy[2 * i]) + fabs(xy[2 * ((i + 1) % n) + 1] - xy[2 * i + 1]);
    return l;
}

/* Eq. 11 of one decomposition, or -INFINITY when a rectangle is too thin or the packing
 * falls below the bound. */
static double score(const texopt_rect *r, size_t count, double bl0, double padding, double bound, double *work,
                    texopt_rect_choice *c)
{
    double *w = work, *h = work + count, *x = work + 2 * count, *y = work + 3 * count, bl1 = 0.0, W, H;
    for (size_t k = 0; k < count; k++) {
        w[k] = r[k].x1 - r[k].x0;
        h[k] = r[k].y1 - r[k].y0;
        if (fmax(w[k], h[k]) > MAX_ASPECT * fmin(w[k], h[k]))
            return -INFINITY;
        bl1 += 2.0 * (w[k] + h[k]);
    }
    double pe = texopt_rect_pack(w, h, count, padding, x, y, &W, &H);
    if (pe < bound)
        return -INFINITY;
    c->efficiency = pe;
    c->boundary_ratio = bl1 / bl0;
    c->rect_count = count;
    c->score = pe - BOUNDARY_WEIGHT * bl1 / bl0;
    return c->score;
}

texopt_status texopt_rect_choose(const double *xy, size_t n, int candidates, uint64_t seed, double padding,
                                 double efficiency_bound, uint8_t *best_choice, texopt_rect_choice *out, char *err,
                                 size_t err_len)
{
    size_t reflex = xy && n >= 4 ? texopt_rect_reflex_corners(xy, n) : 0;
    uint8_t *choice = malloc(reflex + 1);
    double *work = malloc(4 * (n * n + 4) * sizeof *work); /* faces never exceed the grid's cells */
    if (!choice || !work || !out || (reflex && !best_choice) || candidates < 1) {
        free(choice);
        free(work);
        return texopt_fail(err, err_len, candidates < 1 || !out ? TEXOPT_E_INVALID_ARGUMENT : TEXOPT_E_NOMEM,
                           "rectangles: no candidates, no output or out of memory");
    }
    texopt_rng rng;
    texopt_rng_seed(&rng, seed);
    texopt_rect_choice best = {-INFINITY, 0.0, 0.0, 0, 0};
    double bl0 = perimeter(xy, n);
    texopt_status st = TEXOPT_OK;
    for (int k = 0; k < candidates && st == TEXOPT_OK; k++) {
        for (size_t c = 0; c < reflex; c++)
            choice[c] = (uint8_t)(1 + texopt_rng_below(&rng, 3));
        texopt_rect *rects = NULL;
        size_t count = 0;
        st = texopt_rect_decompose(xy, n, choice, &rects, &count, err, err_len);
        texopt_rect_choice c = {0};
        if (st == TEXOPT_OK && score(rects, count, bl0, padding, efficiency_bound, work, &c) > -INFINITY) {
            best.candidates_kept++;
            if (c.score > best.score) {
                c.candidates_kept = best.candidates_kept;
                best = c;
                memcpy(best_choice, choice, reflex);
            }
        }
        free(rects);
    }
    free(choice);
    free(work);
    if (st == TEXOPT_OK && best.candidates_kept == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                         "rectangles: no decomposition passes the aspect and efficiency filters");
    if (st == TEXOPT_OK)
        *out = best;
    return st;
}
