/* tewari.h - baseline targets from the Hessian metric of Tewari, Snyder, Sander, Gortler and
 * Hoppe 2004, "Signal-Specialized Parameterization for Piecewise Linear Reconstruction".
 *
 * A piecewise-linear (or bilinear) reconstruction errs by about (1/8) h^2 |d^2 s/dx^2| along
 * a direction sampled every h: the error is governed by second derivatives, not by the
 * gradient that Sander's signal stretch looks at (a smooth ramp needs few texels, an edge
 * many). Per triangle, the metric M = mean over the triangle of sum_channels H^2 (H the
 * 2x2 Hessian of the texture in domain texel units; H^2 = H^T H shares H's eigenvectors with
 * the squared eigenvalues). Equalising the error gives spacing h ~ 1/sqrt|eig(H)|, i.e. a
 * per-direction scale lambda ~ |eig(H)|^(1/2) = eig(M)^(1/4), normalised as in ssp.h
 * (texopt_targets_from_metric: lambda in [lambda_min, 1], alpha = 0, wR = 0, wS = 1) and
 * solved by the same mesh-wise stage (Sun et al. 2022, section 5 baselines).
 *
 * Does not: solve, pack or bake. */
#ifndef TEXOPT_TEWARI_H
#define TEXOPT_TEWARI_H

#include "mesh.h"
#include "model.h"
#include "status.h"
#include "target.h"

/* Hessian metric per triangle into metric (3 doubles per triangle: m_xx, m_xy, m_yy). */
texopt_status texopt_tewari_metric(const texopt_model *model, const texopt_mesh *mesh, double *metric, char *err,
                                   size_t err_len);

/* Tewari targets; lambda_min in (0, 1] (0 -> 0.1); targets has mesh->triangle_count entries. */
texopt_status texopt_tewari_targets(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                    texopt_triangle_target *targets, char *err, size_t err_len);

/* Tewari targets from every map of the domain
 * (metric_maps.h: weighted by signal_weights, measured on up to `threads` workers): the
 * floor and candidate perceptual uses. */
texopt_status texopt_tewari_targets_every_map(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                              const double *signal_weights, int threads,
                                              texopt_triangle_target *targets, char *err, size_t err_len);

#endif
