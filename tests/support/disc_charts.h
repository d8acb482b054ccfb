/* disc_charts.h - generated round charts (discs and annuli), for tests of how charts are
 * reshaped and packed: a disc fills pi/4 of its bounding box, which a packer that only
 * translates and makes quarter turns cannot beat by placement alone.
 * Does not: weld across charts or give the charts 3D shape (the 3D positions are the texel
 * positions scaled down). */
#ifndef TEXOPT_TEST_DISC_CHARTS_H
#define TEXOPT_TEST_DISC_CHARTS_H

#include "mesh.h"

/* `count` charts of radius 40 texels, 100 texels apart along x: with hole <= 0 a disc of
 * `rings` rings of `segments` vertices around a centre vertex (vertex 0 of each chart),
 * otherwise an annulus from radius `hole` whose inner ring comes first. Triangles are
 * counter-clockwise. NULL when memory runs out. Free with texopt_mesh_destroy. */
texopt_mesh *disc_charts(int count, int rings, int segments, double hole);

#endif
