/* Tests of chart_orient.c: rectangles turned by random angles come back axis-aligned (their
 * box shrinks to their own area), every chart moves rigidly (distances, orientation and
 * centroid kept: no mirror, no scale), charts not allowed to turn or already at their best
 * angle stay bit for bit, and bad layouts are refused. Meshes are built by hand. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chart_orient.h"
#include "handmesh.h"
#include "test.h"
#include "turned_rects.h"

static double box_area(const double *texel, size_t first, size_t count)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t v = first; v < first + count; v++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], texel[2 * v + a]);
            hi[a] = fmax(hi[a], texel[2 * v + a]);
        }
    return (hi[0] - lo[0]) * (hi[1] - lo[1]);
}

/* Chart of vertices [first, first + count) moved rigidly without a mirror: every pairwise
 * distance, every triangle's signed area and the centroid kept. */
static int moved_rigidly(const texopt_mesh *m, const double *in, const double *out, size_t first, size_t count)
{
    double cin[2] = {0, 0}, cout[2] = {0, 0};
    for (size_t i = first; i < first + count; i++) {
        for (int a = 0; a < 2; a++) {
            cin[a] += in[2 * i + a] / (double)count;
            cout[a] += out[2 * i + a] / (double)count;
        }
        for (size_t j = first; j < i; j++) {
            double din = hypot(in[2 * i] - in[2 * j], in[2 * i + 1] - in[2 * j + 1]);
            double dout = hypot(out[2 * i] - out[2 * j], out[2 * i + 1] - out[2 * j + 1]);
            if (fabs(din - dout) > 1e-9 * (1 + din))
                return 0;
        }
    }
    for (size_t t = 0; t < m->triangle_count; t++)
        if (m->triangle[3 * t] >= first && m->triangle[3 * t] < first + count) {
            double a_in = handmesh_doubled_area(in, m->triangle + 3 * t, 2);
            double a_out = handmesh_doubled_area(out, m->triangle + 3 * t, 2);
            if (fabs(a_in - a_out) > 1e-9 * (1 + fabs(a_in)))
                return 0;
        }
    return hypot(cin[0] - cout[0], cin[1] - cout[1]) < 1e-9;
}

TEST(turned_rectangles_come_back_axis_aligned_and_rigid)
{
    enum { CHARTS = 16 };
    double turn[CHARTS], sides[2 * CHARTS], angle[CHARTS];
    for (int c = 0; c < CHARTS; c++)
        turn[c] = -1.5 + 3.0 * c / (CHARTS - 1); /* -86 to 86 degrees */
    texopt_mesh *m = turned_rects(CHARTS, turn, 0, 64, sides, 3);
    CHECK(m != NULL);
    double *out = malloc(sizeof(double) * 2 * m->vertex_count);
    char err[256] = "";
    CHECK_OK(texopt_chart_orient(m, m->texel, NULL, out, angle, err, sizeof err), err);
    const double quarter = 2 * atan(1.0);
    for (size_t c = 0; c < CHARTS; c++) {
        double own = sides[2 * c] * sides[2 * c + 1];
        CHECK_MSG(box_area(out, 4 * c, 4) <= own * (1 + 1e-9), "chart %zu: box %.3f for a %.3f rectangle", c,
                  box_area(out, 4 * c, 4), own);
        CHECK(moved_rigidly(m, m->texel, out, 4 * c, 4));
        CHECK(fabs(angle[c]) <= quarter / 2 + 1e-12);
        /* The turn undoes the generated one up to quarter turns. */
        double undone = angle[c] + turn[c];
        CHECK_NEAR(undone - quarter * round(undone / quarter), 0, 1e-9);
    }
    free(out);
    texopt_mesh_destroy(m);
}

TEST(charts_not_turnable_or_already_best_stay_bit_for_bit)
{
    /* chart 0 turned but not allowed to turn, chart 1 axis-aligned, chart 2 turned by
     * 0.0005 (its box, at most 1 + 0.0005 (16 + 1/16) of its area for sides of 4 to 64, would
     * shrink by less than 1%: not worth a resampling at an angle), chart 3 turned and
     * allowed. */
    const double turn[4] = {0.5, 0, 0.0005, 0.5};
    double sides[8], angle[4];
    texopt_mesh *m = turned_rects(4, turn, 0, 64, sides, 11);
    CHECK(m != NULL);
    const uint8_t turnable[4] = {0, 1, 1, 1};
    double *out = malloc(sizeof(double) * 2 * m->vertex_count);
    char err[256] = "";
    CHECK_OK(texopt_chart_orient(m, m->texel, turnable, out, angle, err, sizeof err), err);
    CHECK(memcmp(out, m->texel, sizeof(double) * 2 * 12) == 0);
    CHECK(angle[0] == 0 && angle[1] == 0 && angle[2] == 0);
    CHECK_NEAR(angle[3], -0.5, 1e-9);
    CHECK(memcmp(out + 24, m->texel + 24, sizeof(double) * 8) != 0);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(bad_layouts_are_refused)
{
    const double turn[1] = {0.5};
    double sides[2];
    texopt_mesh *m = turned_rects(1, turn, 0, 64, sides, 5);
    CHECK(m != NULL);
    double out[8];
    char err[256] = "";
    CHECK(texopt_chart_orient(m, m->texel, NULL, m->texel, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    m->texel[3] = NAN;
    CHECK(texopt_chart_orient(m, m->texel, NULL, out, NULL, err, sizeof err) == TEXOPT_E_NUMERIC);
    CHECK(strstr(err, "vertex 1") != NULL);
    m->chart_of[1] = 7;
    m->texel[3] = 1;
    CHECK(texopt_chart_orient(m, m->texel, NULL, out, NULL, err, sizeof err) == TEXOPT_E_INTERNAL);
    texopt_mesh_destroy(m);
}
