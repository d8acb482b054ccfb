/* param_tutte.h - Tutte's barycentric embedding with Floater's mean-value weights.
 *
 * Floater 2003, "Mean value coordinates"; Tutte 1963: every interior vertex is the weighted
 * mean of its neighbours, the boundary is fixed on a convex polygon. With positive weights
 * (mean-value weights are positive for any 3D one-ring) the layout of a disk is a bijection
 * (Tutte, Floater): no triangle flips. The mean-value weights reproduce a planar chart whose
 * boundary is fixed where it lies. The square parameterization (param_square.h) reuses the
 * interior solve with its own boundary. */
#ifndef TEXOPT_PARAM_TUTTE_H
#define TEXOPT_PARAM_TUTTE_H

#include "param_chart.h"
#include "status.h"

/* Lays out the disk `chart` with its boundary on a circle (by 3D arc length, counter-
 * clockwise, circumference = boundary length): writes 2 doubles per vertex into uv
 * (caller-owned, 2 * vertex_count). */
texopt_status texopt_param_tutte(const texopt_param_chart *chart, double *uv, char *err, size_t err_len);

/* Solves for the interior vertices of `chart` with its boundary vertices held at their
 * entries of uv; interior entries are written. divisor (NULL = all 1) divides the weight of
 * every edge ij by divisor[j], the reweighting of Yoshizawa et al. 2004. */
texopt_status texopt_param_embed_interior(const texopt_param_chart *chart, const texopt_param_boundary *boundary,
                                          const double *divisor, double *uv, char *err, size_t err_len);

#endif
