/* handmesh.h - texopt_mesh structs filled by hand, for tests that must control a layout
 * exactly (texel positions, 3D positions, charts) without going through a glTF model.
 *
 * handmesh_alloc gives zeroed arrays for the fields the layout stages read (texel,
 * point_of, position, triangle, area_3d, area_texel, flags, chart_of), every vertex its own
 * point, one chart, a 256 x 256 frame; the test fills texel, position and triangle, then
 * handmesh_finish derives areas and flags as mesh.h documents them. Free with
 * texopt_mesh_destroy. Does not: weld, build one-rings or find charts (mesh.c does). */
#ifndef TEXOPT_TEST_HANDMESH_H
#define TEXOPT_TEST_HANDMESH_H

#include <stddef.h>
#include <stdint.h>

#include "mesh.h"

/* NULL when memory runs out. */
texopt_mesh *handmesh_alloc(size_t vertex_count, size_t triangle_count);

/* Twice the signed area of triangle t (3 indices) over points p with `stride` doubles each
 * (the first two used): positive for counter-clockwise corners. */
double handmesh_doubled_area(const double *p, const uint32_t *t, int stride);

/* Barycentric weights of input texel point p in triangle t (mesh->texel); 1 when p is
 * inside it (weights >= -1e-9). */
int handmesh_barycentric(const texopt_mesh *m, size_t t, const double p[2], double w[3]);

/* area_3d (true 3D area), area_texel (signed) and the DEGENERATE_3D / DEGENERATE_UV /
 * FLIPPED flags of every triangle. */
void handmesh_finish(texopt_mesh *m);

#endif
