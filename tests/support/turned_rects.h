/* turned_rects.h - a hand-built layout of rectangles, each turned by a given angle, for
 * tests of chart orientation and of the packing of turned charts.
 *
 * Does: one chart per rectangle (4 vertices, 2 counter-clockwise triangles), sides of
 * size / 16 to size texels from a seeded generator, turned about its first corner and placed
 * at random in [0, 8 size]^2; positions equal the texels (z = 0). Free with texopt_mesh_destroy.
 * Does not: weld or find charts through mesh.c (handmesh.h). */
#ifndef TEXOPT_TEST_TURNED_RECTS_H
#define TEXOPT_TEST_TURNED_RECTS_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"

/* turn: `charts` angles (radians, counter-clockwise); sides: 2 per chart, written (width,
 * height before the turn); aspect > 0 fixes height = width / aspect, 0 draws both sides.
 * NULL when memory runs out. */
texopt_mesh *turned_rects(size_t charts, const double *turn, double aspect, double size, double *sides, uint32_t seed);

#endif
