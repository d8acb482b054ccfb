/* candidate.h - one candidate layout of a budget: its output, statistics and loss.
 *
 * Does: run a layout of every domain (job_state.h layout_run) into a candidate of its own,
 * its statistics a copy of the job's so that several candidates can each record theirs, and
 * bake the images it left out. Does not: choose between candidates (job_candidates.h). */
#ifndef TEXOPT_CANDIDATE_H
#define TEXOPT_CANDIDATE_H

#include "evaluate.h"
#include "job_state.h"

typedef struct candidate {
    job_output out;
    texopt_domain_stats *domains;
    texopt_evaluation ev;
} candidate;

/* The layout that `how` describes (its p, source, allocating, refined and plan; not its
 * statistics or output) as candidate c; progress over [from, to] of the job. */
texopt_status job_run_candidate(texopt_job *job, const layout_run *how, candidate *c, double from, double to, char *err,
                                size_t err_len);

/* Bakes the images a candidate left out (BAKE_ALL) into its layouts, recording them in its
 * own statistics. */
texopt_status job_bake_candidate_images(texopt_job *job, const texopt_params *p, candidate *c, double from, double to,
                                        char *err, size_t err_len);

/* Frees a candidate's layout, bakes and statistics. */
void job_candidate_free(texopt_job *job, candidate *c);

#endif
