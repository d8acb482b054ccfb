/* resize_check.h - never worse than a resize: each new layout judged against its input
 * layout resized to the same file texture pixels.
 *
 * Does: for each domain perceptual laid out anew, resize its input layout's images with
 * Lanczos-3 (input_method.h) to the pixels the new layout writes, measure both on the
 * choice's views (CHOICE_CAMERAS) in every map that shows the domain and lit (map_check.h),
 * and keep the resize unless the new layout is below it in one and above it in none (stats
 * resize_check: every map's q, the map that decided; input_layout_kept). A domain at its
 * input's pixels thus keeps its input (the identity resize, q 0). Every image is baked
 * first, as it will be saved. Domains are judged one after another, each beside the others'
 * kept layouts. params.resize_check -1 leaves the layouts as they are. Does not: lay out
 * (job_candidates.h). */
#ifndef TEXOPT_RESIZE_CHECK_H
#define TEXOPT_RESIZE_CHECK_H

#include "job_state.h"

/* Judges the domains of *out (the budget p's kept layout, statistics in job->stats) and puts
 * the resize in place of those it keeps; progress at `at` of the job. */
texopt_status job_keep_resize_if_better(texopt_job *job, const texopt_params *p, job_output *out, double at, char *err,
                                        size_t err_len);

#endif
