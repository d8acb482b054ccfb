/* test_atlas_refine.c - charts deformed toward axis-aligned shapes (engine/layout/atlas_refine.c).
 *
 * Three L-shaped grid charts (12 x 12 cells, one quadrant removed, every vertex jittered),
 * turned by 30 degrees: one counter-clockwise, one mirrored (clockwise, as v-down texel
 * layouts are), one marked keep_shape. The first two must come out with every boundary edge
 * within 0.15 rad of an axis, filling their axis-aligned box (the L's 0.75) far better
 * than turned (0.49), with no triangle reversed and their area kept within 10%; the
 * third is copied exactly. A distortion bound below what the deformation needs keeps all;
 * charts that keep their angle are refined only when turned by 2 degrees, not 30. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_refine.h"
#include "handmesh.h"
#include "rng.h"
#include "test.h"

#define N 12
#define CHARTS 3
#define TURN (30.0 * 3.14159265358979323846 / 180.0)

static int in_l(int i, int j)
{
    return !(i >= N / 2 && j >= N / 2);
}

/* Grid vertex (i, j) of chart c: index, or -1 when no cell of the L uses it. */
static int grid_vertex(int i, int j)
{
    int used = 0;
    for (int di = -1; di <= 0; di++)
        for (int dj = -1; dj <= 0; dj++) {
            int ci = i + di, cj = j + dj;
            used |= ci >= 0 && cj >= 0 && ci < N && cj < N && in_l(ci, cj);
        }
    return used ? j * (N + 1) + i : -1;
}

static texopt_mesh *l_charts(double turn)
{
    size_t per_v = (N + 1) * (N + 1), cells = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            cells += (size_t)in_l(i, j);
    texopt_mesh *m = handmesh_alloc(CHARTS * per_v, CHARTS * 2 * cells);
    if (!m)
        return NULL;
    m->chart_count = CHARTS;
    texopt_rng rng;
    texopt_rng_seed(&rng, 7);
    size_t t = 0;
    for (int c = 0; c < CHARTS; c++) {
        double mirror = c == 1 ? -1.0 : 1.0, ox = 40.0 * c;
        for (int j = 0; j <= N; j++)
            for (int i = 0; i <= N; i++) {
                double x = i + 0.2 * (texopt_rng_uniform(&rng) - 0.5), y = j + 0.2 * (texopt_rng_uniform(&rng) - 0.5);
                double *p = m->texel + 2 * (c * per_v + (size_t)(j * (N + 1) + i));
                p[0] = ox + cos(turn) * x - sin(turn) * y;
                p[1] = mirror * (sin(turn) * x + cos(turn) * y);
                double *q = m->position + 3 * (c * per_v + (size_t)(j * (N + 1) + i));
                q[0] = p[0];
                q[1] = p[1];
            }
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                if (!in_l(i, j))
                    continue;
                uint32_t a = (uint32_t)(c * per_v) + (uint32_t)grid_vertex(i, j);
                uint32_t b = (uint32_t)(c * per_v) + (uint32_t)grid_vertex(i + 1, j);
                uint32_t d = (uint32_t)(c * per_v) + (uint32_t)grid_vertex(i, j + 1);
                uint32_t e = (uint32_t)(c * per_v) + (uint32_t)grid_vertex(i + 1, j + 1);
                uint32_t tri[6] = {a, b, e, a, e, d};
                for (int k = 0; k < 2; k++, t++) {
                    memcpy(m->triangle + 3 * t, tri + 3 * k, 3 * sizeof *tri);
                    m->chart_of[t] = (uint32_t)c;
                }
            }
    }
    handmesh_finish(m);
    return m;
}

static double chart_area(const texopt_mesh *m, const double *xy, uint32_t c, int *reversed)
{
    double area = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (m->chart_of[t] != c)
            continue;
        double a = 0.5 * handmesh_doubled_area(xy, m->triangle + 3 * t, 2);
        *reversed += (a < 0) != (m->area_texel[t] < 0) || a == 0;
        area += fabs(a);
    }
    return area;
}

/* Area over the axis-aligned box of chart c. */
static double box_fill(const texopt_mesh *m, const double *xy, uint32_t c)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    int reversed = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3 && m->chart_of[t] == c; k++)
            for (int d = 0; d < 2; d++) {
                lo[d] = fmin(lo[d], xy[2 * m->triangle[3 * t + k] + d]);
                hi[d] = fmax(hi[d], xy[2 * m->triangle[3 * t + k] + d]);
            }
    return chart_area(m, xy, c, &reversed) / ((hi[0] - lo[0]) * (hi[1] - lo[1]));
}

/* Largest angle between a boundary edge of chart c (a grid edge on the L's outline) and
 * its closest axis. */
static double worst_axis_angle(const double *xy, int c)
{
    size_t per_v = (N + 1) * (N + 1);
    double worst = 0;
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++)
            for (int dir = 0; dir < 2; dir++) {
                int i1 = i + (dir == 0), j1 = j + (dir == 1);
                if (i1 > N || j1 > N || grid_vertex(i, j) < 0 || grid_vertex(i1, j1) < 0)
                    continue;
                /* a boundary edge has an L cell on one side only */
                int s0 = dir == 0 ? (j > 0 && in_l(i, j - 1)) : (i > 0 && in_l(i - 1, j));
                int s1 = dir == 0 ? (j < N && in_l(i, j)) : (i < N && in_l(i, j));
                if (s0 == s1)
                    continue;
                const double *a = xy + 2 * (c * per_v + (size_t)grid_vertex(i, j));
                const double *b = xy + 2 * (c * per_v + (size_t)grid_vertex(i1, j1));
                double angle = fmod(fabs(atan2(b[1] - a[1], b[0] - a[0])), 3.14159265358979323846 / 2);
                worst = fmax(worst, fmin(angle, 3.14159265358979323846 / 2 - angle));
            }
    return worst;
}

TEST(l_charts_come_out_axis_aligned_filling_their_boxes)
{
    texopt_mesh *m = l_charts(TURN);
    CHECK(m != NULL);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    uint8_t keep[CHARTS] = {0, 0, 1};
    texopt_atlas_refine_report rep;
    char err[256];
    CHECK(texopt_atlas_refine(m, m->texel, keep, NULL, 0, out, &rep, NULL, err, sizeof err) == TEXOPT_OK);
    CHECK(rep.charts_refined == 2 && rep.charts_skipped == 1);
    for (uint32_t c = 0; c < 2; c++) {
        int reversed = 0;
        double before = box_fill(m, m->texel, c), after = box_fill(m, out, c);
        double area_ratio = chart_area(m, out, c, &reversed) / chart_area(m, m->texel, c, &(int){0});
        CHECK_MSG(before < 0.55 && after > 0.68, "chart %u box fill %.3f -> %.3f", c, before, after);
        CHECK_MSG(worst_axis_angle(out, (int)c) < 0.15, "chart %u edge %.3f rad off its axis", c,
                  worst_axis_angle(out, (int)c));
        CHECK_MSG(reversed == 0, "chart %u: %d triangles reversed", c, reversed);
        CHECK_MSG(fabs(area_ratio - 1) < 0.1, "chart %u area ratio %.3f", c, area_ratio);
    }
    size_t per_v = (N + 1) * (N + 1);
    CHECK(memcmp(out + 2 * 2 * per_v, m->texel + 2 * 2 * per_v, 2 * per_v * sizeof *out) == 0);
    CHECK_MSG(rep.distortion > 1.0 && rep.distortion < 1.5, "distortion %.4f", rep.distortion);
    CHECK_MSG(fabs(rep.boundary_after / rep.boundary_before - 1) < 0.1, "boundary %.2f -> %.2f", rep.boundary_before,
              rep.boundary_after);
    free(out);
    texopt_mesh_destroy(m);
}

/* A chart with a hole has two boundary loops: it is left as it is. */
TEST(a_chart_with_a_hole_is_left_as_it_is)
{
    /* a 3 x 3 grid of cells without its centre cell */
    texopt_mesh *m = handmesh_alloc(16, 16);
    CHECK(m != NULL);
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            m->texel[2 * (j * 4 + i)] = i + 0.3 * j;
            m->texel[2 * (j * 4 + i) + 1] = j;
        }
    size_t t = 0;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            if (i == 1 && j == 1)
                continue;
            uint32_t a = (uint32_t)(j * 4 + i), tri[6] = {a, a + 1, a + 5, a, a + 5, a + 4};
            memcpy(m->triangle + 3 * t, tri, sizeof tri);
            t += 2;
        }
    handmesh_finish(m);
    double out[32];
    texopt_atlas_refine_report rep;
    CHECK(texopt_atlas_refine(m, m->texel, NULL, NULL, 0, out, &rep, NULL, NULL, 0) == TEXOPT_OK);
    CHECK(rep.charts_refined == 0 && rep.charts_skipped == 1);
    CHECK(memcmp(out, m->texel, sizeof out) == 0);
    texopt_mesh_destroy(m);
}

/* A bound the deformation cannot meet (the L's distortion is above 1) leaves every chart as
 * it was. */
TEST(charts_past_the_distortion_bound_are_left_as_they_are)
{
    texopt_mesh *m = l_charts(TURN);
    CHECK(m != NULL);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    texopt_atlas_refine_report rep;
    CHECK(texopt_atlas_refine(m, m->texel, NULL, NULL, 1.0 + 1e-9, out, &rep, NULL, NULL, 0) == TEXOPT_OK);
    CHECK_MSG(rep.charts_refined == 0 && rep.charts_too_distorted == CHARTS, "refined %zu, too distorted %zu",
              rep.charts_refined, rep.charts_too_distorted);
    CHECK(memcmp(out, m->texel, 2 * m->vertex_count * sizeof *out) == 0);
    CHECK(texopt_atlas_refine(m, m->texel, NULL, NULL, 1.5, out, &rep, NULL, NULL, 0) == TEXOPT_OK);
    CHECK(rep.charts_refined == CHARTS);
    free(out);
    texopt_mesh_destroy(m);
}

/* A chart whose angle on the texel grid matters is refined only when the turn is small:
 * the 30-degree L's are left as they are, the same L's turned by 2 degrees are refined. */
TEST(charts_keeping_their_angle_turn_little_or_not_at_all)
{
    uint8_t all[CHARTS] = {1, 1, 1};
    double turns[2] = {TURN, 2.0 * 3.14159265358979323846 / 180.0};
    for (int k = 0; k < 2; k++) {
        texopt_mesh *m = l_charts(turns[k]);
        CHECK(m != NULL);
        double *out = malloc(2 * m->vertex_count * sizeof *out);
        texopt_atlas_refine_report rep;
        CHECK(texopt_atlas_refine(m, m->texel, NULL, all, 0, out, &rep, NULL, NULL, 0) == TEXOPT_OK);
        size_t want = k == 0 ? 0 : CHARTS;
        CHECK_MSG(rep.charts_refined == want && rep.charts_kept_angle == CHARTS - want,
                  "turn %.3f: refined %zu, kept angle %zu", turns[k], rep.charts_refined, rep.charts_kept_angle);
        free(out);
        texopt_mesh_destroy(m);
    }
}
