/* bake_pool.h - the re-bake of a run's domains into their packed layouts.
 *
 * Does: re-bake the images of a domain that a run's bake plan names (job_state.h bake_plan)
 * from the input layout into the packed one (rebake.h), several images side by side, one
 * thread each, with progress per finished image; turn a normal map's tangent-space XY with
 * the layout (rebake.h) unless the domain's primitives store TANGENT (io/gltf_tangents.h:
 * stored tangents are kept by the saver, and the map must then stay as it was). Does not:
 * lay out or resize (budget_layout.h, input_method.h). */
#ifndef TEXOPT_BAKE_POOL_H
#define TEXOPT_BAKE_POOL_H

#include "job_state.h"

/* Re-bakes the images of domain d that run->plan names from the input layout into packed
 * (output texels of a size[0] x size[1] frame, per vertex of `charts`: the domain's layout
 * mesh, job_state.h, or NULL for the input's own vertices), into run->out, their sizes and
 * whether they were rewritten in run->domains[d]; progress over [from, to] of the job. */
texopt_status job_rebake_domain(texopt_job *job, const layout_run *run, int d, const texopt_mesh *charts,
                                const double *packed, const int size[2], double from, double to, char *err,
                                size_t err_len);

/* Bakes the images of run->out that its layout's run left out (run->plan: under BAKE_ALL
 * every one, as the saved model needs them) into the layouts it packed. */
texopt_status job_bake_remaining_images(texopt_job *job, const layout_run *run, double from, double to, char *err,
                                        size_t err_len);

#endif
