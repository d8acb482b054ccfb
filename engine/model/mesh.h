/* mesh.h - the connectivity of one texture domain, in texel units.
 *
 * Built from a texopt_model domain. Vertices are UV vertices: model vertices with equal
 * position and equal UV are welded into one, so a vertex is split exactly where the UV
 * layout has a seam. Points are 3D vertices: all vertices with equal position share a
 * point, so one-rings cross UV seams. Charts are the connected components of triangles
 * through shared UV vertices. Model vertices no triangle uses are kept (every model vertex
 * of the domain maps to a mesh vertex, so new UVs can be written back to all of them); such a
 * vertex belongs to no chart and no triangle.
 *
 * Degenerate triangles (zero area in 3D or in texels) are flagged and carried through; the
 * stages leave them alone. A triangle is degenerate when its doubled area is at most 1e-10
 * times its longest edge squared (a relative test: a tiny but well-shaped triangle is not
 * degenerate; a sliver whose height is below ~1e-10 of its length is).
 *
 * Orientation: a chart's orientation (chart_sign) is the sign of the larger of its total
 * positive and total negative texel area (area-weighted majority; ties count as +1). The
 * sign alone is no verdict: texel space has v pointing down, so the ordinary charts of many
 * glTF models are negative. A chart mirrored against the others (a symmetric half) simply
 * has the other sign, and no flipped triangle.
 *
 * FLIPPED marks fold-overs. Orientation patches are the triangles joined through shared UV
 * edges with equal orientation. A triangle is FLIPPED when it is not degenerate in UV, its
 * orientation is opposite to its chart's, and its patch holds less than 20% of the chart's
 * texel area. Mirrored halves welded at their mirror line (equal UVs there) form one chart
 * with two large patches of opposite orientation: that is a mirror, not a flip, and neither
 * half is FLIPPED (their texels overlap: coverage.h reports it). Stages that need "the input
 * orientation" of a triangle use the sign of area_texel.
 *
 * Built in texopt_mesh_create from exact float equality (what glTF exporters produce; -0 and
 * +0 are equal), with hash maps: linear time (about 0.05 s for 130k triangles, 0.5 s for a
 * million). */
#ifndef TEXOPT_MESH_H
#define TEXOPT_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "model.h"
#include "status.h"

enum texopt_triangle_flag {
    TEXOPT_TRI_DEGENERATE_3D = 1u << 0,
    TEXOPT_TRI_DEGENERATE_UV = 1u << 1,
    TEXOPT_TRI_FLIPPED = 1u << 2,  /* a fold-over: reversed against its chart, in a small
                                      orientation patch (see above) */
    TEXOPT_TRI_OVERLAPS = 1u << 3, /* covers a texel another triangle covers too (or itself
                                      again through REPEAT); neighbours sharing an edge never
                                      do. Set by texopt_coverage_measure (coverage.h) */
    TEXOPT_TRI_WRAPPED = 1u << 4   /* some UV outside [0,1] by more than 1e-3 texel: relies on
                                      the wrap mode */
};

typedef struct texopt_mesh {
    int domain;                 /* index into the model's domains */
    int width, height;          /* texel frame of the domain */
    texopt_wrap wrap_s, wrap_t; /* the domain's wrap modes (how UVs outside [0,1] read) */

    size_t vertex_count;
    double *texel;      /* 2 per vertex: (width * u, height * v) */
    uint32_t *point_of; /* per vertex: its welded 3D point */
    size_t model_vertex_count;
    uint32_t *model_vertex;           /* per vertex: one model vertex it came from */
    uint32_t *vertex_of_model_vertex; /* per model vertex of the domain (in the order of the
                                         domain's primitives): its mesh vertex */

    size_t point_count;
    double *position; /* 3 per point, world space */

    size_t triangle_count;
    uint32_t *triangle;       /* 3 per triangle, vertex indices */
    uint32_t *model_triangle; /* per triangle: model triangle index */
    double *area_3d;          /* per triangle, world units squared */
    double *area_texel;       /* per triangle, signed, texels */
    uint8_t *flags;           /* per triangle, texopt_triangle_flag bits */

    size_t chart_count;
    uint32_t *chart_of;          /* per triangle; charts numbered in order of first triangle */
    int8_t *chart_sign;          /* per chart: +1 or -1, its dominant orientation (see above) */
    uint8_t *vertex_on_boundary; /* per vertex: 1 when on an edge used by one triangle only
                                    (a chart boundary, which includes both sides of a seam) */

    uint32_t *point_triangle_start; /* point_count + 1 offsets into point_triangle */
    uint32_t *point_triangle;       /* triangles around each point (CSR) */
} texopt_mesh;

/* The welded 3D point (3 doubles, world space) of mesh vertex `vertex`. */
static inline const double *texopt_mesh_vertex_point(const texopt_mesh *mesh, uint32_t vertex)
{
    return mesh->position + 3 * (size_t)mesh->point_of[vertex];
}

/* Whether the texel triangle (a, b, c) (2 doubles each) is degenerate by the relative test
 * above: what TEXOPT_TRI_DEGENERATE_UV says of a mesh's own layout, for any layout. */
int texopt_texel_triangle_degenerate(const double *a, const double *b, const double *c);

/* The texel area of the layout texel (2 doubles per vertex), degenerate triangles counting
 * nothing (they cover nothing, coverage.h); with paid (per triangle, may be NULL: 1 each)
 * a triangle counts only its paid share, so mirrored twins laid on one region are not
 * taken for twice the texels. */
double texopt_layout_area(const texopt_mesh *mesh, const double *texel, const double *paid);

/* The columns of P are the edges b - a and c - a of triangle t (vertices a, b, c) in an
 * orthonormal frame of its 3D plane with x along b - a: P is upper triangular with a positive
 * diagonal. Returns -1 (P not meaningful) when the triangle has no area, else 0. */
int texopt_mesh_plane_edges(const texopt_mesh *mesh, size_t t, double P[2][2]);

/* Builds the mesh of domain `domain` of `model`. On success the caller owns *out and frees it
 * with texopt_mesh_destroy. */
texopt_status texopt_mesh_create(texopt_mesh **out, const texopt_model *model, int domain, char *err, size_t err_len);

void texopt_mesh_destroy(texopt_mesh *mesh);

/* Writes the triangles of the one-ring of `triangle` (every triangle sharing a 3D point with
 * it, through UV seams), `triangle` itself first, into out[0..cap). Returns the full count,
 * which may exceed cap (then only cap are written). */
size_t texopt_mesh_one_ring(const texopt_mesh *mesh, uint32_t triangle, uint32_t *out, size_t cap);

#endif
