/* metric_maps.h - the signal metrics' targets (ssp.h, tewari.h) from every map of a domain.
 *
 * Perceptual uses the Hessian metric's targets as a floor under stage 1's and both metrics'
 * targets as candidate layouts (pipeline.c). Measured on base colour alone, a material whose
 * base colour is flat and whose detail lies in another map (an emissive label, scratches in
 * an occlusion-roughness-metallic image) has a flat metric: every triangle gets lambda 1, and
 * the floor lifts every triangle stage 1 shrank to k^2 of the input's area, erasing stage 1's
 * allocation (which sees every map, triloss.h). Here each decoded image of the domain gets its
 * own metric and targets (each normalised on its own, as texopt_targets_from_metric does), and
 * each triangle takes the target of the map that asks it the largest area, the most demanding
 * one: the same rule as stage 1's loss, the maximum over maps. A map flat over the mesh asks
 * nothing; when every map is flat every triangle gets lambda 1, as from one flat map.
 * With one image the targets are those of texopt_targets_from_metric on it.
 * Does not: weigh maps by what a light shows of them (lit_weight.h; stage 1 does), solve,
 * pack or bake. */
#ifndef TEXOPT_METRIC_MAPS_H
#define TEXOPT_METRIC_MAPS_H

#include "mesh.h"
#include "model.h"
#include "ssp.h"
#include "status.h"
#include "target.h"

/* Targets into targets[mesh->triangle_count] from the metric `probe` gives on each decoded
 * image of the mesh's domain, lambda_k = eigenvalue_k ^ exponent (texopt_targets_from_metric),
 * the maps measured on up to `threads` workers (< 1: one; the result does not depend on it).
 * Fails with TEXOPT_E_UNSUPPORTED when the domain has no decoded image. */
texopt_status texopt_metric_targets_every_map(const texopt_model *model, const texopt_mesh *mesh,
                                              texopt_signal_probe probe, double exponent, double lambda_min,
                                              int threads, texopt_triangle_target *targets, char *err,
                                              size_t err_len);

#endif
