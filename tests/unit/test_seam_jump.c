/* test_seam_jump.c - the texture's jump across an input seam (engine/param/seam_jump.c).
 *
 * Two triangles share a 3D edge; the second reads the texture through its own UVs. An
 * image of two flat halves (0.2 left, 0.7 right): the jump is 0 when both sides lie in one
 * half, 0.5 when they lie in different halves, and 0 where the two share the edge's texel
 * corners (no seam). */
#include <math.h>
#include <stdlib.h>

#include "handmesh.h"
#include "image.h"
#include "seam_jump.h"
#include "test.h"

/* Triangles 0 = (0, 1, 2) and 1 = (3, 4, 5), vertices 3 and 4 on the points of 1 and 0
 * (points are vertex ids): they share that 3D edge; in texels triangle 1 lies across the
 * edge from triangle 0, shifted by (dx, 0), so the edge reads the image at x + dx there. */
static texopt_mesh *seam_pair(double dx)
{
    texopt_mesh *m = handmesh_alloc(6, 2);
    if (!m)
        return NULL;
    static const double xyz[6][3] = {{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}};
    static const uint32_t point[6] = {0, 1, 2, 1, 0, 5};
    static const double texel[6][2] = {{64, 64}, {64, 192}, {16, 64}, {64, 192}, {64, 64}, {112, 64}};
    for (uint32_t v = 0; v < 6; v++) {
        m->point_of[v] = point[v];
        m->triangle[v] = v;
        m->texel[2 * v] = texel[v][0] + (v >= 3 ? dx : 0);
        m->texel[2 * v + 1] = texel[v][1];
        for (int a = 0; a < 3; a++)
            m->position[3 * v + (uint32_t)a] = xyz[v][a];
    }
    handmesh_finish(m);
    return m;
}

/* 256 x 256, 3 channels: 0.2 where x < 128, 0.7 beyond. */
static int halves(texopt_image *img)
{
    char err[64];
    if (texopt_image_create(img, 256, 256, 3, err, sizeof err) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < 256; y++)
        for (int x = 0; x < 256; x++)
            for (int c = 0; c < 3; c++)
                texopt_image_at(img, x, y)[c] = x < 128 ? 0.2f : 0.7f;
    return 0;
}

TEST(the_jump_is_what_each_side_reads)
{
    texopt_image img = {0};
    CHECK(halves(&img) == 0);
    texopt_mesh *same = seam_pair(8), *across = seam_pair(128), *joined = seam_pair(0);
    CHECK(same && across && joined);
    if (same && across && joined && img.pixels) {
        CHECK_NEAR(texopt_seam_jump(same, &img, 0, 1), 0, 1e-6);
        CHECK_NEAR(texopt_seam_jump(across, &img, 0, 1), 0.5, 1e-6);
        CHECK_NEAR(texopt_seam_jump(across, &img, 1, 0), 0.5, 1e-6);
        /* one vertex list: the edge's texel corners are shared, no seam */
        joined->triangle[3] = 1;
        joined->triangle[4] = 0;
        CHECK_NEAR(texopt_seam_jump(joined, &img, 0, 1), 0, 0);
    }
    texopt_mesh_destroy(same);
    texopt_mesh_destroy(across);
    texopt_mesh_destroy(joined);
    texopt_image_destroy(&img);
}
