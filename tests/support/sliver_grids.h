/* sliver_grids.h - textured grids whose UV layout holds a strip of zero-area or sliver
 * triangles, and mirrored twins of them, for the tests of stage 2, the layout check and the
 * pipeline (issue 37: exporters map faces to one texel line).
 *
 * Does: an n x n grid of quads over [0,1]^2 in 3D (z = 0, every triangle of 3D area
 * 1 / (2 n^2)), its UVs inside [0.05, 0.95]^2, the row of quads between vertex rows n / 2
 * and n / 2 + 1 (the strip: triangles strip_first .. strip_first + 2 n - 1) squeezed in v to
 * `strip_height` of a row (0: every strip triangle has zero UV area, its three corners on one
 * texel line, none coincident; the rows above are shifted by half a column so that no two
 * strip corners share a UV). Every other triangle has positive UV area, counter-clockwise.
 * With twins, a second copy at x + 1.5 in 3D is mapped on the same UVs mirrored in u (u ->
 * 1 - u): the copy's triangles (from index 2 n^2) lie on the first one's texels with the
 * opposite orientation, a separate chart as mirrored parts of game assets are.
 * Does not: write files or build models (grid_glb.h, fixtures.h take the arrays). */
#ifndef TEXOPT_TEST_SLIVER_GRIDS_H
#define TEXOPT_TEST_SLIVER_GRIDS_H

#include <stddef.h>
#include <stdint.h>

typedef struct sliver_grid {
    float *positions;    /* 3 per vertex */
    float *uvs;          /* 2 per vertex */
    uint32_t *triangles; /* 3 per triangle */
    size_t vertex_count, triangle_count;
    size_t strip_first, strip_count; /* the first copy's strip triangles */
    size_t copy_triangles;           /* triangles per copy (2 n^2) */
} sliver_grid;

/* n even, >= 4; strip_height in [0, 1). Returns 0, or -1 (bad argument, no memory). */
int sliver_grid_make(sliver_grid *g, int n, double strip_height, int twins);

/* Whether triangle t is a strip triangle of either copy. */
int sliver_grid_in_strip(const sliver_grid *g, size_t t);

void sliver_grid_free(sliver_grid *g);

#endif
