/* param_chart.h - the input of the parameterization methods (param_*.h): one disk chart.
 *
 * A chart is triangles over 3D vertices, nothing else: the methods make UVs, so the chart
 * carries none (texopt_mesh of mesh.h is the wrong shape: its vertices are the input's UV
 * vertices of a whole texture domain). The caller owns all arrays. A chart is a disk when
 * every vertex is used, every edge has one or two triangles with consistent orientation, and
 * the boundary edges form one simple loop (Euler characteristic 1). This module checks that,
 * finds the boundary edges (of any triangles) and orders a disk's into its loop, measures
 * the L2/Linf stretch of a layout of the chart and runs the pinned least-squares solve LSCM
 * and ABF share; the methods are in param_*.h. */
#ifndef TEXOPT_PARAM_CHART_H
#define TEXOPT_PARAM_CHART_H

#include <stddef.h>
#include <stdint.h>

#include "sparse_spd.h"
#include "status.h"

#define TEXOPT_PI 3.14159265358979323846

typedef struct texopt_param_chart {
    size_t vertex_count;
    const double *position; /* 3 per vertex */
    size_t triangle_count;
    const uint32_t *triangle; /* 3 per triangle, counter-clockwise seen from the front */
} texopt_param_chart;

/* The boundary loop of a disk chart, in the orientation of its triangles (a layout with the
 * loop counter-clockwise has its triangles counter-clockwise). */
typedef struct texopt_param_boundary {
    size_t count;
    uint32_t *vertex;     /* count vertices, in loop order */
    double *arc;          /* count + 1: 3D arc length from vertex[0]; arc[count] = length */
    uint8_t *on_boundary; /* per chart vertex */
} texopt_param_boundary;

/* Checks that `chart` is a disk and finds its boundary. On success the caller frees *out
 * with texopt_param_boundary_destroy. Fails with TEXOPT_E_INVALID_ARGUMENT naming what is
 * wrong (index out of range, unused vertex, non-manifold edge, holes, closed surface, zero
 * area triangle). */
texopt_status texopt_param_boundary_create(texopt_param_boundary **out, const texopt_param_chart *chart, char *err,
                                           size_t err_len);
void texopt_param_boundary_destroy(texopt_param_boundary *boundary);

/* The edges that only one of `triangle_count` triangles (3 vertex indices each, any mesh,
 * not only a disk) uses, in triangle order, each directed as its triangle lists it: edge
 * e runs from (*edge)[2 e] to (*edge)[2 e + 1]. An edge of three or more triangles is not
 * one of them. On success the caller frees *edge (*count edges); fails only on no memory. */
texopt_status texopt_param_boundary_edges(const uint32_t *triangle, size_t triangle_count, uint32_t **edge,
                                          size_t *count, char *err, size_t err_len);

/* Triangles of the layout uv (2 per vertex) that are not counter-clockwise (flipped or
 * collapsed). */
size_t texopt_param_flips(const texopt_param_chart *chart, const double *uv);

/* Whether the layout's boundary loop crosses itself (touching at an end point does not
 * count): a disk laid out without flips is a bijection onto its boundary's inside exactly
 * when it does not (ABF and LSCM are only locally injective; a long curved chart can wrap
 * onto itself). Quadratic in the boundary's length. */
int texopt_param_boundary_crosses(const texopt_param_boundary *boundary, const double *uv);

/* The corner angles (radians) of triangle t in 3D, at its vertices 0, 1, 2. */
void texopt_param_corner_angles(const texopt_param_chart *chart, size_t t, double angle[3]);

/* The 3D edge lengths of triangle t: opposite its vertices 0, 1, 2. */
void texopt_param_edge_lengths(const texopt_param_chart *chart, size_t t, double length[3]);

/* Texture stretch of Sander et al. 2001 of the layout `uv` (2 per vertex): the singular
 * values G >= g of the Jacobian from the layout to the surface; per triangle
 * L2 = sqrt((G^2 + g^2) / 2), Linf = G. `l2` is the 3D-area-weighted root mean square and
 * `linf` the maximum, both after scaling the layout to the chart's 3D area (so an isometry up
 * to scale measures 1). A collapsed or flipped (clockwise) layout triangle is infinite.
 * `per_vertex_l2`, when not NULL, receives per vertex the root mean square over its
 * triangles (what Yoshizawa et al. 2004 reweight by). Returns -1 when the layout has no area. */
int texopt_param_stretch(const texopt_param_chart *chart, const double *uv, double *l2, double *linf,
                         double *per_vertex_l2);

/* Adds the least-squares row sum_n coef[n] * uv[vertex[n]][axis[n]] = 0 (n < 8) over the
 * layout's unknowns: var[v] >= 0 numbers the free vertices (unknowns 2 var + axis), var[v] < 0
 * marks v pinned at its entries of uv (moved to the right side). */
texopt_status texopt_param_add_layout_row(texopt_spd *spd, const int64_t *var, const double *uv, const uint32_t *vertex,
                                          const int *axis, const double *coef, int n);

/* The rows triangle t adds to a layout system (see texopt_param_solve_pinned). */
typedef texopt_status (*texopt_param_rows_fn)(texopt_spd *spd, const void *context, size_t t, const int64_t *var,
                                              const double *uv);

/* Least-squares layout with vertex pin[0] held at (0, 0) and pin[1] at (d, 0), d their 3D
 * distance; every triangle adds its rows through add_rows (texopt_param_add_layout_row).
 * Writes 2 doubles per vertex into uv. */
texopt_status texopt_param_solve_pinned(const texopt_param_chart *chart, const uint32_t pin[2],
                                        texopt_param_rows_fn add_rows, const void *context, double *uv, char *err,
                                        size_t err_len);

#endif
