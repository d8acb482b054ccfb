/* triangulate.h - constrained triangulation of a planar straight-line graph.
 *
 * Incremental Delaunay insertion (Lawson flips) inside a large enclosing triangle, then each
 * segment recovered by flipping the edges it crosses (Sloan 1993), then the enclosing
 * triangle's corners removed. The result triangulates the convex hull of the points and
 * contains every segment as an edge; it is Delaunay away from the segments but not
 * re-made Delaunay after their recovery (a constrained, not a constrained Delaunay,
 * triangulation). Every triangle gets its depth: the fewest segments a path from outside
 * the hull crosses to reach it, so nested regions bounded by segments are told apart.
 * Does not: add Steiner points, accept coincident points or a segment through a third point
 * (both are errors), or use exact predicates (inputs are texel positions, not adversarial). */
#ifndef TEXOPT_TRIANGULATE_H
#define TEXOPT_TRIANGULATE_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

typedef struct texopt_triangulation {
    uint32_t *triangle; /* 3 point indices per triangle, counter-clockwise */
    int *depth;         /* per triangle: segments crossed from outside the hull (hull = 1
                           when the hull's edges are segments, else 0) */
    size_t triangle_count;
} texopt_triangulation;

/* Triangulates points xy (2 per point) with the segments (2 point indices each) as edges.
 * Fails with TEXOPT_E_INVALID_ARGUMENT on coincident points, fewer than 3 non-collinear
 * points, a segment through another point, or segments that cross. out is zeroed first
 * and owned by the caller (texopt_triangulation_destroy) on success. */
texopt_status texopt_triangulate(const double *xy, size_t point_count, const uint32_t *segment, size_t segment_count,
                                 texopt_triangulation *out, char *err, size_t err_len);

void texopt_triangulation_destroy(texopt_triangulation *t);

#endif
