/* param_chart.c - disk check, boundary loop and stretch of a chart layout (param_chart.h). */
#include "param_chart.h"

#include <math.h>
#include <stdlib.h>

#include "distortion.h"
#include "sort_keys.h"
#include "vec2.h"
#include "vec3.h"

static const double *point(const texopt_param_chart *chart, uint32_t v)
{
    return chart->position + 3 * (size_t)v;
}

void texopt_param_edge_lengths(const texopt_param_chart *chart, size_t t, double length[3])
{
    const uint32_t *v = chart->triangle + 3 * t;
    for (int k = 0; k < 3; k++)
        length[k] = texopt_distance3(point(chart, v[(k + 1) % 3]), point(chart, v[(k + 2) % 3]));
}

void texopt_param_corner_angles(const texopt_param_chart *chart, size_t t, double angle[3])
{
    const uint32_t *v = chart->triangle + 3 * t;
    for (int k = 0; k < 3; k++) {
        const double *a = point(chart, v[k]), *b = point(chart, v[(k + 1) % 3]), *c = point(chart, v[(k + 2) % 3]);
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        /* atan2 of |cross| and dot stays accurate for angles near 0 and pi. */
        angle[k] = atan2(sqrt(cx * cx + cy * cy + cz * cz), e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]);
    }
}

texopt_status texopt_param_boundary_edges(const uint32_t *triangle, size_t triangle_count, uint32_t **edge,
                                          size_t *count, char *err, size_t err_len)
{
    size_t ne = 3 * triangle_count;
    uint64_t *keys = malloc((ne ? ne : 1) * sizeof *keys);
    *edge = malloc(2 * (ne ? ne : 1) * sizeof **edge);
    *count = 0;
    if (!keys || !*edge) {
        free(keys);
        free(*edge);
        *edge = NULL;
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "boundary edges: out of memory");
    }
    for (size_t e = 0; e < ne; e++)
        keys[e] = texopt_edge_key(triangle[e], triangle[e - e % 3 + (e % 3 + 1) % 3]);
    qsort(keys, ne, sizeof *keys, texopt_compare_u64);
    for (size_t e = 0; e < ne; e++) {
        uint32_t a = triangle[e], b = triangle[e - e % 3 + (e % 3 + 1) % 3];
        uint64_t k = texopt_edge_key(a, b);
        const uint64_t *hit = bsearch(&k, keys, ne, sizeof *keys, texopt_compare_u64);
        int shared = (hit > keys && hit[-1] == k) || (hit + 1 < keys + ne && hit[1] == k);
        if (!shared) {
            (*edge)[2 * *count] = a;
            (*edge)[2 * (*count)++ + 1] = b;
        }
    }
    free(keys);
    return TEXOPT_OK;
}

void texopt_param_boundary_destroy(texopt_param_boundary *boundary)
{
    if (!boundary)
        return;
    free(boundary->vertex);
    free(boundary->arc);
    free(boundary->on_boundary);
    free(boundary);
}

static texopt_status check_triangles(const texopt_param_chart *chart, char *err, size_t err_len)
{
    if (!chart || !chart->position || !chart->triangle || chart->triangle_count == 0 || chart->vertex_count < 3 ||
        chart->vertex_count > UINT32_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "chart: empty or NULL");
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        for (int k = 0; k < 3; k++)
            if (v[k] >= chart->vertex_count)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "chart: triangle %zu uses vertex %u of %zu",
                                   t, v[k], chart->vertex_count);
        double angle[3];
        texopt_param_corner_angles(chart, t, angle);
        if (!(angle[0] > 0 && angle[1] > 0 && angle[2] > 0))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "chart: triangle %zu has no area (or a non-finite position)", t);
    }
    return TEXOPT_OK;
}

/* Orders the boundary half-edges (those without a twin) into one loop through next[]. */
static texopt_status walk_loop(texopt_param_boundary *b, const uint32_t *next, size_t boundary_edges, uint32_t start,
                               size_t vertex_count, char *err, size_t err_len)
{
    b->vertex = malloc((boundary_edges ? boundary_edges : 1) * sizeof *b->vertex);
    if (!b->vertex)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart: out of memory");
    uint32_t v = start;
    size_t n = 0;
    do {
        if (n == boundary_edges || v >= vertex_count)
            break;
        b->vertex[n++] = v;
        v = next[v];
    } while (v != start);
    if (n != boundary_edges || v != start)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "chart: the boundary is not one loop (holes or a pinched vertex); not a disk");
    b->count = n;
    return TEXOPT_OK;
}

/* The boundary of a chart whose half-edges are all distinct (nh of them): the edges used
 * by one triangle, walked into one loop from its smallest vertex. */
static texopt_status find_boundary(texopt_param_boundary *b, const texopt_param_chart *chart, size_t nh, char *err,
                                   size_t err_len)
{
    size_t nv = chart->vertex_count, boundary_edges = 0;
    uint32_t *next = malloc(nv * sizeof *next), *edge = NULL;
    b->on_boundary = calloc(nv, 1);
    texopt_status st = TEXOPT_OK;
    if (!next || !b->on_boundary)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart: out of memory");
    if (st == TEXOPT_OK)
        st = texopt_param_boundary_edges(chart->triangle, chart->triangle_count, &edge, &boundary_edges, err, err_len);
    for (size_t v = 0; v < nv && st == TEXOPT_OK; v++)
        next[v] = UINT32_MAX;
    uint32_t start = UINT32_MAX;
    for (size_t e = 0; e < boundary_edges && st == TEXOPT_OK; e++) {
        uint32_t from = edge[2 * e], to = edge[2 * e + 1];
        if (next[from] != UINT32_MAX)
            st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                             "chart: vertex %u is on the boundary twice; not a disk", from);
        next[from] = to;
        b->on_boundary[from] = 1;
        if (from < start)
            start = from;
    }
    free(edge);
    if (st == TEXOPT_OK && boundary_edges == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "chart: closed surface, no boundary; not a disk");
    if (st == TEXOPT_OK)
        st = walk_loop(b, next, boundary_edges, start, nv, err, err_len);
    free(next);
    if (st == TEXOPT_OK) {
        /* Euler characteristic V - E + F = 1 for a disk; E counts each edge once. */
        size_t edges = (nh + boundary_edges) / 2;
        if ((long long)nv - (long long)edges + (long long)chart->triangle_count != 1)
            st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                             "chart: Euler characteristic %lld, not a disk (handles or holes)",
                             (long long)nv - (long long)edges + (long long)chart->triangle_count);
    }
    return st;
}

static texopt_status measure_arcs(texopt_param_boundary *b, const texopt_param_chart *chart, char *err, size_t err_len)
{
    b->arc = malloc((b->count + 1) * sizeof *b->arc);
    if (!b->arc)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart: out of memory");
    b->arc[0] = 0.0;
    for (size_t i = 0; i < b->count; i++)
        b->arc[i + 1] =
            b->arc[i] + texopt_distance3(point(chart, b->vertex[i]), point(chart, b->vertex[(i + 1) % b->count]));
    return TEXOPT_OK;
}

static texopt_status check_used(const texopt_param_chart *chart, char *err, size_t err_len)
{
    uint8_t *used = calloc(chart->vertex_count, 1);
    if (!used)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart: out of memory");
    for (size_t i = 0; i < 3 * chart->triangle_count; i++)
        used[chart->triangle[i]] = 1;
    size_t unused = chart->vertex_count;
    for (size_t v = 0; v < chart->vertex_count && unused == chart->vertex_count; v++)
        if (!used[v])
            unused = v;
    free(used);
    if (unused != chart->vertex_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "chart: vertex %zu is in no triangle", unused);
    return TEXOPT_OK;
}

texopt_status texopt_param_boundary_create(texopt_param_boundary **out, const texopt_param_chart *chart, char *err,
                                           size_t err_len)
{
    *out = NULL;
    texopt_status st = check_triangles(chart, err, err_len);
    if (st == TEXOPT_OK)
        st = check_used(chart, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t nh = 3 * chart->triangle_count;
    uint64_t *half = malloc(nh * sizeof *half);
    texopt_param_boundary *b = calloc(1, sizeof *b);
    if (!half || !b) {
        free(half);
        free(b);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "chart: out of memory");
    }
    for (size_t t = 0; t < chart->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            half[3 * t + k] = ((uint64_t)chart->triangle[3 * t + k] << 32) | chart->triangle[3 * t + (k + 1) % 3];
    qsort(half, nh, sizeof *half, texopt_compare_u64);
    for (size_t h = 1; h < nh && st == TEXOPT_OK; h++)
        if (half[h] == half[h - 1])
            st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                             "chart: edge %u-%u is used twice in one direction (non-manifold or "
                             "inconsistently oriented)",
                             (unsigned)(half[h] >> 32), (unsigned)(uint32_t)half[h]);
    if (st == TEXOPT_OK)
        st = find_boundary(b, chart, nh, err, err_len);
    if (st == TEXOPT_OK)
        st = measure_arcs(b, chart, err, err_len);
    free(half);
    if (st != TEXOPT_OK) {
        texopt_param_boundary_destroy(b);
        return st;
    }
    *out = b;
    return TEXOPT_OK;
}

int texopt_param_stretch(const texopt_param_chart *chart, const double *uv, double *l2, double *linf,
                         double *per_vertex_l2)
{
    double area_3d = 0.0, area_uv = 0.0;
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        double P[2][2];
        texopt_plane_edges(point(chart, v[0]), point(chart, v[1]), point(chart, v[2]), P);
        area_3d += 0.5 * P[0][0] * P[1][1];
        const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *c = uv + 2 * (size_t)v[2];
        area_uv += fabs(texopt_signed_area(a, b, c));
    }
    if (!(area_uv > 0.0) || !(area_3d > 0.0))
        return -1;
    double scale = sqrt(area_3d / area_uv), sum = 0.0, worst = 0.0;
    double *vertex_area = NULL;
    if (per_vertex_l2) {
        vertex_area = calloc(chart->vertex_count, sizeof *vertex_area);
        if (!vertex_area)
            return -1;
        for (size_t v = 0; v < chart->vertex_count; v++)
            per_vertex_l2[v] = 0.0;
    }
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        double P[2][2], T[2][2], J[2][2];
        texopt_plane_edges(point(chart, v[0]), point(chart, v[1]), point(chart, v[2]), P);
        texopt_layout_edges(uv, v, T);
        texopt_jacobian(T, P, scale, J);
        texopt_triangle_distortion d;
        texopt_triangle_distortion_of(J, &d);
        double a = 0.5 * P[0][0] * P[1][1];
        sum += a * d.l2_stretch * d.l2_stretch;
        worst = fmax(worst, d.linf_stretch);
        if (per_vertex_l2)
            for (int k = 0; k < 3; k++) {
                per_vertex_l2[v[k]] += a * d.l2_stretch * d.l2_stretch;
                vertex_area[v[k]] += a;
            }
    }
    if (per_vertex_l2) {
        for (size_t v = 0; v < chart->vertex_count; v++)
            per_vertex_l2[v] = vertex_area[v] > 0 ? sqrt(per_vertex_l2[v] / vertex_area[v]) : 1.0;
        free(vertex_area);
    }
    *l2 = sqrt(sum / area_3d);
    *linf = worst;
    return 0;
}

texopt_status texopt_param_add_layout_row(texopt_spd *spd, const int64_t *var, const double *uv, const uint32_t *vertex,
                                          const int *axis, const double *coef, int n)
{
    uint32_t cols[8];
    double a[8], rhs = 0.0;
    int count = 0;
    for (int k = 0; k < n && k < 8; k++) {
        if (var[vertex[k]] < 0) {
            rhs -= coef[k] * uv[2 * (size_t)vertex[k] + (size_t)axis[k]];
        } else {
            cols[count] = (uint32_t)(2 * var[vertex[k]] + axis[k]);
            a[count++] = coef[k];
        }
    }
    return count > 0 ? texopt_spd_add_row(spd, cols, a, count, &rhs, 1.0) : TEXOPT_OK;
}

texopt_status texopt_param_solve_pinned(const texopt_param_chart *chart, const uint32_t pin[2],
                                        texopt_param_rows_fn add_rows, const void *context, double *uv, char *err,
                                        size_t err_len)
{
    size_t nv = chart->vertex_count, free_count = 0;
    int64_t *var = malloc(nv * sizeof *var);
    double *x = malloc(2 * nv * sizeof *x);
    texopt_spd *spd = NULL;
    texopt_status st = TEXOPT_OK;
    if (!var || !x)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "layout solve: out of memory");
    for (size_t v = 0; v < nv && st == TEXOPT_OK; v++)
        var[v] = (v == pin[0] || v == pin[1]) ? -1 : (int64_t)free_count++;
    if (st == TEXOPT_OK) {
        uv[2 * (size_t)pin[0]] = uv[2 * (size_t)pin[0] + 1] = uv[2 * (size_t)pin[1] + 1] = 0.0;
        uv[2 * (size_t)pin[1]] = texopt_distance3(point(chart, pin[0]), point(chart, pin[1]));
        if (free_count > 0)
            st = texopt_spd_create(&spd, 2 * free_count, 1, err, err_len);
    }
    for (size_t t = 0; t < chart->triangle_count && st == TEXOPT_OK && spd; t++)
        if ((st = add_rows(spd, context, t, var, uv)) != TEXOPT_OK)
            st = texopt_fail(err, err_len, st, "layout solve: cannot assemble the system");
    if (st == TEXOPT_OK && spd)
        st = texopt_spd_solve(spd, x, err, err_len);
    for (size_t v = 0; v < nv && st == TEXOPT_OK; v++)
        if (var[v] >= 0) {
            uv[2 * v] = x[2 * var[v]];
            uv[2 * v + 1] = x[2 * var[v] + 1];
        }
    texopt_spd_destroy(spd);
    free(var);
    free(x);
    return st;
}

size_t texopt_param_flips(const texopt_param_chart *chart, const double *uv)
{
    size_t flips = 0;
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *p = uv + 2 * (size_t)v[2];
        flips += !((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) > 0.0);
    }
    return flips;
}

/* Whether segments pq and rs cross (touching at an end point does not count). */
static int segments_cross(const double *p, const double *q, const double *r, const double *s)
{
    double d1 = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    double d2 = (q[0] - p[0]) * (s[1] - p[1]) - (q[1] - p[1]) * (s[0] - p[0]);
    double d3 = (s[0] - r[0]) * (p[1] - r[1]) - (s[1] - r[1]) * (p[0] - r[0]);
    double d4 = (s[0] - r[0]) * (q[1] - r[1]) - (s[1] - r[1]) * (q[0] - r[0]);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

int texopt_param_boundary_crosses(const texopt_param_boundary *b, const double *uv)
{
    size_t n = b->count;
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1)
                continue; /* adjacent through the loop's start */
            const double *p = uv + 2 * b->vertex[i], *q = uv + 2 * b->vertex[(i + 1) % n];
            const double *r = uv + 2 * b->vertex[j], *s = uv + 2 * b->vertex[(j + 1) % n];
            if (segments_cross(p, q, r, s))
                return 1;
        }
    return 0;
}
