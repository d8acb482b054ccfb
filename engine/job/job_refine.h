/* job_refine.h - closed-loop refinement of a kept candidate layout by its on-screen error.
 *
 * Does: the paper's principle (perceptual loss on screen) applied to the whole mesh: render
 * the layout against the input, take each triangle's on-screen error, move texels from the
 * triangles shown right to those shown wrong (target_allocation.h texopt_reallocate_by_error), solve,
 * pack and bake again, and keep the new layout when its q is lower; a round that is not
 * lower is retried from the best layout with half the step, as a backtracking line search.
 * Does not: choose which candidates are refined (job_candidates.h). */
#ifndef TEXOPT_JOB_REFINE_H
#define TEXOPT_JOB_REFINE_H

#include "candidate.h"

/* What one candidate's refinement did, for the statistics. */
typedef struct refinement_record {
    int rounds, kept, lit;
    double q_before, q_after, seconds;
} refinement_record;

/* Refines *kept, the candidate that made_by made (its p with the rounds to run, its source
 * and its allocation cap, made_by->allocating), in place; what it did in *rec. */
texopt_status job_refine_kept(texopt_job *job, const layout_run *made_by, candidate *kept, double from, double to,
                              refinement_record *rec, char *err, size_t err_len);

/* The kept candidate's refinement in the statistics, with the seconds of every refinement the
 * budget ran. */
void job_record_refinement(texopt_job_stats *js, const refinement_record *r, double seconds);

#endif
