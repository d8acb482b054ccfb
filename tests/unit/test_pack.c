/* Tests of pack.c: charts never overlap and keep the gutter, stay inside the texture, move
 * only by translations and quarter turns, and the reported efficiency is what it says.
 * Meshes are built by hand here (pack reads only triangles, charts and texels). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pack.h"
#include "test.h"

typedef struct test_mesh {
    texopt_mesh m;
} test_mesh;

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static double urand(uint32_t *s)
{
    return (double)(lcg(s) & 0xffffff) / 16777216.0;
}

/* `charts` random charts: even ones a random triangle, odd ones an L made of 4 triangles
 * (concave, so footprints matter), sizes between 2 and 40 texels, at random places. */
static int make_random_charts(test_mesh *t, size_t charts, uint32_t seed)
{
    texopt_mesh *m = &t->m;
    memset(m, 0, sizeof *m);
    size_t max_v = charts * 8, max_t = charts * 4;
    m->texel = calloc(2 * max_v, sizeof(double));
    m->triangle = calloc(3 * max_t, sizeof(uint32_t));
    m->chart_of = calloc(max_t, sizeof(uint32_t));
    m->flags = calloc(max_t, 1);
    if (!m->texel || !m->triangle || !m->chart_of || !m->flags)
        return -1;
    m->chart_count = charts;
    for (size_t c = 0; c < charts; c++) {
        double ox = urand(&seed) * 500, oy = urand(&seed) * 500, s = 2 + urand(&seed) * 38;
        size_t v0 = m->vertex_count;
        if (c % 2 == 0) {
            const double p[3][2] = {{0, 0}, {s, urand(&seed) * s}, {urand(&seed) * s, s}};
            for (int i = 0; i < 3; i++) {
                m->texel[2 * (v0 + i)] = ox + p[i][0];
                m->texel[2 * (v0 + i) + 1] = oy + p[i][1];
            }
            m->vertex_count += 3;
            uint32_t tri[3] = {(uint32_t)v0, (uint32_t)v0 + 1, (uint32_t)v0 + 2};
            memcpy(m->triangle + 3 * m->triangle_count, tri, sizeof tri);
            m->chart_of[m->triangle_count++] = (uint32_t)c;
        } else {
            /* L: (0,0) (2,0) (2,1) (1,1) (1,2) (0,2) scaled by s/2, as 4 triangles. */
            const double p[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
            for (int i = 0; i < 6; i++) {
                m->texel[2 * (v0 + i)] = ox + p[i][0] * s / 2;
                m->texel[2 * (v0 + i) + 1] = oy + p[i][1] * s / 2;
            }
            m->vertex_count += 6;
            const uint32_t tris[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
            for (int k = 0; k < 4; k++) {
                for (int j = 0; j < 3; j++)
                    m->triangle[3 * m->triangle_count + j] = (uint32_t)v0 + tris[k][j];
                m->chart_of[m->triangle_count++] = (uint32_t)c;
            }
        }
    }
    return 0;
}

static void free_test_mesh(test_mesh *t)
{
    free(t->m.texel);
    free(t->m.triangle);
    free(t->m.chart_of);
    free(t->m.flags);
}

static double total_area(const texopt_mesh *m, const double *texel)
{
    double a = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        const double *p = texel + 2 * v[0], *q = texel + 2 * v[1], *r = texel + 2 * v[2];
        a += 0.5 * fabs((q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1]));
    }
    return a;
}

/* Labels every texel cell touched by a chart (points sampled every 1/3 texel on each
 * triangle); returns -1 when two charts come within `radius` cells of each other. */
static int check_separation(const texopt_mesh *m, const double *texel, int w, int h, int radius)
{
    int *label = malloc(sizeof(int) * (size_t)w * h);
    for (int i = 0; i < w * h; i++)
        label[i] = -1;
    int bad = 0;
    for (size_t t = 0; t < m->triangle_count && !bad; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        const double *a = texel + 2 * v[0], *b = texel + 2 * v[1], *c = texel + 2 * v[2];
        double len = fmax(fmax(fabs(b[0] - a[0]) + fabs(b[1] - a[1]), fabs(c[0] - a[0]) + fabs(c[1] - a[1])), 1);
        int n = (int)(len * 3) + 1;
        for (int i = 0; i <= n && !bad; i++)
            for (int j = 0; i + j <= n && !bad; j++) {
                double s = (double)i / n, r = (double)j / n;
                double x = a[0] + s * (b[0] - a[0]) + r * (c[0] - a[0]);
                double y = a[1] + s * (b[1] - a[1]) + r * (c[1] - a[1]);
                int cx = (int)floor(x), cy = (int)floor(y);
                if (cx < 0 || cy < 0 || cx >= w || cy >= h) {
                    bad = 1;
                    break;
                }
                for (int dy = -radius; dy <= radius; dy++)
                    for (int dx = -radius; dx <= radius; dx++) {
                        int nx = cx + dx, ny = cy + dy;
                        if (nx < 0 || ny < 0 || nx >= w || ny >= h)
                            continue;
                        int l = label[ny * w + nx];
                        if (l >= 0 && l != (int)m->chart_of[t])
                            bad = 1;
                    }
                label[cy * w + cx] = (int)m->chart_of[t];
            }
    }
    free(label);
    return bad ? -1 : 0;
}

/* Every triangle's edges must be the input edges turned by the chart's quarter turns. */
static int check_rigid_quarter_turns(const texopt_mesh *m, const double *in, const double *out, const uint8_t *rotation)
{
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        int k = rotation[m->chart_of[t]];
        if (k > 3)
            return -1;
        for (int e = 1; e < 3; e++) {
            double dx = in[2 * v[e]] - in[2 * v[0]], dy = in[2 * v[e] + 1] - in[2 * v[0] + 1];
            double ox = out[2 * v[e]] - out[2 * v[0]], oy = out[2 * v[e] + 1] - out[2 * v[0] + 1];
            double rx = k == 0 ? dx : k == 1 ? -dy : k == 2 ? -dx : dy;
            double ry = k == 0 ? dy : k == 1 ? dx : k == 2 ? -dy : -dx;
            if (fabs(rx - ox) > 1e-9 || fabs(ry - oy) > 1e-9)
                return -1;
        }
    }
    return 0;
}

TEST(random_charts_do_not_overlap_stay_inside_and_only_turn)
{
    test_mesh t;
    CHECK(make_random_charts(&t, 120, 7) == 0);
    double *out = malloc(sizeof(double) * 2 * t.m.vertex_count);
    texopt_pack_result r;
    int fits = 0;
    char err[256] = "";
    texopt_pack_options opt = {.gutter = 4};
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 256, 0, &opt, out, &r, &fits, err, sizeof err), err);
    CHECK(fits);
    CHECK(r.height >= r.used_height && r.height % 4 == 0);
    for (size_t v = 0; v < t.m.vertex_count; v++) {
        CHECK(out[2 * v] >= 2 - 1e-9 && out[2 * v] <= 256 - 2 + 1e-9);
        CHECK(out[2 * v + 1] >= 2 - 1e-9 && out[2 * v + 1] <= r.height - 2 + 1e-9);
    }
    /* gutter 4: points of two charts are >= 4 texels apart, so their cells differ by >= 3 */
    CHECK(check_separation(&t.m, out, 256, r.height, 2) == 0);
    CHECK(check_rigid_quarter_turns(&t.m, t.m.texel, out, r.rotation) == 0);
    CHECK_NEAR(r.area_efficiency, total_area(&t.m, t.m.texel) / (256.0 * r.height), 1e-12);
    int turned = 0;
    for (size_t c = 0; c < r.chart_count; c++)
        turned += r.rotation[c] != 0;
    CHECK(turned > 0); /* a bottom-left packer of L shapes uses its rotations */
    texopt_pack_result_destroy(&r);
    free(out);
    free_test_mesh(&t);
}

TEST(interlocking_footprints_beat_bounding_boxes)
{
    /* 60 L-shaped charts cover 3/4 of their bounding boxes: a box packer cannot exceed
     * 0.75 efficiency; footprint packing nests them and should reach more than 0.6 with the
     * gutter, while still separating them. */
    test_mesh t;
    CHECK(make_random_charts(&t, 60, 11) == 0);
    double *out = malloc(sizeof(double) * 2 * t.m.vertex_count);
    texopt_pack_result r;
    int fits;
    char err[256] = "";
    texopt_pack_options opt = {.gutter = 2};
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 160, 0, &opt, out, &r, &fits, err, sizeof err), err);
    CHECK(fits);
    CHECK(check_separation(&t.m, out, 160, r.height, 0) == 0);
    CHECK_MSG(r.area_efficiency > 0.5, "efficiency %.3f", r.area_efficiency);
    texopt_pack_result_destroy(&r);
    free(out);
    free_test_mesh(&t);
}

TEST(fixed_size_reports_when_charts_do_not_fit)
{
    test_mesh t;
    CHECK(make_random_charts(&t, 40, 3) == 0);
    double *out = malloc(sizeof(double) * 2 * t.m.vertex_count);
    texopt_pack_result r;
    int fits = 1;
    char err[256] = "";
    double area = total_area(&t.m, t.m.texel);
    int side = (int)sqrt(area) / 2; /* a quarter of the area needed */
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, side, side, NULL, out, &r, &fits, err, sizeof err), err);
    CHECK(fits == 0);
    texopt_pack_result_destroy(&r);
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 4 * side, 4 * side, NULL, out, &r, &fits, err, sizeof err), err);
    CHECK(fits == 1);
    CHECK(check_separation(&t.m, out, 4 * side, 4 * side, 2) == 0);
    texopt_pack_result_destroy(&r);
    free(out);
    free_test_mesh(&t);
}

TEST(packing_is_deterministic)
{
    test_mesh t;
    CHECK(make_random_charts(&t, 50, 5) == 0);
    size_t n = 2 * t.m.vertex_count;
    double *a = malloc(sizeof(double) * n), *b = malloc(sizeof(double) * n);
    texopt_pack_result r;
    int fits;
    char err[256] = "";
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 200, 0, NULL, a, &r, &fits, err, sizeof err), err);
    texopt_pack_result_destroy(&r);
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 200, 0, NULL, b, &r, &fits, err, sizeof err), err);
    texopt_pack_result_destroy(&r);
    CHECK(memcmp(a, b, sizeof(double) * n) == 0);
    free(a);
    free(b);
    free_test_mesh(&t);
}

TEST(bad_layouts_are_refused)
{
    test_mesh t;
    CHECK(make_random_charts(&t, 4, 1) == 0);
    double *out = malloc(sizeof(double) * 2 * t.m.vertex_count);
    texopt_pack_result r;
    int fits;
    char err[256] = "";
    t.m.texel[3] = NAN;
    CHECK(texopt_pack_charts(&t.m, t.m.texel, 64, 0, NULL, out, &r, &fits, err, sizeof err) == TEXOPT_E_NUMERIC);
    t.m.texel[3] = 1;
    CHECK(texopt_pack_charts(&t.m, t.m.texel, 0, 0, NULL, out, &r, &fits, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    free(out);
    free_test_mesh(&t);
}

TEST(a_packer_reused_gives_the_one_shot_packing_and_follows_a_sequence)
{
    test_mesh t;
    CHECK(make_random_charts(&t, 30, 9) == 0);
    size_t n = 2 * t.m.vertex_count;
    double *a = malloc(sizeof(double) * n), *b = malloc(sizeof(double) * n);
    texopt_pack_result r;
    int fits;
    char err[256] = "";
    texopt_pack_options opt = {.gutter = 4, .cell = 1};
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 200, 0, &opt, a, &r, &fits, err, sizeof err), err);
    texopt_pack_result_destroy(&r);
    texopt_packer *p = NULL;
    CHECK_OK(texopt_packer_create(&p, &t.m, t.m.texel, &opt, 200, err, sizeof err), err);
    for (int run = 0; run < 2; run++) { /* the packer keeps no state between runs */
        CHECK_OK(texopt_packer_run(p, 200, 0, NULL, b, &r, &fits, err, sizeof err), err);
        CHECK(fits);
        CHECK(memcmp(a, b, sizeof(double) * n) == 0);
        CHECK(r.used_width <= 200 && r.used_width > 150);
        texopt_pack_result_destroy(&r);
    }
    /* The reversed order places the smallest chart first, at the bottom-left corner. */
    uint32_t seq[30];
    double smallest = INFINITY;
    uint32_t small_chart = 0;
    for (uint32_t c = 0; c < 30; c++) {
        seq[c] = 29 - c;
        double area = 0;
        for (size_t tri = 0; tri < t.m.triangle_count; tri++)
            if (t.m.chart_of[tri] == c) {
                const uint32_t *v = t.m.triangle + 3 * tri;
                const double *p0 = t.m.texel + 2 * v[0], *p1 = t.m.texel + 2 * v[1], *p2 = t.m.texel + 2 * v[2];
                area += 0.5 * fabs((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]));
            }
        if (area < smallest) {
            smallest = area;
            small_chart = c;
        }
    }
    seq[0] = small_chart;
    seq[29 - small_chart] = 29;
    texopt_pack_options by_seq = {.sequence = seq};
    CHECK_OK(texopt_packer_run(p, 200, 0, &by_seq, b, &r, &fits, err, sizeof err), err);
    CHECK(fits);
    CHECK(check_separation(&t.m, b, 200, r.height, 2) == 0);
    CHECK(check_rigid_quarter_turns(&t.m, t.m.texel, b, r.rotation) == 0);
    double lo_x = INFINITY, lo_y = INFINITY;
    for (size_t tri = 0; tri < t.m.triangle_count; tri++)
        if (t.m.chart_of[tri] == small_chart)
            for (int j = 0; j < 3; j++) {
                lo_x = fmin(lo_x, b[2 * t.m.triangle[3 * tri + j]]);
                lo_y = fmin(lo_y, b[2 * t.m.triangle[3 * tri + j] + 1]);
            }
    CHECK(lo_x < 3.5 && lo_y < 3.5); /* gutter / 2 plus at most one cell */
    texopt_pack_result_destroy(&r);
    /* A sequence that repeats a chart is refused. */
    seq[1] = seq[0];
    CHECK(texopt_packer_run(p, 200, 0, &by_seq, b, &r, &fits, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_packer_destroy(p);
    texopt_packer_destroy(NULL);
    free(a);
    free(b);
    free_test_mesh(&t);
}

/* Square charts of the given sides (two triangles each), spread apart. */
static int make_squares(test_mesh *t, const double *side, size_t charts)
{
    texopt_mesh *m = &t->m;
    memset(m, 0, sizeof *m);
    m->texel = calloc(8 * charts, sizeof(double));
    m->triangle = calloc(6 * charts, sizeof(uint32_t));
    m->chart_of = calloc(2 * charts, sizeof(uint32_t));
    m->flags = calloc(2 * charts, 1);
    if (!m->texel || !m->triangle || !m->chart_of || !m->flags)
        return -1;
    m->chart_count = charts;
    for (size_t c = 0; c < charts; c++) {
        const double corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int i = 0; i < 4; i++) {
            m->texel[2 * (4 * c + i)] = 100.0 * (double)c + corner[i][0] * side[c];
            m->texel[2 * (4 * c + i) + 1] = corner[i][1] * side[c];
        }
        const uint32_t tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int k = 0; k < 2; k++) {
            for (int j = 0; j < 3; j++)
                m->triangle[3 * (2 * c + k) + j] = (uint32_t)(4 * c) + tris[k][j];
            m->chart_of[2 * c + k] = (uint32_t)c;
        }
    }
    m->vertex_count = 4 * charts;
    m->triangle_count = 2 * charts;
    return 0;
}

static double chart_low(const texopt_mesh *m, const double *texel, uint32_t chart, int axis)
{
    double lo = INFINITY;
    for (size_t t = 0; t < m->triangle_count; t++)
        if (m->chart_of[t] == chart)
            for (int j = 0; j < 3; j++)
                lo = fmin(lo, texel[2 * m->triangle[3 * t + j] + axis]);
    return lo;
}

TEST(a_chart_takes_a_gap_exactly_its_width_and_not_a_narrower_one)
{
    /* With gutter 2 and one-texel cells a square of side s has a footprint of s + 3 cells
     * a side. Squares 10, 10 and 4 in a strip 13 + 13 + 7 cells wide: the last one fills the
     * 7 cells left beside the first two, on the bottom row. One cell narrower, it cannot, and
     * goes on top of them although the bottom rows still have 6 free cells. */
    const double side[3] = {10, 10, 4};
    test_mesh t;
    CHECK(make_squares(&t, side, 3) == 0);
    double *out = malloc(sizeof(double) * 2 * t.m.vertex_count);
    texopt_pack_result r;
    int fits;
    char err[256] = "";
    texopt_pack_options opt = {.gutter = 2, .cell = 1};
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 33, 0, &opt, out, &r, &fits, err, sizeof err), err);
    CHECK(fits);
    CHECK(check_separation(&t.m, out, 33, r.height, 1) == 0);
    CHECK_MSG(chart_low(&t.m, out, 2, 1) < 2 && chart_low(&t.m, out, 2, 0) > 25, "small square at (%g, %g)",
              chart_low(&t.m, out, 2, 0), chart_low(&t.m, out, 2, 1));
    texopt_pack_result_destroy(&r);
    CHECK_OK(texopt_pack_charts(&t.m, t.m.texel, 32, 0, &opt, out, &r, &fits, err, sizeof err), err);
    CHECK(fits);
    CHECK(check_separation(&t.m, out, 32, r.height, 1) == 0);
    CHECK_MSG(chart_low(&t.m, out, 2, 1) > 12, "small square at (%g, %g)", chart_low(&t.m, out, 2, 0),
              chart_low(&t.m, out, 2, 1));
    texopt_pack_result_destroy(&r);
    free(out);
    free_test_mesh(&t);
}
