/* ssp.h - baseline targets from the signal-stretch metric (Sander, Gortler, Snyder, Hoppe
 * 2002, "Signal-Specialized Parametrization"), for the mesh-wise solver (meshwise.h).
 *
 * Per triangle, the signal-stretch metric tensor M = mean over the triangle of
 * sum_channels grad s grad s^T, with s the base colour texture (R, G, B; a grey texture its
 * one channel) and the gradient in texel units of the domain frame. Its eigenvectors are the
 * directions in which the signal changes fastest and slowest; a layout that spends texels
 * where the signal changes (Sander's signal stretch, "SSPOP" in Sun et al. 2022, section 5)
 * scales each direction by sqrt(eigenvalue): the signal then changes at the same rate per
 * output texel everywhere. texopt_targets_from_metric turns any such tensor into targets
 * (Tewari's Hessian metric uses it too, tewari.h).
 *
 * Targets (target.h): J = V(beta) diag(lambda1, lambda2) V(beta)^T with lambda in
 * [lambda_min, 1], the largest per-direction scale of the domain (98th percentile, so one
 * outlier does not shrink everything) mapped to 1, alpha = 0, w_rotation = 0, w_stretch = 1.
 * Degenerate triangles get J = I with zero weights. A signal with no variation anywhere
 * (a flat texture) gives lambda = 1 everywhere. Scaling to the budget is the budget's job:
 * targets only fix the relative allocation, as the perceptual stage's do.
 *
 * Does not: solve for the layout (meshwise.h), pack or bake. */
#ifndef TEXOPT_SSP_H
#define TEXOPT_SSP_H

#include "mesh.h"
#include "model.h"
#include "status.h"
#include "target.h"

/* Per-triangle symmetric 2x2 tensors, 3 doubles per triangle (m_xx, m_xy, m_yy), in domain
 * texel units, to targets: lambda_k = (eigenvalue_k)^exponent, normalised as above.
 * lambda_min in (0, 1] (0 -> 0.1). targets has mesh->triangle_count entries. */
texopt_status texopt_targets_from_metric(const texopt_mesh *mesh, const double *metric, double exponent,
                                         double lambda_min, texopt_triangle_target *targets, char *err, size_t err_len);

/* The base colour image of the mesh's domain (the first image of the domain, which is the
 * base colour binding when there is one), or NULL when it was not decoded. */
const texopt_image *texopt_domain_signal_image(const texopt_model *model, const texopt_mesh *mesh);

/* Adds to m[3] the tensor of the signal at image position (x, y) (image texels);
 * (sx, sy) convert image texels to domain texels (domain = sx * image along x). */
typedef void (*texopt_signal_probe)(const texopt_image *img, texopt_wrap wrap_s, texopt_wrap wrap_t, double x, double y,
                                    double sx, double sy, double m[3]);

/* Mean of probe over each triangle of the mesh (the centroids of its regular subdivision
 * into about one-texel pieces, at most 32 x 32) into metric (3 doubles per triangle; zeros
 * for degenerate triangles). Fails when the domain's base colour image was not decoded. */
texopt_status texopt_signal_metric(const texopt_model *model, const texopt_mesh *mesh, texopt_signal_probe probe,
                                   double *metric, char *err, size_t err_len);

/* texopt_signal_metric of image img (any decoded image of the mesh's domain) instead of the
 * base colour's. Cannot fail. */
texopt_status texopt_signal_metric_of(const texopt_model *model, const texopt_mesh *mesh, const texopt_image *img,
                                      texopt_signal_probe probe, double *metric);

/* Signal-stretch metric per triangle into metric (3 doubles per triangle). */
texopt_status texopt_ssp_metric(const texopt_model *model, const texopt_mesh *mesh, double *metric, char *err,
                                size_t err_len);

/* SSP targets (exponent 1/2 of the signal-stretch metric). */
texopt_status texopt_ssp_targets(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                 texopt_triangle_target *targets, char *err, size_t err_len);

/* SSP targets from every map of the domain
 * (metric_maps.h: weighted by signal_weights, measured on up to `threads` workers): the
 * candidate perceptual uses. */
texopt_status texopt_ssp_targets_every_map(const texopt_model *model, const texopt_mesh *mesh, double lambda_min,
                                           const double *signal_weights, int threads, texopt_triangle_target *targets,
                                           char *err, size_t err_len);

#endif
