/* test_chart_gap.c - the smallest distance between two charts (engine/layout/chart_gap.c).
 *
 * Two charts, each a square of 4 x 4 texels in two triangles, laid at known offsets: side
 * by side 3 texels apart, corner to corner (3 and 4 apart along the axes: 5), touching
 * (0), crossing (0); a chart skipped leaves one chart (INFINITY). A third chart far away
 * does not change the smallest distance, and is the nearest when the second is skipped. */
#include <math.h>
#include <string.h>

#include "chart_gap.h"
#include "handmesh.h"
#include "test.h"

#define SIDE 4.0

/* The two squares, the second moved by (dx, dy); a third, when `third`, at (100, 100). */
static texopt_mesh *squares(double dx, double dy, int third)
{
    size_t charts = third ? 3 : 2;
    texopt_mesh *m = handmesh_alloc(4 * charts, 2 * charts);
    if (!m)
        return NULL;
    double at[3][2] = {{0, 0}, {dx, dy}, {100, 100}};
    for (size_t c = 0; c < charts; c++) {
        double corner[4][2] = {{0, 0}, {SIDE, 0}, {SIDE, SIDE}, {0, SIDE}};
        for (int k = 0; k < 4; k++) {
            m->texel[2 * (4 * c + k)] = at[c][0] + corner[k][0];
            m->texel[2 * (4 * c + k) + 1] = at[c][1] + corner[k][1];
            m->position[3 * (4 * c + k)] = corner[k][0];
            m->position[3 * (4 * c + k) + 1] = corner[k][1];
        }
        uint32_t b = (uint32_t)(4 * c), tri[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        memcpy(m->triangle + 6 * c, tri, sizeof tri);
        m->chart_of[2 * c] = m->chart_of[2 * c + 1] = (uint32_t)c;
    }
    m->chart_count = charts;
    handmesh_finish(m);
    return m;
}

static void measure(double dx, double dy, int third, const uint8_t *skip, double *gap)
{
    char err[128];
    *gap = -1;
    texopt_mesh *m = squares(dx, dy, third);
    CHECK(m != NULL);
    CHECK_OK(texopt_chart_gap(m, m->texel, skip, gap, err, sizeof err), err);
    texopt_mesh_destroy(m);
}

static double gap_of(double dx, double dy, int third, const uint8_t *skip)
{
    double gap;
    measure(dx, dy, third, skip, &gap);
    return gap;
}

TEST(side_by_side_squares_are_their_offset_less_a_side_apart)
{
    CHECK_NEAR(gap_of(SIDE + 3, 0.5, 0, NULL), 3.0, 1e-12);
    CHECK_NEAR(gap_of(0.5, -(SIDE + 3), 0, NULL), 3.0, 1e-12);
}

TEST(corner_to_corner_squares_are_the_corners_distance_apart)
{
    CHECK_NEAR(gap_of(SIDE + 3, SIDE + 4, 0, NULL), 5.0, 1e-12);
}

TEST(touching_or_crossing_squares_are_zero_apart)
{
    CHECK_NEAR(gap_of(SIDE, 1, 0, NULL), 0.0, 1e-12);
    CHECK_NEAR(gap_of(1, 1, 0, NULL), 0.0, 1e-12);
}

TEST(a_far_third_chart_leaves_the_nearest_pair)
{
    CHECK_NEAR(gap_of(SIDE + 2, 0, 1, NULL), 2.0, 1e-12);
    uint8_t skip[3] = {0, 1, 0}; /* the near one left out: the third is the nearest */
    CHECK_NEAR(gap_of(SIDE + 2, 0, 1, skip), hypot(100 - SIDE, 100 - SIDE), 1e-9);
}

TEST(one_chart_left_is_infinitely_far_from_any_other)
{
    uint8_t skip[2] = {1, 0};
    CHECK(isinf(gap_of(SIDE + 2, 0, 0, skip)));
}
