/* chart_unfold.c - overlapping charts laid out anew as disks (chart_unfold.h). */
#include "chart_unfold.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "param_abf.h"
#include "param_tutte.h"
#include "scaffold.h"
#include "sort_keys.h"
#include "vec2.h"
#include "vec3.h"

#define PART_TURN (3.14159265358979323846 / 18) /* 10 degrees */
#define PART_TURNS 18                           /* either way: a half turn */
#define PART_SHRINKS 4                          /* halvings of a part that clashes at every turn */

/* One chart as a parameterization input: its mesh vertices numbered locally. */
typedef struct local_chart {
    uint32_t *local_of;  /* per mesh vertex: its local index, UINT32_MAX outside the chart */
    uint32_t *vertex;    /* per local vertex: its mesh vertex */
    double *position;    /* 3 per local vertex */
    uint32_t *triangle;  /* 3 per chart triangle, local */
    double *uv;          /* 2 per local vertex */
    size_t vertex_count; /* of the chart being laid out */
    size_t triangle_count;
    size_t filled_vertices, filled_triangles; /* with the fans that fill its holes (fill_holes) */
    uint32_t *part_of;                        /* per mesh triangle: its part (chart_parts) */
    uint64_t *keys;                           /* 12 per mesh triangle: scratch of chart_parts, then
                                                 the parts' boundaries */
    uint8_t *placed;                          /* per mesh vertex: laid by a part (unfold_chart) */
} local_chart;

/* Whether chart c has a side of the orientation opposite to its own that is no fold-over:
 * mirrored halves (mesh.h: neither side is FLIPPED). */
static int chart_is_mirrored(const texopt_mesh *mesh, uint32_t c)
{
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (mesh->chart_of[t] == c && !(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_UV | TEXOPT_TRI_FLIPPED)) &&
            (mesh->area_texel[t] > 0 ? 1 : -1) != mesh->chart_sign[c])
            return 1;
    return 0;
}

/* Fills lc with the triangles of chart c in part `part` (part_of per triangle; NULL: all of
 * the chart) and their vertices; returns their input texel area. */
static double gather_chart(const texopt_mesh *mesh, uint32_t c, const uint32_t *part_of, uint32_t part, local_chart *lc)
{
    double area = 0;
    lc->vertex_count = lc->triangle_count = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (mesh->chart_of[t] != c || (part_of && part_of[t] != part))
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t v = mesh->triangle[3 * t + (size_t)k];
            if (lc->local_of[v] == UINT32_MAX) {
                lc->local_of[v] = (uint32_t)lc->vertex_count;
                lc->vertex[lc->vertex_count] = v;
                memcpy(lc->position + 3 * lc->vertex_count, texopt_mesh_vertex_point(mesh, v), 3 * sizeof(double));
                lc->vertex_count++;
            }
            lc->triangle[3 * lc->triangle_count + (size_t)k] = lc->local_of[v];
        }
        lc->triangle_count++;
        if (!(mesh->flags[t] & TEXOPT_TRI_DEGENERATE_UV))
            area += fabs(mesh->area_texel[t]);
    }
    return area;
}

/* Half-edge a -> b as a sortable key. */
static uint64_t half_edge(uint32_t a, uint32_t b)
{
    return (uint64_t)a << 32 | b;
}

static int has_half_edge(const uint64_t *keys, size_t n, uint64_t key)
{
    return bsearch(&key, keys, n, sizeof *keys, texopt_compare_u64) != NULL;
}

/* The boundary half-edge that follows a -> b round b (through the triangles at b, from the
 * one holding a -> b): so a pinched vertex's fans give loops of their own. UINT32_MAX when
 * the rotation does not end (a non-manifold vertex). `after` maps each half-edge to the
 * next one of its triangle. */
static uint32_t next_boundary_vertex(const uint64_t *keys, const uint64_t *after, size_t n, uint32_t a, uint32_t b)
{
    uint64_t e = half_edge(a, b);
    for (size_t steps = 0; steps <= n; steps++) {
        const uint64_t *hit = bsearch(&e, keys, n, sizeof *keys, texopt_compare_u64);
        if (!hit)
            return UINT32_MAX;
        uint64_t out = after[hit - keys]; /* b -> c in the same triangle */
        uint32_t c = (uint32_t)out;
        if (!has_half_edge(keys, n, half_edge(c, b)))
            return c;
        e = half_edge(c, b); /* into the triangle across b -> c */
    }
    return UINT32_MAX;
}

/* Fills every boundary loop of the chart but the longest (in 3D) with a fan round a new
 * vertex at the loop's centroid, after the chart's vertices and triangles, so that a chart
 * with holes or pinched vertices (its boundary through a vertex twice) becomes a disk whose
 * layout, fans dropped, is the chart's. Returns 1 when it filled some, 0 when the chart has
 * one loop, -1 when a rotation does not close, -2 when out of memory. */
static int fill_holes(local_chart *lc)
{
    size_t nh = 3 * lc->triangle_count;
    uint64_t *pairs = malloc(2 * (nh ? nh : 1) * sizeof *pairs), *keys = malloc((nh ? nh : 1) * sizeof *keys);
    uint64_t *after = malloc((nh ? nh : 1) * sizeof *after);
    uint32_t *from = malloc((nh ? nh : 1) * sizeof *from), *to = malloc((nh ? nh : 1) * sizeof *to);
    uint8_t *used = calloc(nh ? nh : 1, 1);
    double *length = malloc((nh ? nh : 1) * sizeof *length);
    size_t *loop_of = malloc((nh ? nh : 1) * sizeof *loop_of), *stack = malloc((nh ? nh : 1) * sizeof *stack);
    uint32_t *at = calloc(lc->vertex_count ? lc->vertex_count : 1, sizeof *at); /* 1 + stack index of v's edge */
    size_t nb = 0, loops = 0;
    int result = -2;
    lc->filled_vertices = lc->vertex_count;
    lc->filled_triangles = lc->triangle_count;
    if (!pairs || !keys || !after || !from || !to || !used || !length || !loop_of || !stack || !at)
        goto done;
    result = -1;
    for (size_t h = 0; h < nh; h++) {
        const uint32_t *v = lc->triangle + h - h % 3;
        pairs[2 * h] = half_edge(v[h % 3], v[(h % 3 + 1) % 3]);
        pairs[2 * h + 1] = half_edge(v[(h % 3 + 1) % 3], v[(h % 3 + 2) % 3]);
    }
    qsort(pairs, nh, 2 * sizeof *pairs, texopt_compare_u64);
    for (size_t h = 0; h < nh; h++) {
        keys[h] = pairs[2 * h];
        after[h] = pairs[2 * h + 1];
    }
    for (size_t h = 0; h < nh; h++) {
        uint32_t a = (uint32_t)(keys[h] >> 32), b = (uint32_t)keys[h];
        if (!has_half_edge(keys, nh, half_edge(b, a))) {
            from[nb] = a;
            to[nb++] = b;
        }
    }
    /* Loops: each boundary half-edge is followed by the one its rotation reaches; a loop
     * through a vertex twice (a pinch) is split there into simple loops. */
    for (size_t e = 0; e < nb; e++) {
        size_t top = 0;
        for (size_t f = e; !used[f];) {
            used[f] = 1;
            stack[top++] = f;
            at[from[f]] = (uint32_t)top;
            if (at[to[f]]) { /* a simple loop closes at to[f]: stack[at - 1 .. top) */
                size_t first = at[to[f]] - 1;
                length[loops] = 0;
                for (size_t i = first; i < top; i++) {
                    loop_of[stack[i]] = loops;
                    at[from[stack[i]]] = 0;
                    length[loops] += texopt_distance3(lc->position + 3 * (size_t)from[stack[i]],
                                                      lc->position + 3 * (size_t)to[stack[i]]);
                }
                loops++;
                top = first;
            }
            uint32_t c = next_boundary_vertex(keys, after, nh, from[f], to[f]);
            size_t g = 0;
            while (g < nb && !(from[g] == to[f] && to[g] == c))
                g++;
            if (g == nb)
                goto done;
            f = g;
        }
        if (top != 0)
            goto done;
    }
    result = loops > 1;
    size_t outer = 0;
    for (size_t k = 1; k < loops; k++)
        if (length[k] > length[outer])
            outer = k;
    for (size_t k = 0; k < loops && result == 1; k++) {
        if (k == outer)
            continue;
        size_t w = lc->filled_vertices++, count = 0;
        double *centre = lc->position + 3 * w;
        centre[0] = centre[1] = centre[2] = 0;
        for (size_t e = 0; e < nb; e++)
            if (loop_of[e] == k) {
                for (int a = 0; a < 3; a++)
                    centre[a] += lc->position[3 * (size_t)from[e] + (size_t)a];
                count++;
                uint32_t *t = lc->triangle + 3 * lc->filled_triangles++;
                t[0] = to[e];
                t[1] = from[e];
                t[2] = (uint32_t)w;
            }
        for (int a = 0; a < 3; a++)
            centre[a] /= (double)count;
    }
done:
    free(pairs);
    free(keys);
    free(after);
    free(from);
    free(to);
    free(used);
    free(length);
    free(loop_of);
    free(stack);
    free(at);
    return result;
}

/* The chart's layout by linear ABF, by Tutte when ABF's fails, flips or crosses itself. */
static texopt_status disk_layout(const texopt_param_chart *chart, const texopt_param_boundary *b, double *uv,
                                 int *by_tutte)
{
    char err[256];
    texopt_status st = texopt_param_abf(chart, uv, NULL, err, sizeof err);
    *by_tutte = st == TEXOPT_E_NOMEM ? 0
                : st != TEXOPT_OK    ? 1
                                     : texopt_param_flips(chart, uv) > 0 || texopt_param_boundary_crosses(b, uv);
    return *by_tutte ? texopt_param_tutte(chart, uv, err, sizeof err) : st;
}

/* uv (counter-clockwise, any scale) placed in the input's frame as chart c: mirrored to the
 * chart's sign, scaled to texel area `area`, turned and moved by the rigid least-squares fit
 * to the input positions. */
static void place_like_input(const texopt_mesh *mesh, uint32_t c, double area, local_chart *lc, double *texel_out)
{
    size_t n = lc->vertex_count;
    double mirror = mesh->chart_sign[c] < 0 ? -1.0 : 1.0, have = 0, pc[2] = {0, 0}, qc[2] = {0, 0};
    for (size_t i = 0; i < n; i++)
        lc->uv[2 * i + 1] *= mirror;
    for (size_t t = 0; t < lc->triangle_count; t++) {
        const double *a = lc->uv + 2 * (size_t)lc->triangle[3 * t], *b = lc->uv + 2 * (size_t)lc->triangle[3 * t + 1],
                     *p = lc->uv + 2 * (size_t)lc->triangle[3 * t + 2];
        have += 0.5 * fabs((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
    }
    double s = sqrt(area / have);
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 2; a++) {
            lc->uv[2 * i + (size_t)a] *= s;
            pc[a] += lc->uv[2 * i + (size_t)a] / (double)n;
            qc[a] += mesh->texel[2 * (size_t)lc->vertex[i] + (size_t)a] / (double)n;
        }
    double dot = 0, cross = 0;
    for (size_t i = 0; i < n; i++) {
        const double *q = mesh->texel + 2 * (size_t)lc->vertex[i];
        double px = lc->uv[2 * i] - pc[0], py = lc->uv[2 * i + 1] - pc[1], qx = q[0] - qc[0], qy = q[1] - qc[1];
        dot += px * qx + py * qy;
        cross += px * qy - py * qx;
    }
    double turn = atan2(cross, dot), co = cos(turn), si = sin(turn);
    for (size_t i = 0; i < n; i++) {
        double px = lc->uv[2 * i] - pc[0], py = lc->uv[2 * i + 1] - pc[1];
        texel_out[2 * (size_t)lc->vertex[i]] = qc[0] + co * px - si * py;
        texel_out[2 * (size_t)lc->vertex[i] + 1] = qc[1] + si * px + co * py;
    }
}

/* Lays the part of chart c (gather_chart) out anew into texel_out; *laid 0 when it is no
 * disk (or has no texel area). */
static texopt_status unfold_part(const texopt_mesh *mesh, uint32_t c, const uint32_t *part_of, uint32_t part,
                                 local_chart *lc, double *texel_out, int *laid, int *by_tutte)
{
    double area = gather_chart(mesh, c, part_of, part, lc);
    int filled = area > 0 ? fill_holes(lc) : -1;
    texopt_param_chart chart = {lc->filled_vertices, lc->position, lc->filled_triangles, lc->triangle};
    texopt_param_boundary *b = NULL;
    char err[256];
    texopt_status st = filled == -2 ? TEXOPT_E_NOMEM
                       : filled < 0 ? TEXOPT_E_INVALID_ARGUMENT
                                    : texopt_param_boundary_create(&b, &chart, err, sizeof err);
    int tutte = 0;
    if (st == TEXOPT_OK && filled) { /* the fans are no surface to keep angles of */
        tutte = 1;
        st = texopt_param_tutte(&chart, lc->uv, err, sizeof err);
    } else if (st == TEXOPT_OK)
        st = disk_layout(&chart, b, lc->uv, &tutte);
    texopt_param_boundary_destroy(b);
    *laid = st == TEXOPT_OK;
    *by_tutte |= tutte;
    if (*laid)
        place_like_input(mesh, c, area, lc, texel_out);
    for (size_t i = 0; i < lc->vertex_count; i++)
        lc->local_of[lc->vertex[i]] = UINT32_MAX;
    return st == TEXOPT_E_NOMEM ? st : TEXOPT_OK;
}

static uint32_t find_root(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* part_of[t] for chart c's triangles: its edge-connected part, numbered from 0; returns how
 * many. A chart's parts meet only at vertices (a strip of triangles joined corner to
 * corner). keys (6 per mesh triangle) is scratch. */
static uint32_t chart_parts(const texopt_mesh *mesh, uint32_t c, uint32_t *part_of, uint64_t *keys)
{
    size_t n = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        part_of[t] = (uint32_t)t;
        if (mesh->chart_of[t] == c)
            for (int k = 0; k < 3; k++) {
                uint32_t a = mesh->triangle[3 * t + (size_t)k], b = mesh->triangle[3 * t + (size_t)(k + 1) % 3];
                keys[2 * n] = texopt_edge_key(a, b);
                keys[2 * n++ + 1] = t;
            }
    }
    qsort(keys, n, 2 * sizeof *keys, texopt_compare_u64);
    for (size_t i = 1; i < n; i++)
        if (keys[2 * i] == keys[2 * i - 2])
            part_of[find_root(part_of, (uint32_t)keys[2 * i + 1])] = find_root(part_of, (uint32_t)keys[2 * i - 1]);
    uint32_t parts = 0; /* keys reused: [t] a root's part number, [nt + t] t's root */
    size_t nt = mesh->triangle_count;
    for (size_t t = 0; t < nt; t++)
        if (mesh->chart_of[t] == c) {
            keys[nt + t] = find_root(part_of, (uint32_t)t);
            if (keys[nt + t] == t)
                keys[t] = parts++;
        }
    for (size_t t = 0; t < nt; t++)
        if (mesh->chart_of[t] == c)
            part_of[t] = (uint32_t)keys[keys[nt + t]];
    return parts;
}

/* The chart's boundary edges (of one triangle) with their parts into keys, 2 each (edge
 * key, part); returns how many. */
static size_t part_boundaries(const texopt_mesh *mesh, uint32_t c, const uint32_t *part_of, uint64_t *keys)
{
    size_t n = 0, nb = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (mesh->chart_of[t] == c)
            for (int k = 0; k < 3; k++) {
                keys[2 * n] =
                    texopt_edge_key(mesh->triangle[3 * t + (size_t)k], mesh->triangle[3 * t + (size_t)(k + 1) % 3]);
                keys[2 * n++ + 1] = part_of[t];
            }
    qsort(keys, n, 2 * sizeof *keys, texopt_compare_u64);
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && keys[2 * j] == keys[2 * i])
            j++;
        if (j - i == 1) {
            keys[2 * nb] = keys[2 * i];
            keys[2 * nb++ + 1] = keys[2 * i + 1];
        }
        i = j;
    }
    return nb;
}

/* Whether a boundary edge of part `part` crosses one of the parts marked laid in done
 * (edges sharing a vertex do not count). */
static int part_crosses_laid(const uint64_t *edges, size_t nb, uint32_t part, const uint8_t *done, const double *x)
{
    for (size_t i = 0; i < nb; i++) {
        if (edges[2 * i + 1] != part)
            continue;
        uint32_t a = (uint32_t)(edges[2 * i] >> 32), b = (uint32_t)edges[2 * i];
        for (size_t j = 0; j < nb; j++) {
            uint32_t c = (uint32_t)(edges[2 * j] >> 32), d = (uint32_t)edges[2 * j];
            if (!done[edges[2 * j + 1]] || a == c || a == d || b == c || b == d)
                continue;
            const double *pa = x + 2 * (size_t)a, *pb = x + 2 * (size_t)b, *pc = x + 2 * (size_t)c,
                         *pd = x + 2 * (size_t)d;
            double d1 = texopt_signed_area(pa, pb, pc), d2 = texopt_signed_area(pa, pb, pd),
                   d3 = texopt_signed_area(pc, pd, pa), d4 = texopt_signed_area(pc, pd, pb);
            if (((d1 > 0) != (d2 > 0) || d1 == 0 || d2 == 0) && ((d3 > 0) != (d4 > 0) || d3 == 0 || d4 == 0))
                return 1;
        }
    }
    return 0;
}

/* A point of triangle t just off its corner `at` (1% of the way to its centroid). */
static void near_corner(const texopt_mesh *mesh, size_t t, uint32_t at, const double *x, double p[2])
{
    const uint32_t *v = mesh->triangle + 3 * t;
    for (int a = 0; a < 2; a++)
        p[a] = 0.99 * x[2 * (size_t)at + a] +
               0.01 / 3 * (x[2 * (size_t)v[0] + a] + x[2 * (size_t)v[1] + a] + x[2 * (size_t)v[2] + a]);
}

static int inside_triangle(const texopt_mesh *mesh, size_t t, const double *x, const double p[2])
{
    const uint32_t *v = mesh->triangle + 3 * t;
    const double *a = x + 2 * (size_t)v[0], *b = x + 2 * (size_t)v[1], *c = x + 2 * (size_t)v[2];
    double d0 = texopt_signed_area(a, b, p), d1 = texopt_signed_area(b, c, p), d2 = texopt_signed_area(c, a, p);
    return (d0 > 0 && d1 > 0 && d2 > 0) || (d0 < 0 && d1 < 0 && d2 < 0);
}

/* Whether triangle t's corners are all of the part being laid (marked 4 in placed, or the
 * shared vertex, 3) or all of the laid ones (1 or 3). */
static int triangle_of(const texopt_mesh *mesh, size_t t, const uint8_t *placed, int new_part)
{
    for (int k = 0; k < 3; k++) {
        uint8_t p = placed[mesh->triangle[3 * t + (size_t)k]];
        if (new_part ? !(p & 4) && p != 3 : p != 1 && p != 3)
            return 0;
    }
    return 1;
}

/* Whether the part being laid (its vertices marked 4 in placed, the laid parts' 1, the one
 * they share 3) lies in a laid part or one in it where no boundary crossing shows it: a
 * vertex of one in a triangle of the other, or, at the shared vertex, a point of one's
 * triangle just off it in the other's (a wedge inside a wedge). */
static int part_inside_laid(const texopt_mesh *mesh, uint32_t c, uint32_t at, const uint8_t *placed, const double *x)
{
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (mesh->chart_of[t] != c)
            continue;
        int is_new = triangle_of(mesh, t, placed, 1), is_laid = !is_new && triangle_of(mesh, t, placed, 0);
        if (!is_new && !is_laid)
            continue;
        for (size_t u = 0; u < mesh->triangle_count; u++) /* the chart's vertices, through its triangles */
            for (int k = 0; k < 3 && mesh->chart_of[u] == c; k++) {
                uint32_t v = mesh->triangle[3 * u + (size_t)k];
                if ((is_laid ? (placed[v] & 4) != 0 : placed[v] == 1) && inside_triangle(mesh, t, x, x + 2 * (size_t)v))
                    return 1;
            }
        const uint32_t *w = mesh->triangle + 3 * t;
        if (w[0] != at && w[1] != at && w[2] != at)
            continue;
        double p[2];
        near_corner(mesh, t, at, x, p);
        for (size_t u = 0; u < mesh->triangle_count; u++)
            if (mesh->chart_of[u] == c && triangle_of(mesh, u, placed, !is_new) && inside_triangle(mesh, u, x, p))
                return 1;
    }
    return 0;
}

/* Whether the part being laid crosses or lies in the laid ones (or they in it). */
static int part_clashes(const texopt_mesh *mesh, uint32_t c, uint32_t at, const uint8_t *placed, const uint64_t *edges,
                        size_t nb, uint32_t part, const uint8_t *done, const double *x)
{
    return part_crosses_laid(edges, nb, part, done, x) || part_inside_laid(mesh, c, at, placed, x);
}

/* Scales the vertices marked 4 in placed about `pivot` by `scale` and turns them by `angle`. */
static void scale_part(const uint8_t *placed, size_t nv, const double pivot[2], double scale, double angle, double *x)
{
    double co = scale * cos(angle), si = scale * sin(angle);
    for (size_t v = 0; v < nv; v++)
        if (placed[v] & 4) {
            double dx = x[2 * v] - pivot[0], dy = x[2 * v + 1] - pivot[1];
            x[2 * v] = pivot[0] + co * dx - si * dy;
            x[2 * v + 1] = pivot[1] + si * dx + co * dy;
        }
}

/* Turns (and shrinks) the part being laid about the vertex `at` it shares with the laid
 * ones until it clashes with none of them (part_clashes): turns of 0, +1, -1, +2, -2, ...
 * PART_TURN up to a half turn either way, then the same at half the size, up to
 * PART_SHRINKS times (stage 2 grows it back inside its scaffold). */
static void turn_part_clear(const texopt_mesh *mesh, uint32_t c, uint32_t at, const uint8_t *placed,
                            const uint64_t *edges, size_t nb, uint32_t part, const uint8_t *done, double *x)
{
    double pivot[2] = {x[2 * (size_t)at], x[2 * (size_t)at + 1]};
    for (int shrink = 0; shrink <= PART_SHRINKS; shrink++) {
        if (shrink)
            scale_part(placed, mesh->vertex_count, pivot, 0.5, PART_TURNS * PART_TURN, x); /* back to 0 */
        for (int k = 1; k <= 2 * PART_TURNS; k++) {
            if (!part_clashes(mesh, c, at, placed, edges, nb, part, done, x))
                return;
            scale_part(placed, mesh->vertex_count, pivot, 1.0, (k % 2 ? 1 : -1) * k * PART_TURN, x);
        }
    }
}

/* Lays chart c out anew into texel_out, part by part when its parts meet at vertices: each
 * part as a disk, placed like the input, then moved so that the vertex it shares with the
 * parts laid before it stays where they put it, turned (and shrunk) about that vertex until
 * it clashes with none of them (turn_part_clear; a part meeting them at more vertices than
 * one closes a loop no rigid move keeps: no disk). *laid 0 when it is no disk. */
static texopt_status unfold_chart(const texopt_mesh *mesh, uint32_t c, local_chart *lc, double *texel_out, int *laid,
                                  int *by_tutte)
{
    *by_tutte = 0;
    uint32_t parts = chart_parts(mesh, c, lc->part_of, lc->keys);
    if (parts <= 1)
        return unfold_part(mesh, c, NULL, 0, lc, texel_out, laid, by_tutte);
    memset(lc->placed, 0, mesh->vertex_count);
    uint64_t *edges = lc->keys + 2 * mesh->triangle_count * 3; /* after chart_parts' scratch */
    size_t nb = part_boundaries(mesh, c, lc->part_of, edges);
    uint8_t *done_part = calloc(parts, 1);
    texopt_status st = done_part ? TEXOPT_OK : TEXOPT_E_NOMEM;
    *laid = 1;
    for (uint32_t done = 0; done < parts && *laid && st == TEXOPT_OK; done++) {
        /* the next part: one meeting the laid ones at a vertex (the first part: any) */
        uint32_t next = UINT32_MAX, shared = UINT32_MAX;
        for (size_t t = 0; t < mesh->triangle_count && next == UINT32_MAX; t++) {
            if (mesh->chart_of[t] != c || lc->part_of[t] == UINT32_MAX)
                continue;
            for (int k = 0; k < 3 && next == UINT32_MAX; k++)
                if (done == 0 || lc->placed[mesh->triangle[3 * t + (size_t)k]]) {
                    next = lc->part_of[t];
                    shared = done == 0 ? UINT32_MAX : mesh->triangle[3 * t + (size_t)k];
                }
        }
        if (next == UINT32_MAX) { /* no part meets the laid ones: not one chart */
            *laid = 0;
            break;
        }
        double keep[2] = {0, 0};
        if (shared != UINT32_MAX)
            memcpy(keep, texel_out + 2 * (size_t)shared, sizeof keep);
        size_t meets = 0;
        for (size_t t = 0; t < mesh->triangle_count; t++)
            if (mesh->chart_of[t] == c && lc->part_of[t] == next)
                for (int k = 0; k < 3; k++) {
                    uint32_t v = mesh->triangle[3 * t + (size_t)k];
                    meets += lc->placed[v] == 1;
                    lc->placed[v] |= lc->placed[v] ? 2 : 4; /* counted once */
                }
        int part_laid = 0;
        if (meets > 1)
            *laid = 0;
        else
            st = unfold_part(mesh, c, lc->part_of, next, lc, texel_out, &part_laid, by_tutte);
        *laid &= part_laid;
        double shift[2] = {0, 0};
        if (shared != UINT32_MAX)
            for (int a = 0; a < 2; a++)
                shift[a] = keep[a] - texel_out[2 * (size_t)shared + (size_t)a];
        for (size_t t = 0; t < mesh->triangle_count; t++)
            if (mesh->chart_of[t] == c && lc->part_of[t] == next)
                lc->part_of[t] = UINT32_MAX; /* laid */
        for (size_t v = 0; v < mesh->vertex_count; v++)
            if (lc->placed[v] & 4) {
                texel_out[2 * v] += shift[0];
                texel_out[2 * v + 1] += shift[1];
            }
        if (shared != UINT32_MAX) {
            memcpy(texel_out + 2 * (size_t)shared, keep, sizeof keep);
            turn_part_clear(mesh, c, shared, lc->placed, edges, nb, next, done_part, texel_out);
        }
        done_part[next] = 1;
        for (size_t v = 0; v < mesh->vertex_count; v++)
            if (lc->placed[v])
                lc->placed[v] = 1;
    }
    free(done_part);
    if (!*laid) /* parts laid before the one that failed go back */
        for (size_t t = 0; t < mesh->triangle_count; t++)
            if (mesh->chart_of[t] == c)
                for (int k = 0; k < 3; k++) {
                    size_t v = mesh->triangle[3 * t + (size_t)k];
                    memcpy(texel_out + 2 * v, mesh->texel + 2 * v, 2 * sizeof *texel_out);
                }
    return st;
}

static void local_chart_free(local_chart *lc)
{
    free(lc->local_of);
    free(lc->vertex);
    free(lc->position);
    free(lc->triangle);
    free(lc->uv);
    free(lc->part_of);
    free(lc->keys);
    free(lc->placed);
}

texopt_status texopt_unfold_charts(const texopt_mesh *mesh, const uint8_t *keep, double *texel_out, uint8_t *unfolded,
                                   texopt_unfold_report *report, char *err, size_t err_len)
{
    if (!mesh || !texel_out || !report || !mesh->texel || (mesh->triangle_count && !mesh->chart_sign))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unfold: NULL mesh, output or report");
    memset(report, 0, sizeof *report);
    memcpy(texel_out, mesh->texel, 2 * mesh->vertex_count * sizeof *texel_out);
    size_t nv = mesh->vertex_count ? mesh->vertex_count : 1, nt = mesh->triangle_count ? mesh->triangle_count : 1;
    uint8_t *over = malloc(mesh->chart_count ? mesh->chart_count : 1);
    /* room for the fans (fill_holes): a vertex and a triangle per boundary edge at most */
    local_chart lc = {0};
    lc.local_of = malloc(nv * sizeof *lc.local_of);
    lc.vertex = malloc(nv * sizeof *lc.vertex);
    lc.position = malloc(3 * (nv + 3 * nt) * sizeof *lc.position);
    lc.triangle = malloc(12 * nt * sizeof *lc.triangle);
    lc.uv = malloc(2 * (nv + 3 * nt) * sizeof *lc.uv);
    lc.part_of = malloc(nt * sizeof *lc.part_of);
    lc.keys = malloc(12 * nt * sizeof *lc.keys);
    lc.placed = malloc(nv);
    texopt_status st =
        over && lc.local_of && lc.vertex && lc.position && lc.triangle && lc.uv && lc.part_of && lc.keys && lc.placed
            ? TEXOPT_OK
            : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "unfold: out of memory");
    if (st == TEXOPT_OK)
        st = texopt_scaffold_overlapping_charts(mesh, mesh->texel, over, &report->overlapping, err, err_len);
    if (st == TEXOPT_OK && unfolded)
        memset(unfolded, 0, mesh->chart_count);
    /* A mirror whose halves only lie on one another keeps its sharing; an extent too large
     * to raster is taken for one (twice NULL). */
    size_t *twice = st == TEXOPT_OK && report->overlapping ? malloc(mesh->chart_count * sizeof *twice) : NULL;
    if (st == TEXOPT_OK && report->overlapping && !twice)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "unfold: out of memory");
    if (twice && texopt_count_overlap_per_chart(mesh, mesh->texel, twice, err, err_len) != TEXOPT_OK) {
        free(twice);
        twice = NULL;
    }
    for (size_t v = 0; st == TEXOPT_OK && v < mesh->vertex_count; v++)
        lc.local_of[v] = UINT32_MAX;
    for (uint32_t c = 0; st == TEXOPT_OK && c < mesh->chart_count; c++) {
        int laid = 0, by_tutte = 0;
        if (!over[c])
            continue;
        if (keep && keep[c])
            report->kept++;
        else if (chart_is_mirrored(mesh, c) && (!twice || twice[c] == 0))
            report->mirrored++;
        else if ((st = unfold_chart(mesh, c, &lc, texel_out, &laid, &by_tutte)) == TEXOPT_OK) {
            report->unfolded += laid;
            report->tutte += laid && by_tutte;
            report->not_disks += !laid;
            if (unfolded)
                unfolded[c] = (uint8_t)laid;
        } else
            texopt_fail(err, err_len, st, "unfold: out of memory");
    }
    free(over);
    free(twice);
    local_chart_free(&lc);
    return st;
}

/* Per vertex, the index of its tie in share->ties, UINT32_MAX for none; NULL on no memory. */
static uint32_t *tie_of_vertex(const texopt_mesh *mesh, const texopt_texel_share *share)
{
    uint32_t *tie = malloc((mesh->vertex_count ? mesh->vertex_count : 1) * sizeof *tie);
    for (size_t v = 0; tie && v < mesh->vertex_count; v++)
        tie[v] = UINT32_MAX;
    for (size_t k = 0; tie && k < share->tie_count; k++)
        if (share->ties[k].vertex < mesh->vertex_count)
            tie[share->ties[k].vertex] = (uint32_t)k;
    return tie;
}

/* Per chart, 1 for the charts texopt_unfold_charts must leave alone: every secondary, and
 * the primary of a group with an untied secondary vertex. */
static void mark_kept_groups(const texopt_mesh *mesh, const texopt_texel_share *share, const uint32_t *tie,
                             uint8_t *keep)
{
    memset(keep, 0, mesh->chart_count);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint32_t c = mesh->chart_of[t], p = share->primary_of[c];
        if (p == c)
            continue;
        keep[c] = 1;
        for (int k = 0; k < 3; k++)
            if (tie[mesh->triangle[3 * t + (size_t)k]] == UINT32_MAX)
                keep[p] = 1;
    }
}

/* Per primary, 1 when its secondaries are to be laid on its layout: it was laid out anew,
 * or it starts without overlap and one of them does not. */
static void mark_followed_groups(const texopt_mesh *mesh, const texopt_texel_share *share, const uint8_t *keep,
                                 const uint8_t *unfolded, const uint8_t *over, uint8_t *follow)
{
    memset(follow, 0, mesh->chart_count);
    for (uint32_t c = 0; c < mesh->chart_count; c++) {
        uint32_t p = share->primary_of[c];
        if (p != c && !keep[p] && (unfolded[p] || (!over[p] && over[c])))
            follow[p] = 1;
    }
}

/* Puts every vertex of the secondaries of the primaries marked in follow on its tie's
 * point of texel_out. */
static void lay_on_primaries(const texopt_mesh *mesh, const texopt_texel_share *share, const uint32_t *tie,
                             const uint8_t *follow, double *texel_out)
{
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint32_t c = mesh->chart_of[t], p = share->primary_of[c];
        if (p == c || !follow[p])
            continue;
        for (int k = 0; k < 3; k++) {
            const texopt_texel_tie *tt = &share->ties[tie[mesh->triangle[3 * t + (size_t)k]]];
            for (int a = 0; a < 2; a++) {
                double x = 0;
                for (int j = 0; j < 3; j++)
                    x += tt->weight[j] * texel_out[2 * (size_t)tt->corner[j] + (size_t)a];
                texel_out[2 * (size_t)tt->vertex + (size_t)a] = x;
            }
        }
    }
}

/* Marks in keep the primaries of followed groups some chart of which still overlaps
 * itself in texel (ties where the primary overlapped itself can be ambiguous); returns how
 * many. */
static size_t keep_groups_still_overlapping(const texopt_mesh *mesh, const texopt_texel_share *share,
                                            const uint8_t *follow, const uint8_t *over_now, uint8_t *keep)
{
    size_t n = 0;
    for (uint32_t c = 0; c < mesh->chart_count; c++) {
        uint32_t p = share->primary_of[c];
        if (follow[p] && over_now[c] && !keep[p]) {
            keep[p] = 1;
            n++;
        }
    }
    return n;
}

/* Releases from its group (texel_share.h) each secondary of a followed group that overlaps
 * itself after the pass where it did in the input and its primary no longer does: it covers
 * texels twice on its own, so it cannot lie on the primary without overlap; the next pass
 * lays it out on its own. *released counts them. */
static texopt_status release_overlapping_secondaries(const texopt_mesh *mesh, texopt_texel_share *share,
                                                     const uint8_t *follow, const uint8_t *over_in,
                                                     const uint8_t *over_now, size_t *released, char *err,
                                                     size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    *released = 0;
    for (uint32_t c = 0; c < mesh->chart_count && st == TEXOPT_OK; c++) {
        uint32_t p = share->primary_of[c];
        if (p != c && follow[p] && over_now[c] && over_in[c] && !over_now[p]) {
            st = texopt_texel_share_release(share, mesh, c, err, err_len);
            ++*released;
        }
    }
    return st;
}

/* One pass: the charts not kept unfolded, the followed groups' secondaries laid on their
 * primaries; over_now receives the charts that overlap themselves after it. */
static texopt_status unfold_pass(const texopt_mesh *mesh, const texopt_texel_share *share, const uint32_t *tie,
                                 const uint8_t *keep, const uint8_t *over_in, uint8_t *unfolded, uint8_t *follow,
                                 uint8_t *over_now, double *texel_out, texopt_unfold_report *report, char *err,
                                 size_t err_len)
{
    texopt_status st = texopt_unfold_charts(mesh, keep, texel_out, unfolded, report, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    mark_followed_groups(mesh, share, keep, unfolded, over_in, follow);
    lay_on_primaries(mesh, share, tie, follow, texel_out);
    for (uint32_t c = 0; c < mesh->chart_count; c++) {
        uint32_t p = share->primary_of[c];
        if (p != c && follow[p]) {
            report->followed++;
            report->kept -= over_in[c] != 0; /* texopt_unfold_charts counted it */
        }
    }
    return texopt_scaffold_overlapping_charts(mesh, texel_out, over_now, NULL, err, err_len);
}

texopt_status texopt_unfold_groups(const texopt_mesh *mesh, texopt_texel_share *share, double *texel_out,
                                   texopt_unfold_report *report, char *err, size_t err_len)
{
    if (!share || share->secondary_count == 0)
        return texopt_unfold_charts(mesh, NULL, texel_out, NULL, report, err, err_len);
    if (!mesh || share->chart_count != mesh->chart_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unfold: sharing groups of another mesh");
    size_t nc = mesh->chart_count ? mesh->chart_count : 1;
    uint32_t *tie = tie_of_vertex(mesh, share);
    uint8_t *keep = malloc(nc), *unfolded = malloc(nc), *over_in = malloc(nc), *follow = malloc(nc);
    uint8_t *over_now = malloc(nc);
    texopt_status st = tie && keep && unfolded && over_in && follow && over_now
                           ? TEXOPT_OK
                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "unfold: out of memory for sharing groups");
    if (st == TEXOPT_OK) {
        mark_kept_groups(mesh, share, tie, keep);
        st = texopt_scaffold_overlapping_charts(mesh, mesh->texel, over_in, NULL, err, err_len);
    }
    if (st == TEXOPT_OK)
        st = unfold_pass(mesh, share, tie, keep, over_in, unfolded, follow, over_now, texel_out, report, err, err_len);
    size_t released = 0;
    if (st == TEXOPT_OK)
        st = release_overlapping_secondaries(mesh, share, follow, over_in, over_now, &released, err, err_len);
    if (st == TEXOPT_OK && released > 0) {
        free(tie);
        if (!(tie = tie_of_vertex(mesh, share)))
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "unfold: out of memory for sharing groups");
        else
            mark_kept_groups(mesh, share, tie, keep);
    }
    /* A group laid out as one that still overlaps is left alone whole, as before. */
    if (st == TEXOPT_OK && (keep_groups_still_overlapping(mesh, share, follow, over_now, keep) > 0 || released > 0))
        st = unfold_pass(mesh, share, tie, keep, over_in, unfolded, follow, over_now, texel_out, report, err, err_len);
    free(tie);
    free(keep);
    free(unfolded);
    free(over_in);
    free(follow);
    free(over_now);
    return st;
}
