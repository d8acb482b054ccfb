/* axis_deform.h - angle-driven deformation toward an axis-aligned chart (Liu et al. 2019, 3.1.2).
 *
 * Given one chart (counter-clockwise triangles), its boundary loop and the target polar
 * angles of axis_angles.h, moves the chart's vertices to minimise eq. 10,
 *   E_d + lambda E_align,  det J > 0 for every triangle,
 * with E_d the symmetric Dirichlet energy (eq. 9) RELATIVE TO THE GIVEN LAYOUT rest (not
 * the 3D surface: the layout's texel allocation is what is to be kept) and E_align the
 * boundary alignment energy of eq. 8 (gamma 0.3): each boundary edge's polar angle, tracked
 * continuously so an edge turns one way only, pulled to (pi/2) Theta_i, its length to its
 * rest length. Algorithm 1: lambda starts at E_d / E_align, each round minimises by L-BFGS
 * (5 pairs) with a line search whose largest step keeps every determinant positive, and
 * lambda grows 6 times per round until every edge is within 0.1 rad of its target or 10
 * rounds ran. The chart is first turned by the angles' rotation.
 * Not here: the flattening to an exactly axis-aligned boundary (Fu et al. 2016), and
 * everything after it (rectangle decomposition, packing, distortion reduction). */
#ifndef TEXOPT_AXIS_DEFORM_H
#define TEXOPT_AXIS_DEFORM_H

#include <stddef.h>
#include <stdint.h>

#include "axis_angles.h"
#include "status.h"

typedef struct texopt_axis_deform_report {
    int rounds;             /* lambda rounds run */
    double max_angle_error; /* radians, largest |theta_i - (pi/2) Theta_i| at the end */
    double distortion;      /* E_d at the end (1 = the rest layout's shape everywhere) */
} texopt_axis_deform_report;

/* rest: 2 per vertex, the given layout (every triangle counter-clockwise in it); loop: the
 * boundary's vertex indices, counter-clockwise, loop_count = angles->count (the angles of
 * the loop's points at rest). xy (2 per vertex) receives the deformed chart. report may be
 * NULL. */
texopt_status texopt_axis_deform(size_t vertex_count, const double *rest, size_t triangle_count,
                                 const uint32_t *triangle, const uint32_t *loop, const texopt_axis_angles *angles,
                                 double *xy, texopt_axis_deform_report *report, char *err, size_t err_len);

#endif
