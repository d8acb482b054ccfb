/* domain_unfold.h - `--bijective` for the charts that overlap themselves in the input
 * layout: a start the scaffold can box (layout/chart_unfold.h).
 *
 * Does: per domain, when some chart overlapping itself in the input can be laid out anew,
 * jd->layout = the input mesh with new texels for those charts: the same vertices,
 * triangles and charts (the model needs no vertex split; checked), so stage 2, packing, the
 * layout check and the written UVs work on it and the re-bake maps each triangle from its
 * input UVs as for new charts (bake_pool.c). A sharing group (texel_share.h) is laid out
 * as one (chart_unfold.h texopt_unfold_groups: its secondaries follow their primary, one
 * that is no twin leaves it), or left alone when it cannot be; the paid shares are measured
 * again on the new layout (a fold laid out flat pays for its texels) and the sharing view is re-based on it; the counts go to the
 * domain's statistics. Does not: restate the targets (domain_prepare.c does it for every
 * jd->layout, target_restate.h) or solve. */
#ifndef TEXOPT_DOMAIN_UNFOLD_H
#define TEXOPT_DOMAIN_UNFOLD_H

#include "job_state.h"

texopt_status job_unfold_domain(texopt_job *job, int d, char *err, size_t err_len);

#endif
