/* triangulate.c - constrained triangulation: Lawson insertion, Sloan segment recovery.
 *
 * Triangles keep their neighbour across the edge opposite each corner; every flip keeps
 * the point it was made for at corner 0 of both new triangles, so insertion can legalise
 * the edges opposite the new point with a plain stack. Segment recovery and the searches it
 * needs scan the triangle list: the scaffold triangulates one chart's boundary at a time
 * (hundreds to a few thousand points), where that costs less than keeping an index. */
#include "triangulate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sort_keys.h"

#define SUPER_SCALE 64.0 /* enclosing triangle size, in extents of the points */

typedef struct tri {
    uint32_t v[3];
    int32_t nb[3]; /* neighbour across the edge opposite v[i], -1 for none */
} tri;

typedef struct builder {
    double *p; /* input points then the 3 enclosing corners */
    size_t n;  /* input points */
    tri *t;
    size_t count, cap;
    int32_t last; /* where the next point search starts */
} builder;

static double orient(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* > 0 when d lies inside the circle through the counter-clockwise a, b, c. */
static double incircle(const double *a, const double *b, const double *c, const double *d)
{
    double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1];
    double cx = c[0] - d[0], cy = c[1] - d[1];
    double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    return ax * (by * c2 - b2 * cy) - ay * (bx * c2 - b2 * cx) + a2 * (bx * cy - by * cx);
}

static const double *pt(const builder *b, uint32_t v)
{
    return b->p + 2 * (size_t)v;
}

static int32_t new_tri(builder *b)
{
    if (b->count == b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 64;
        tri *grown = realloc(b->t, cap * sizeof *grown);
        if (!grown)
            return -1;
        b->t = grown;
        b->cap = cap;
    }
    return (int32_t)b->count++;
}

static void set_tri(builder *b, int32_t t, uint32_t v0, uint32_t v1, uint32_t v2, int32_t n0, int32_t n1, int32_t n2)
{
    tri *x = &b->t[t];
    x->v[0] = v0;
    x->v[1] = v1;
    x->v[2] = v2;
    x->nb[0] = n0;
    x->nb[1] = n1;
    x->nb[2] = n2;
}

/* Points triangle t's neighbour across its edge (x, y) to `to`. By the edge, not by the old
 * neighbour: one triangle can border both triangles a split replaces. */
static void relink(builder *b, int32_t t, uint32_t x, uint32_t y, int32_t to)
{
    if (t < 0)
        return;
    for (int i = 0; i < 3; i++) {
        uint32_t p = b->t[t].v[(i + 1) % 3], q = b->t[t].v[(i + 2) % 3];
        if ((p == x && q == y) || (p == y && q == x))
            b->t[t].nb[i] = to;
    }
}

static int corner_facing(const builder *b, int32_t t, int32_t neighbour)
{
    for (int i = 0; i < 3; i++)
        if (b->t[t].nb[i] == neighbour)
            return i;
    return -1;
}

/* Flips the edge opposite corner i of t: t = (p, a, b), its neighbour u = (q, b, a) become
 * t = (p, a, q) and u = (p, q, b). */
static void flip(builder *b, int32_t t, int i)
{
    tri *T = &b->t[t];
    int32_t u = T->nb[i];
    int j = corner_facing(b, u, t);
    const tri *U = &b->t[u];
    uint32_t p = T->v[i], a = T->v[(i + 1) % 3], c = T->v[(i + 2) % 3], q = U->v[j];
    int32_t tA = T->nb[(i + 2) % 3], tB = T->nb[(i + 1) % 3];
    int32_t uA = U->nb[(j + 1) % 3], uB = U->nb[(j + 2) % 3];
    set_tri(b, t, p, a, q, uA, u, tA);
    set_tri(b, u, p, q, c, uB, tB, t);
    relink(b, uA, a, q, t);
    relink(b, tB, c, p, u);
}

/* Restores the Delaunay property around a new point that sits at corner 0 of the
 * triangles on the stack. */
static int legalise(builder *b, int32_t *stack, size_t top, size_t stack_cap)
{
    while (top > 0) {
        int32_t t = stack[--top];
        int32_t u = b->t[t].nb[0];
        if (u < 0)
            continue;
        int j = corner_facing(b, u, t);
        const tri *T = &b->t[t];
        if (incircle(pt(b, T->v[0]), pt(b, T->v[1]), pt(b, T->v[2]), pt(b, b->t[u].v[j])) <= 0.0)
            continue;
        flip(b, t, 0);
        if (top + 2 > stack_cap)
            return -1;
        stack[top++] = t;
        stack[top++] = u;
    }
    return 0;
}

/* The triangle holding point p (walking from the last one, then scanning), with the corner
 * whose opposite edge p lies on in *edge (-1 when strictly inside). */
static int32_t locate(const builder *b, const double *p, int *edge)
{
    int32_t t = b->last;
    for (size_t steps = 0; steps < b->count + 8 && t >= 0; steps++) {
        int moved = 0, zero = -1;
        for (int i = 0; i < 3 && !moved; i++) {
            double o = orient(pt(b, b->t[t].v[(i + 1) % 3]), pt(b, b->t[t].v[(i + 2) % 3]), p);
            if (o < 0.0) {
                t = b->t[t].nb[i];
                moved = 1;
            } else if (o == 0.0)
                zero = i;
        }
        if (!moved) {
            *edge = zero;
            return t;
        }
    }
    for (size_t s = 0; s < b->count; s++) {
        int zero = -1, inside = 1;
        for (int i = 0; i < 3 && inside; i++) {
            double o = orient(pt(b, b->t[s].v[(i + 1) % 3]), pt(b, b->t[s].v[(i + 2) % 3]), p);
            inside = o >= 0.0;
            if (o == 0.0)
                zero = i;
        }
        if (inside) {
            *edge = zero;
            return (int32_t)s;
        }
    }
    return -1;
}

static int split_inside(builder *b, int32_t t, uint32_t p, int32_t *stack)
{
    int32_t t1 = new_tri(b), t2 = new_tri(b);
    if (t1 < 0 || t2 < 0)
        return -1;
    tri old = b->t[t];
    int32_t ts[3] = {t, t1, t2};
    for (int k = 0; k < 3; k++) {
        set_tri(b, ts[k], p, old.v[(k + 1) % 3], old.v[(k + 2) % 3], old.nb[k], ts[(k + 1) % 3], ts[(k + 2) % 3]);
        relink(b, old.nb[k], old.v[(k + 1) % 3], old.v[(k + 2) % 3], ts[k]);
        stack[k] = ts[k];
    }
    return 3;
}

/* p on the edge opposite corner i of t, shared with u: four triangles around p. */
static int split_edge(builder *b, int32_t t, int i, uint32_t p, int32_t *stack)
{
    int32_t u = b->t[t].nb[i];
    if (u < 0)
        return -1; /* on the enclosing triangle: cannot happen for input points */
    int j = corner_facing(b, u, t);
    tri T = b->t[t], U = b->t[u];
    uint32_t c = T.v[i], a = T.v[(i + 1) % 3], bb = T.v[(i + 2) % 3], d = U.v[j];
    int32_t t_ca = T.nb[(i + 2) % 3], t_bc = T.nb[(i + 1) % 3];
    int32_t u_db = U.nb[(j + 2) % 3], u_ad = U.nb[(j + 1) % 3];
    int32_t t3 = new_tri(b), t4 = new_tri(b);
    if (t3 < 0 || t4 < 0)
        return -1;
    int32_t t1 = t, t2 = u;
    set_tri(b, t1, p, c, a, t_ca, t4, t2);
    set_tri(b, t2, p, bb, c, t_bc, t1, t3);
    set_tri(b, t3, p, d, bb, u_db, t2, t4);
    set_tri(b, t4, p, a, d, u_ad, t3, t1);
    relink(b, t_ca, c, a, t1);
    relink(b, t_bc, bb, c, t2);
    relink(b, u_db, d, bb, t3);
    relink(b, u_ad, a, d, t4);
    stack[0] = t1;
    stack[1] = t2;
    stack[2] = t3;
    stack[3] = t4;
    return 4;
}

static texopt_status insert_points(builder *b, char *err, size_t err_len)
{
    size_t stack_cap = 4 * (b->n + 8) + 64;
    int32_t *stack = malloc(stack_cap * sizeof *stack);
    if (!stack)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    texopt_status st = TEXOPT_OK;
    for (size_t v = 0; v < b->n && st == TEXOPT_OK; v++) {
        int edge = -1;
        int32_t t = locate(b, pt(b, (uint32_t)v), &edge);
        if (t < 0) {
            st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "triangulate: point %zu not located", v);
            break;
        }
        for (int k = 0; k < 3; k++) {
            const double *q = pt(b, b->t[t].v[k]);
            if (q[0] == pt(b, (uint32_t)v)[0] && q[1] == pt(b, (uint32_t)v)[1])
                st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: points %zu and %u coincide", v,
                                 b->t[t].v[k]);
        }
        if (st != TEXOPT_OK)
            break;
        int pushed = edge < 0 ? split_inside(b, t, (uint32_t)v, stack) : split_edge(b, t, edge, (uint32_t)v, stack);
        if (pushed < 0 || legalise(b, stack, (size_t)pushed, stack_cap) < 0)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
        b->last = t;
    }
    free(stack);
    return st;
}

/* Whether segment (a, b) and edge (x, y) cross at a point inside both. */
static int crosses(const builder *b, uint32_t a, uint32_t c, uint32_t x, uint32_t y)
{
    if (x == a || x == c || y == a || y == c)
        return 0;
    const double *pa = pt(b, a), *pc = pt(b, c), *px = pt(b, x), *py = pt(b, y);
    double o1 = orient(pa, pc, px), o2 = orient(pa, pc, py);
    double o3 = orient(px, py, pa), o4 = orient(px, py, pc);
    return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
}

/* The triangle and corner whose opposite edge is (x, y) in either direction, or -1. */
static int32_t find_edge(const builder *b, uint32_t x, uint32_t y, int *corner)
{
    for (size_t t = 0; t < b->count; t++)
        for (int i = 0; i < 3; i++) {
            uint32_t p = b->t[t].v[(i + 1) % 3], q = b->t[t].v[(i + 2) % 3];
            if ((p == x && q == y) || (p == y && q == x)) {
                *corner = i;
                return (int32_t)t;
            }
        }
    return -1;
}

static int point_on_segment(const builder *b, uint32_t a, uint32_t c)
{
    const double *pa = pt(b, a), *pc = pt(b, c);
    for (size_t v = 0; v < b->n; v++) {
        if (v == a || v == c)
            continue;
        const double *q = pt(b, (uint32_t)v);
        if (orient(pa, pc, q) != 0.0)
            continue;
        double d = (q[0] - pa[0]) * (pc[0] - pa[0]) + (q[1] - pa[1]) * (pc[1] - pa[1]);
        double l = (pc[0] - pa[0]) * (pc[0] - pa[0]) + (pc[1] - pa[1]) * (pc[1] - pa[1]);
        if (d > 0.0 && d < l)
            return 1;
    }
    return 0;
}

static int is_segment(const uint64_t *keys, size_t count, uint32_t x, uint32_t y)
{
    uint64_t k = texopt_edge_key(x, y);
    return bsearch(&k, keys, count, sizeof *keys, texopt_compare_u64) != NULL;
}

/* Sloan's recovery of segment (a, c): flip every crossing edge whose quadrilateral is
 * convex, requeue the rest and the new diagonals that still cross. keys: every segment,
 * sorted (texopt_edge_key): a crossing edge that is one means two segments cross. */
static texopt_status recover_segment(builder *b, uint32_t a, uint32_t c, const uint64_t *keys, size_t key_count,
                                     char *err, size_t err_len)
{
    int corner;
    if (find_edge(b, a, c, &corner) >= 0)
        return TEXOPT_OK;
    if (point_on_segment(b, a, c))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "triangulate: segment %u-%u passes through another point", a, c);
    size_t cap = 64, head = 0, tail = 0;
    uint32_t *queue = malloc(2 * cap * sizeof *queue);
    if (!queue)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    texopt_status st = TEXOPT_OK;
    for (size_t t = 0; t < b->count && st == TEXOPT_OK; t++)
        for (int i = 0; i < 3; i++) {
            int32_t u = b->t[t].nb[i];
            uint32_t x = b->t[t].v[(i + 1) % 3], y = b->t[t].v[(i + 2) % 3];
            if ((u >= 0 && u < (int32_t)t) || !crosses(b, a, c, x, y))
                continue;
            if (is_segment(keys, key_count, x, y)) {
                st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: segments %u-%u and %u-%u cross",
                                 a, c, x, y);
                break;
            }
            if (tail == cap) {
                uint32_t *grown = realloc(queue, 4 * cap * sizeof *grown);
                if (!grown) {
                    st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
                    break;
                }
                queue = grown;
                cap *= 2;
            }
            queue[2 * tail] = x;
            queue[2 * tail + 1] = y;
            tail++;
        }
    size_t limit = 64 * (tail + 1) * (tail + 1) + 1000;
    for (size_t steps = 0; st == TEXOPT_OK && head != tail; steps++) {
        if (steps > limit) {
            st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                             "triangulate: segment %u-%u not recovered (crossing segments?)", a, c);
            break;
        }
        uint32_t x = queue[2 * (head % cap)], y = queue[2 * (head % cap) + 1];
        head++;
        int32_t t = find_edge(b, x, y, &corner);
        int32_t u = t >= 0 ? b->t[t].nb[corner] : -1;
        if (u < 0) {
            st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "triangulate: lost edge %u-%u", x, y);
            break;
        }
        uint32_t p = b->t[t].v[corner], e1 = b->t[t].v[(corner + 1) % 3], e2 = b->t[t].v[(corner + 2) % 3];
        uint32_t q = b->t[u].v[corner_facing(b, u, t)];
        int convex = orient(pt(b, p), pt(b, e1), pt(b, q)) > 0.0 && orient(pt(b, p), pt(b, q), pt(b, e2)) > 0.0;
        if (convex)
            flip(b, t, corner);
        uint32_t nx = convex ? p : x, ny = convex ? q : y;
        if (!convex || crosses(b, a, c, nx, ny)) { /* the queue never holds more than it started with */
            queue[2 * (tail % cap)] = nx;
            queue[2 * (tail % cap) + 1] = ny;
            tail++;
        }
    }
    free(queue);
    return st;
}

/* Depth by levels: flood each level through non-segment edges, then step across the
 * segments on its border into the next. */
static texopt_status compute_depths(const builder *b, const uint64_t *keys, size_t segment_count, int *depth, char *err,
                                    size_t err_len)
{
    int32_t *level = malloc((b->count + 1) * sizeof *level); /* triangles of the level, in order */
    if (!level)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    size_t n = 0;
    for (size_t t = 0; t < b->count; t++) {
        int outside = b->t[t].v[0] >= b->n || b->t[t].v[1] >= b->n || b->t[t].v[2] >= b->n;
        depth[t] = outside ? 0 : -1;
        if (outside)
            level[n++] = (int32_t)t;
    }
    for (int d = 0; n > 0; d++) {
        for (size_t k = 0; k < n; k++) /* n grows while the level floods */
            for (int i = 0; i < 3; i++) {
                int32_t t = level[k], u = b->t[t].nb[i];
                if (u >= 0 && depth[u] < 0 &&
                    !is_segment(keys, segment_count, b->t[t].v[(i + 1) % 3], b->t[t].v[(i + 2) % 3])) {
                    depth[u] = d;
                    level[n++] = u;
                }
            }
        size_t next = 0;
        for (size_t k = 0; k < n; k++)
            for (int i = 0; i < 3; i++) {
                int32_t u = b->t[level[k]].nb[i];
                if (u >= 0 && depth[u] < 0) {
                    depth[u] = d + 1;
                    level[n + next++] = u;
                }
            }
        memmove(level, level + n, next * sizeof *level);
        n = next;
    }
    free(level);
    return TEXOPT_OK;
}

static texopt_status enclose(builder *b, const double *xy, char *err, size_t err_len)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t v = 0; v < b->n; v++)
        for (int k = 0; k < 2; k++) {
            if (!isfinite(xy[2 * v + k]))
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: point %zu is not finite", v);
            lo[k] = fmin(lo[k], xy[2 * v + k]);
            hi[k] = fmax(hi[k], xy[2 * v + k]);
        }
    double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
    double r = SUPER_SCALE * fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), 1e-12);
    memcpy(b->p, xy, 2 * b->n * sizeof *b->p);
    double *s = b->p + 2 * b->n;
    s[0] = cx - r;
    s[1] = cy - r;
    s[2] = cx + r;
    s[3] = cy - r;
    s[4] = cx;
    s[5] = cy + r;
    int32_t t = new_tri(b);
    if (t < 0)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    set_tri(b, t, (uint32_t)b->n, (uint32_t)b->n + 1, (uint32_t)b->n + 2, -1, -1, -1);
    return TEXOPT_OK;
}

static texopt_status collect(const builder *b, const int *depth, texopt_triangulation *out, char *err, size_t err_len)
{
    size_t n = 0;
    out->triangle = malloc((3 * b->count + 1) * sizeof *out->triangle);
    out->depth = malloc((b->count + 1) * sizeof *out->depth);
    if (!out->triangle || !out->depth)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    for (size_t t = 0; t < b->count; t++) {
        const tri *x = &b->t[t];
        if (x->v[0] >= b->n || x->v[1] >= b->n || x->v[2] >= b->n)
            continue;
        memcpy(out->triangle + 3 * n, x->v, sizeof x->v);
        out->depth[n++] = depth[t];
    }
    out->triangle_count = n;
    if (n == 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: the points are collinear");
    return TEXOPT_OK;
}

texopt_status texopt_triangulate(const double *xy, size_t point_count, const uint32_t *segment, size_t segment_count,
                                 texopt_triangulation *out, char *err, size_t err_len)
{
    if (!out || (!xy && point_count) || (!segment && segment_count))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: NULL argument");
    memset(out, 0, sizeof *out);
    if (point_count < 3 || point_count > (size_t)INT32_MAX / 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: %zu points", point_count);
    for (size_t s = 0; s < segment_count; s++)
        if (segment[2 * s] >= point_count || segment[2 * s + 1] >= point_count || segment[2 * s] == segment[2 * s + 1])
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triangulate: segment %zu is invalid", s);
    builder b = {0};
    b.n = point_count;
    b.p = malloc(2 * (point_count + 3) * sizeof *b.p);
    int *depth = NULL;
    uint64_t *keys = malloc((segment_count ? segment_count : 1) * sizeof *keys);
    texopt_status st = b.p && keys ? enclose(&b, xy, err, err_len)
                                   : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    for (size_t s = 0; s < segment_count && st == TEXOPT_OK; s++)
        keys[s] = texopt_edge_key(segment[2 * s], segment[2 * s + 1]);
    if (st == TEXOPT_OK)
        qsort(keys, segment_count, sizeof *keys, texopt_compare_u64);
    if (st == TEXOPT_OK)
        st = insert_points(&b, err, err_len);
    for (size_t s = 0; s < segment_count && st == TEXOPT_OK; s++)
        st = recover_segment(&b, segment[2 * s], segment[2 * s + 1], keys, segment_count, err, err_len);
    if (st == TEXOPT_OK && !(depth = malloc((b.count + 1) * sizeof *depth)))
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triangulate: out of memory");
    if (st == TEXOPT_OK)
        st = compute_depths(&b, keys, segment_count, depth, err, err_len);
    if (st == TEXOPT_OK)
        st = collect(&b, depth, out, err, err_len);
    if (st != TEXOPT_OK)
        texopt_triangulation_destroy(out);
    free(depth);
    free(keys);
    free(b.p);
    free(b.t);
    return st;
}

void texopt_triangulation_destroy(texopt_triangulation *t)
{
    if (!t)
        return;
    free(t->triangle);
    free(t->depth);
    memset(t, 0, sizeof *t);
}
