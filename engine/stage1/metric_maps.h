/* metric_maps.h - the signal metrics' targets (ssp.h, tewari.h) from every map of a domain.
 *
 * Perceptual uses the Hessian metric's targets as a floor under stage 1's and both metrics'
 * targets as candidate layouts (pipeline.c). Measured on base colour alone, a material whose
 * base colour is flat and whose detail lies in another map (an emissive label, scratches in
 * an occlusion-roughness-metallic image) has a flat metric: every triangle gets lambda 1, and
 * the floor lifts every triangle stage 1 shrank to k^2 of the input's area, erasing stage 1's
 * allocation (which sees every map, triloss.h). Here each decoded image of the domain is
 * measured, scaled by its weight (lit_weight.h: what a lit render shows of a unit change of
 * it, as stage 1 scales its signals) and the metrics are summed: a metric is a sum of squared
 * derivatives over channels already, and a signal scaled by w has w^2 times the metric. One
 * normalisation follows (texopt_targets_from_metric), so a faint map asks few texels and a map
 * no light shows none. With one image and no weights the targets are those of that image.
 * Does not: solve, pack or bake. */
#ifndef TEXOPT_METRIC_MAPS_H
#define TEXOPT_METRIC_MAPS_H

#include "mesh.h"
#include "model.h"
#include "ssp.h"
#include "status.h"
#include "target.h"

/* Targets into targets[mesh->triangle_count] from the sum over the decoded images of the mesh's
 * domain of the metric `probe` gives, each times its weight squared (signal_weights as
 * texopt_lit_signal_weights fills them; NULL: 1), lambda_k = eigenvalue_k ^ exponent
 * (texopt_targets_from_metric). The maps are measured on up to `threads` workers (< 1: one;
 * the result does not depend on it). Fails with TEXOPT_E_UNSUPPORTED when the domain has no
 * decoded image. */
texopt_status texopt_metric_targets_every_map(const texopt_model *model, const texopt_mesh *mesh,
                                              texopt_signal_probe probe, double exponent, double lambda_min,
                                              const double *signal_weights, int threads,
                                              texopt_triangle_target *targets, char *err, size_t err_len);

#endif
