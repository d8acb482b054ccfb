/* param_grids.h - generated disk charts with known answers for the parameterization tests
 * (tests/unit/test_param_*.c): an n x n grid of the unit square lifted into 3D by a shape,
 * and the checks those tests share (flips, best similarity fit). */
#ifndef TEXOPT_PARAM_GRIDS_H
#define TEXOPT_PARAM_GRIDS_H

#include <stddef.h>
#include <stdint.h>

#include "param_chart.h"

typedef enum param_shape {
    SHAPE_TILTED_PLANE, /* planar, rotated out of the xy plane */
    SHAPE_CYLINDER,     /* rolled about the y axis: developable (every grid quad is planar) */
    SHAPE_BUMP          /* a Gaussian bump: curved, not developable */
} param_shape;

typedef struct param_grid {
    texopt_param_chart chart;
    double *position;
    uint32_t *triangle;
    double *plane;                 /* 2 per vertex: the grid point (x, y) in the unit square */
    uint32_t vertex_of_grid_start; /* the vertex numbering is rotated by this (see below) */
} param_grid;

/* (n + 1)^2 vertices, 2 n^2 counter-clockwise triangles, every corner in two of them. Interior points are jittered
 * (only along y for the cylinder, which keeps every quad planar); the boundary is not.
 * Vertex indices are rotated by `shift` (grid point g becomes vertex (g + nv - shift) % nv),
 * so the boundary loop need not start at a corner. */
param_grid *param_grid_create(int n, param_shape shape, uint32_t shift);
void param_grid_destroy(param_grid *grid);

/* Triangles whose layout is not counter-clockwise (signed area <= 0). */
size_t param_layout_flips(const texopt_param_chart *chart, const double *uv);

/* Fits uv ~ s R p + t (a similarity, p = the grid's plane points) in least squares; returns
 * the largest residual and writes the scale s. */
double param_similarity_residual(const param_grid *grid, const double *uv, double *scale);

#endif
