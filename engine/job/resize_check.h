/* resize_check.h - never worse than a resize: each new layout judged against its input
 * layout resized to the same file texture pixels.
 *
 * Does: for each domain perceptual laid out anew, resize its input layout's images with
 * Lanczos-3 (input_method.h) to the pixels the new layout writes, and re-bake them into the
 * input layout by the engine's fit as well (input_method.h job_refit_input_layout; not at the
 * input's own size, nor for a layout over several tiles). Each image takes its fitted bake
 * where that is above the resize in no map that reads it, else its resize: the mix. All are
 * measured on the choice's views (CHOICE_CAMERAS) in every map that shows the domain and lit
 * (map_check.h). The new layout is kept when it is below the resize in one map and above it
 * in none, and not above the mix in what a viewer shows (lit, else base colour) when the mix
 * beats the resize too; else the mix when it beats the resize; else the resize (stats
 * resize_check: every map's q, what was kept, the map that decided; input_layout_kept). So
 * what is written is above the resize in no map, and a domain at its input's pixels keeps
 * its input (the identity resize, q 0). Every image is baked first, as it will be saved.
 * Domains are judged one after another, each beside the others' kept layouts.
 * params.resize_check -1 leaves the layouts as they are. Does not: lay out
 * (job_candidates.h). */
#ifndef TEXOPT_RESIZE_CHECK_H
#define TEXOPT_RESIZE_CHECK_H

#include "job_state.h"

/* Judges the domains of *out (the budget p's kept layout, statistics in job->stats) and puts
 * the resize in place of those it keeps; progress at `at` of the job. */
texopt_status job_keep_resize_if_better(texopt_job *job, const texopt_params *p, job_output *out, double at, char *err,
                                        size_t err_len);

#endif
