/* job_candidates.h - the best layout of one budget: candidates, refinement, choice.
 *
 * Does: for method "perceptual", up to five candidate layouts per budget: the targets
 * allocated to the budget (target_allocation.h) up to input density and up to 1.5x it, the targets as
 * they are (a uniform scale by the budget), and the signal metrics' targets (tewari.h, ssp.h)
 * as those methods lay them out. The candidates bake only base colour (all q looks at) and
 * are evaluated in one pass (whole-mesh loss q, evaluate.h, on the icosahedron's 12 views,
 * not on the 20 the reported q uses: CHOICE_CAMERAS); the best of stage 1's, and the best
 * metric one when its q is lower, are refined in closed loop (job_refine.h), the one lower
 * after its rounds is kept, unless a resize of the input layout is not worse
 * (resize_check.h); its other images are baked after that. Other methods make their one
 * layout. Does not: save or evaluate the reported q (pipeline.c). */
#ifndef TEXOPT_JOB_CANDIDATES_H
#define TEXOPT_JOB_CANDIDATES_H

#include "job_state.h"

/* One budget (p) into *out, with its statistics in job->stats; with_stats: the statistics
 * will be written (the loss share is measured). Progress over [from, to] of the job. */
texopt_status job_run_best_budget(texopt_job *job, const texopt_params *p, int with_stats, job_output *out, double from,
                                  double to, char *err, size_t err_len);

/* The per-triangle loss share (paper Fig. 16) of the kept layout's solved layouts, into
 * job->stats. */
texopt_status job_measure_chosen_loss_share(texopt_job *job, const job_output *out, char *err, size_t err_len);

#endif
