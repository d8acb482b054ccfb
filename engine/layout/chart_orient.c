/* chart_orient.c - smallest bounding rectangle per chart by rotating calipers over its
 * convex hull, and the rigid turn that makes it axis-aligned (see chart_orient.h). */
#include "chart_orient.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A turn must shrink the chart's axis-aligned box by more than this share to be made:
 * below it the packing gains nothing measurable and the texture would still be resampled
 * at an angle. */
#define KEEP_MARGIN 0.01

typedef struct point {
    double x, y;
} point;

typedef struct chart_vertices {
    uint32_t *start; /* chart_count + 1 offsets into vertex */
    uint32_t *vertex;
} chart_vertices;

static void chart_vertices_destroy(chart_vertices *cv)
{
    free(cv->start);
    free(cv->vertex);
}

/* The vertices of each chart, each once (a vertex belongs to one chart: charts are the
 * components through shared UV vertices). */
static texopt_status group_vertices(const texopt_mesh *mesh, chart_vertices *cv, char *err, size_t err_len)
{
    size_t nv = mesh->vertex_count, nc = mesh->chart_count;
    uint32_t *chart_of_vertex = malloc(sizeof(uint32_t) * (nv ? nv : 1));
    cv->start = calloc(nc + 1, sizeof(uint32_t));
    cv->vertex = malloc(sizeof(uint32_t) * (nv ? nv : 1));
    if (!chart_of_vertex || !cv->start || !cv->vertex) {
        free(chart_of_vertex);
        chart_vertices_destroy(cv);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to group chart vertices");
    }
    for (size_t v = 0; v < nv; v++)
        chart_of_vertex[v] = UINT32_MAX;
    texopt_status st = TEXOPT_OK;
    for (size_t t = 0; t < mesh->triangle_count && st == TEXOPT_OK; t++) {
        uint32_t c = mesh->chart_of[t];
        if (c >= nc)
            st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "triangle %zu: chart %u out of range", t, c);
        for (int j = 0; j < 3 && st == TEXOPT_OK; j++)
            chart_of_vertex[mesh->triangle[3 * t + j]] = c;
    }
    for (size_t v = 0; v < nv && st == TEXOPT_OK; v++)
        if (chart_of_vertex[v] != UINT32_MAX)
            cv->start[chart_of_vertex[v] + 1]++;
    for (size_t c = 0; c < nc; c++)
        cv->start[c + 1] += cv->start[c];
    uint32_t *fill = malloc(sizeof(uint32_t) * (nc ? nc : 1));
    if (st == TEXOPT_OK && !fill)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to group chart vertices");
    if (st == TEXOPT_OK) {
        memcpy(fill, cv->start, sizeof(uint32_t) * nc);
        for (size_t v = 0; v < nv; v++)
            if (chart_of_vertex[v] != UINT32_MAX)
                cv->vertex[fill[chart_of_vertex[v]]++] = (uint32_t)v;
    }
    free(fill);
    free(chart_of_vertex);
    if (st != TEXOPT_OK)
        chart_vertices_destroy(cv);
    return st;
}

static int compare_points(const void *a, const void *b)
{
    const point *p = a, *q = b;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    return p->y < q->y ? -1 : (p->y > q->y);
}

static double cross(point o, point a, point b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/* Convex hull of pts[0..n) (sorted in place) into hull, counter-clockwise, collinear points
 * dropped (Andrew's monotone chain); hull needs room for 2 n. Returns its size. */
static size_t convex_hull(point *pts, size_t n, point *hull)
{
    qsort(pts, n, sizeof *pts, compare_points);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0)
            k--;
        hull[k++] = pts[i];
    }
    for (size_t i = n - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0)
            k--;
        hull[k++] = pts[i];
    }
    return k > 1 ? k - 1 : k; /* the last point repeats the first */
}

/* Area of the hull's bounding rectangle with sides along (c, s) and (-s, c). */
static double box_area(const point *hull, size_t h, double c, double s)
{
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (size_t i = 0; i < h; i++) {
        double u = c * hull[i].x + s * hull[i].y, v = -s * hull[i].x + c * hull[i].y;
        u0 = fmin(u0, u);
        u1 = fmax(u1, u);
        v0 = fmin(v0, v);
        v1 = fmax(v1, v);
    }
    return (u1 - u0) * (v1 - v0);
}

/* The turn in (-pi/4, pi/4] that makes the hull's smallest bounding rectangle axis-aligned,
 * or 0 when it does not shrink the axis-aligned box by more than KEEP_MARGIN. */
static double best_turn(const point *hull, size_t h)
{
    double current = box_area(hull, h, 1, 0), best = current, turn = 0;
    for (size_t i = 0; i < h; i++) {
        point a = hull[i], b = hull[(i + 1) % h];
        double len = hypot(b.x - a.x, b.y - a.y);
        if (!(len > 0))
            continue;
        double c = (b.x - a.x) / len, s = (b.y - a.y) / len, area = box_area(hull, h, c, s);
        if (area < best) {
            best = area;
            turn = -atan2(s, c);
        }
    }
    if (!(best < (1 - KEEP_MARGIN) * current))
        return 0;
    const double quarter = 2 * atan(1.0); /* pi / 2 */
    turn -= quarter * round(turn / quarter);
    return turn;
}

/* Turns chart c's vertices by its best turn about their centroid; pts and hull are scratch
 * for the largest chart. */
static double orient_chart(const chart_vertices *cv, size_t c, const double *texel, point *pts, point *hull,
                           double *texel_out)
{
    size_t n = cv->start[c + 1] - cv->start[c];
    const uint32_t *vs = cv->vertex + cv->start[c];
    if (n < 3)
        return 0;
    double cx = 0, cy = 0;
    for (size_t i = 0; i < n; i++) {
        pts[i].x = texel[2 * vs[i]];
        pts[i].y = texel[2 * vs[i] + 1];
        cx += pts[i].x;
        cy += pts[i].y;
    }
    cx /= (double)n;
    cy /= (double)n;
    double turn = best_turn(hull, convex_hull(pts, n, hull));
    if (turn == 0)
        return 0;
    double co = cos(turn), si = sin(turn);
    for (size_t i = 0; i < n; i++) {
        double x = texel[2 * vs[i]] - cx, y = texel[2 * vs[i] + 1] - cy;
        texel_out[2 * vs[i]] = cx + co * x - si * y;
        texel_out[2 * vs[i] + 1] = cy + si * x + co * y;
    }
    return turn;
}

texopt_status texopt_chart_orient(const texopt_mesh *mesh, const double *texel, const uint8_t *turnable,
                                  double *texel_out, double *angle_out, char *err, size_t err_len)
{
    if (!mesh || !texel || !texel_out || texel == texel_out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "chart_orient: mesh, layout and a separate output are required");
    for (size_t i = 0; i < 2 * mesh->vertex_count; i++)
        if (!isfinite(texel[i]))
            return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "chart_orient: vertex %zu has a non-finite position",
                               i / 2);
    chart_vertices cv = {0};
    texopt_status st = group_vertices(mesh, &cv, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t largest = 1;
    for (size_t c = 0; c < mesh->chart_count; c++)
        if (cv.start[c + 1] - cv.start[c] > largest)
            largest = cv.start[c + 1] - cv.start[c];
    point *pts = malloc(sizeof(point) * largest), *hull = malloc(sizeof(point) * 2 * largest);
    if (!pts || !hull)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for chart hulls");
    if (st == TEXOPT_OK) {
        memcpy(texel_out, texel, sizeof(double) * 2 * mesh->vertex_count);
        for (size_t c = 0; c < mesh->chart_count; c++) {
            double turn = !turnable || turnable[c] ? orient_chart(&cv, c, texel, pts, hull, texel_out) : 0;
            if (angle_out)
                angle_out[c] = turn;
        }
    }
    free(pts);
    free(hull);
    chart_vertices_destroy(&cv);
    return st;
}
