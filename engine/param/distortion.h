/* distortion.h - geometric distortion of a layout and flip counting.
 *
 * The metrics of the parameterization lecture (../shared/papers/lecture-mesh-
 * parameterization.txt), each a function of the singular values smax >= smin of the Jacobian
 * J from a triangle in its 3D plane to the layout: conformal smax/smin (Degener et al. 2003),
 * MIPS smax/smin + smin/smax (Hormann and Greiner 2000), isometric sqrt(smax^2 + smin^-2)
 * (Aigerman et al. 2014), maximal isometric max(smax, 1/smin) (Sorkine et al. 2002), area
 * max(det J, 1/det J), symmetric Dirichlet, and the texture stretch of Sander et al. 2001 of
 * the inverse map (layout to surface, singular values 1/smin >= 1/smax): L2 sqrt((smin^-2 +
 * smax^-2) / 2) and Linf 1/smin. Each is minimal (1, 2, sqrt 2, 1, 1, 4, 1, 1) for an
 * isometry.
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
#include <stdint.h>

#include "mesh.h"
#include "status.h"

/* The metrics of one triangle (see above); all +inf when det J <= 0. */
typedef struct texopt_triangle_distortion {
    double sigma_max, sigma_min;
    double conformal, mips, isometric, max_isometric, area, symmetric_dirichlet;
    double l2_stretch, linf_stretch;
} texopt_triangle_distortion;

/* A metric over a layout: 3D-area-weighted mean (for L2 stretch the root mean square of
 * Sander et al., their L2 norm) and worst triangle. */
typedef struct texopt_distortion_stat {
    double mean, max;
} texopt_distortion_stat;

typedef struct texopt_distortion {
    double symmetric_dirichlet;     /* area-weighted mean, >= 4; 4 = isometric up to scale */
    double max_symmetric_dirichlet; /* worst triangle */
    texopt_distortion_stat conformal, mips, isometric, max_isometric, area;
    texopt_distortion_stat l2_stretch, linf_stretch;
    size_t counted; /* triangles that entered the measure */
    size_t flipped; /* det grad_phi <= 0 relative to the input orientation */
} texopt_distortion;

/* Measures the layout `texel` (2 per mesh vertex; NULL = mesh->texel). Fails with
 * TEXOPT_E_INVALID_ARGUMENT when no triangle can be counted or the layout has zero area,
 * and with TEXOPT_E_NUMERIC on non-finite positions. A flipped or collapsed triangle has an
 * infinite energy; then symmetric_dirichlet and every other metric is +inf (and `flipped`
 * says why). The frame of the 3D plane has no orientation relative to texel space, so the
 * metrics use |det J|; orientation is what `flipped` judges. */
texopt_status texopt_distortion_measure(const texopt_mesh *mesh, const double *texel, texopt_distortion *out, char *err,
                                        size_t err_len);

/* The columns of T are the layout edges of triangle tri (2 per vertex in `layout`). */
void texopt_layout_edges(const double *layout, const uint32_t tri[3], double T[2][2]);

/* J = scale * T P^-1: the Jacobian from the 3D plane frame to the layout. */
void texopt_jacobian(const double T[2][2], const double P[2][2], double scale, double J[2][2]);

/* The lecture's metrics of one triangle from its Jacobian. */
void texopt_triangle_distortion_of(const double J[2][2], texopt_triangle_distortion *out);

/* The metrics as JSON: {"counted", "flipped", and per metric {"mean", "max"}} under the
 * names symmetric_dirichlet, conformal, mips, isometric, max_isometric, area, l2_stretch,
 * linf_stretch; an infinite value is null. NULL when out of memory. */
struct cJSON *texopt_distortion_json(const texopt_distortion *d);

/* Number of non-degenerate triangles whose det grad_phi <= 0 relative to mesh->texel. */
size_t texopt_count_flipped(const texopt_mesh *mesh, const double *texel);

#endif
