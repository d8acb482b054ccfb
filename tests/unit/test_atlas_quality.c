/* test_atlas_quality.c - Liu et al. 2019's PE, BL and CN (engine/param/atlas_quality.c) on a
 * unit square of two triangles in 3D, laid out as one chart or cut along its diagonal, whose
 * values follow from the definitions by hand. */
#include <math.h>
#include <string.h>

#include "atlas_quality.h"
#include "handmesh.h"
#include "test.h"

/* The square (0,0,0)-(1,1,0) as triangles (p0 p1 p2) and (p0 p2 p3). With `cut`, the second
 * triangle has its own copies of p0 and p2 (a seam along the diagonal) and lies 12 texels to
 * the right of the first in the layout; else both share one layout, the square at 10 texels
 * a unit. */
static texopt_mesh *square(int cut)
{
    static const double corner[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    texopt_mesh *m = handmesh_alloc(cut ? 6 : 4, 2);
    for (int p = 0; p < 4; p++)
        memcpy(m->position + 3 * p, corner[p], sizeof corner[p]);
    static const uint32_t welded[6] = {0, 1, 2, 0, 2, 3}, split[6] = {0, 1, 2, 4, 5, 3};
    memcpy(m->triangle, cut ? split : welded, sizeof welded);
    for (int v = 0; v < 4; v++) {
        m->texel[2 * v] = 10 * corner[v][0];
        m->texel[2 * v + 1] = 10 * corner[v][1];
    }
    if (cut) {
        m->point_of[4] = 0, m->point_of[5] = 2;
        double copies[4] = {12, 0, 22, 10};
        memcpy(m->texel + 8, copies, sizeof copies);
        m->texel[6] += 12; /* p3 belongs to the second triangle only */
        m->chart_count = 2;
    }
    handmesh_finish(m);
    return m;
}

TEST(one_chart_fills_its_box_and_has_no_cut)
{
    texopt_mesh *m = square(0);
    texopt_atlas_quality q;
    char err[256] = "";
    CHECK_OK(texopt_atlas_quality_measure(m, NULL, &q, err, sizeof err), err);
    CHECK_NEAR(q.packing_efficiency, 1.0, 1e-12);
    CHECK_NEAR(q.boundary_length, 0.0, 1e-12); /* the square's border is no cut */
    CHECK_EQ_INT(q.charts, 1);
    /* Turned by 45 degrees the square fills half its box; the turn changes no cut. */
    double turned[8];
    for (int v = 0; v < 4; v++) {
        double x = m->texel[2 * v], y = m->texel[2 * v + 1];
        turned[2 * v] = (x - y) * sqrt(0.5) + 3;
        turned[2 * v + 1] = (x + y) * sqrt(0.5) - 7;
    }
    CHECK_OK(texopt_atlas_quality_measure(m, turned, &q, err, sizeof err), err);
    CHECK_NEAR(q.packing_efficiency, 0.5, 1e-12);
    CHECK_NEAR(q.boundary_length, 0.0, 1e-12);
    texopt_mesh_destroy(m);
}

TEST(a_seam_counts_its_3d_length_once_over_the_surface_diagonal)
{
    texopt_mesh *m = square(1);
    texopt_atlas_quality q;
    char err[256] = "";
    CHECK_OK(texopt_atlas_quality_measure(m, NULL, &q, err, sizeof err), err);
    /* Two triangles of 50 texels each in a box 22 x 10. */
    CHECK_NEAR(q.packing_efficiency, 100.0 / 220.0, 1e-12);
    /* The diagonal, sqrt 2 long, over the square's own diagonal: 1, not 2 (one cut, two sides). */
    CHECK_NEAR(q.boundary_length, 1.0, 1e-12);
    CHECK_EQ_INT(q.charts, 2);
    texopt_mesh_destroy(m);
}

TEST(a_layout_without_extent_is_refused)
{
    texopt_mesh *m = square(0);
    double flat[8] = {0, 0, 5, 0, 9, 0, 2, 0};
    texopt_atlas_quality q;
    char err[256] = "";
    CHECK(texopt_atlas_quality_measure(m, flat, &q, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "no extent") != NULL);
    texopt_mesh_destroy(m);
}
