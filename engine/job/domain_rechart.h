/* domain_rechart.h - `--charts new` (issue 41): a job's domains laid out on new charts.
 *
 * Does: before the domains are prepared, cut each into new disk charts laid out by the chosen
 * parameterization (param/rechart.h) and split the model's vertices where a chart boundary
 * runs through a shared vertex (model/model_split.h: the model draws as before). Per domain,
 * the layout mesh: the same triangles, welded by the new charts, its "input" layout the new
 * charts placed side by side at the input's texel density (jd->layout; stage 2, packing, the
 * layout check and the written UVs work on it); and the targets stage 1 found for the input
 * layout (jd->mesh) restated for the new one. The re-bake still reads the input's texture
 * through the input's UVs (bake_pool.c), triangle by triangle.
 * Does not: choose a layout by quality (the chosen method runs on the new charts as on the
 * input's), nor keep sharing groups (new charts share no texels). */
#ifndef TEXOPT_DOMAIN_RECHART_H
#define TEXOPT_DOMAIN_RECHART_H

#include "job_state.h"

/* Re-charts every domain and splits the model's vertices; per domain the charts are kept in
 * job->domains[d].rechart. */
texopt_status job_rechart_model(texopt_job *job, char *err, size_t err_len);

/* jd->layout for domain d (jd->mesh built from the split model). */
texopt_status job_rechart_layout_mesh(texopt_job *job, int d, char *err, size_t err_len);

/* Restates targets found for jd->mesh's layout (deformations from its texels) for
 * jd->layout's: J' = J (d input / d new); a triangle whose map would mirror keeps its stretch
 * and loses its rotation target. */
void job_rechart_targets(const job_domain *jd, texopt_triangle_target *targets);

/* The mesh a domain's layout is solved, packed and written on: jd->layout with new charts,
 * else the input's. */
const texopt_mesh *job_layout_mesh(const job_domain *jd);

#endif
