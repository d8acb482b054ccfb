/* axis_angles.h - target polar angles of an axis-aligned chart (Liu et al. 2019, 3.1.1).
 *
 * First step of atlas refinement with bounded packing efficiency ("Atlas Refinement with
 * Bounded Packing Efficiency", Liu, Ye, Fu, Liu 2019, section 3.1.1): for one chart's
 * boundary loop, the integer polar angle Theta_i (in quarter turns) each boundary edge is to
 * be turned to, so that the chart becomes axis-aligned without a fold-over:
 *  - the edge directions are smoothed along the boundary (eq. 3, 4: a Gaussian of
 *    sigma = 0.004 of the boundary length, at most 5 passes, a direction kept when its
 *    smoothed one turns by more than 90 degrees), updating the interior angles;
 *  - one rotation makes the smoothed directions as axis-aligned as possible (eq. 5, sum of
 *    l_i x^2 y^2); the energy is a function of one angle with period 90 degrees, so it is
 *    minimised by 720 samples and a golden-section search, not L-BFGS;
 *  - each direction is snapped to its closest axis (eq. 6), giving integer corner turns
 *    K_i = 2 - alpha_i / (pi / 2) with sum 4; corners with K_i > 1 (an interior angle of 0
 *    or less: a fold-over) are split onto K_i - 1 neighbouring non-corner vertices;
 *  - Theta follows from the start edge (the one closest to its axis) by Theta_{i+1} =
 *    Theta_i + K_i (eq. 2).
 * Not here: the deformation that turns the edges to these angles (axis_deform.h, 3.1.2);
 * still to do (issue 40): the flattening, rectangle decomposition, packing and distortion
 * reduction, and the corner-reduction tweaks of the paper's supplementary material. */
#ifndef TEXOPT_AXIS_ANGLES_H
#define TEXOPT_AXIS_ANGLES_H

#include <stddef.h>

#include "status.h"

typedef struct texopt_axis_angles {
    double rotation; /* radians, applied (counter-clockwise) to the chart before Theta holds */
    int *theta;      /* per edge i (from point i to point i + 1): target polar angle / (pi/2) */
    int *turn;       /* per point i + 1 (between edges i and i + 1): K, in {..., -1, 0, 1} */
    size_t count;    /* edges = points */
    size_t start;    /* the start edge */
} texopt_axis_angles;

/* Target angles of the closed counter-clockwise boundary loop xy (count points, 2 each,
 * no repeated first point). Fails on fewer than 4 points, a zero-length edge or a loop
 * whose turns do not add up to one counter-clockwise turn (not a simple CCW loop). out is
 * owned by the caller on success (texopt_axis_angles_destroy). */
texopt_status texopt_axis_angles_compute(const double *xy, size_t count, texopt_axis_angles *out, char *err,
                                         size_t err_len);

void texopt_axis_angles_destroy(texopt_axis_angles *a);

#endif
