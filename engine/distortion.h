/* distortion.h - geometric distortion of a layout and flip counting.
 *
 * Symmetric Dirichlet energy of the map from the 3D surface to the layout (Sun et al. 2022,
 * eq. 24; Smith and Schaefer 2015): per triangle |J|_F^2 + |J^-1|_F^2 of the 2x2 Jacobian J
 * from the triangle in its own 3D plane to texel space, area-weighted (3D area) mean over the
 * counted triangles. The layout is first scaled uniformly so its total texel area equals the
 * total 3D area of the counted triangles: a pure change of texture resolution then costs
 * nothing, and the measure says how far the layout is from an isometry up to scale. The
 * minimum, 4, is reached by an isometric layout.
 *
 * Flip counting compares each triangle with its INPUT orientation (mesh->texel): a triangle
 * is flipped when det grad_phi <= 0, i.e. its new signed texel area has not the sign of its
 * input signed area (mirrored input charts are not flipped by being mirrored).
 *
 * Triangles flagged degenerate (3D or UV) are not counted by either measure. */
#ifndef TEXOPT_DISTORTION_H
#define TEXOPT_DISTORTION_H

#include <stddef.h>

#include "mesh.h"
#include "status.h"

typedef struct texopt_distortion {
    double symmetric_dirichlet; /* area-weighted mean, >= 4; 4 = isometric up to scale */
    double max_symmetric_dirichlet; /* worst triangle */
    size_t counted;             /* triangles that entered the measure */
    size_t flipped;             /* det grad_phi <= 0 relative to the input orientation */
} texopt_distortion;

/* Measures the layout `texel` (2 per mesh vertex; NULL = mesh->texel). Fails with
 * TEXOPT_E_INVALID_ARGUMENT when no triangle can be counted or the layout has zero area,
 * and with TEXOPT_E_NUMERIC on non-finite positions. A flipped or collapsed triangle has an
 * infinite energy; then symmetric_dirichlet is +inf (and `flipped` says why). */
texopt_status texopt_distortion_measure(const texopt_mesh *mesh, const double *texel,
                                        texopt_distortion *out, char *err, size_t err_len);

/* Number of non-degenerate triangles whose det grad_phi <= 0 relative to mesh->texel. */
size_t texopt_count_flipped(const texopt_mesh *mesh, const double *texel);

#endif
