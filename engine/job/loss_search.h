/* loss_search.h - the target_loss budget of a job.
 *
 * Does: search the smallest relative cost whose q is at most params.target_loss
 * (target_search.h's bisection on log c_r), each step only the budget's part of the job
 * (job_candidates.h), evaluated in memory. The step the search will answer with (cost_max's,
 * then each that meets the target) is kept with the statistics it recorded, so the chosen
 * cost is not made a second time. Does not: save (pipeline.c). */
#ifndef TEXOPT_LOSS_SEARCH_H
#define TEXOPT_LOSS_SEARCH_H

#include "evaluate.h"
#include "job_state.h"

/* Searches the cost for the budget p and hands over the step it answers with: its output in
 * *out, its q in *ev, its statistics back in job->stats, its parameters in *chosen;
 * progress over [from, to] of the job. */
texopt_status job_search_target_loss(texopt_job *job, const texopt_params *p, double from, double to,
                                     texopt_params *chosen, job_output *out, texopt_evaluation *ev, char *err,
                                     size_t err_len);

#endif
