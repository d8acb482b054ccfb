/* domain_prepare.h - the budget-independent part of one texture domain.
 *
 * Does: per domain of a loaded model, its mesh, input coverage, the charts sharing texels
 * (texel_share.h) and their paid shares, the keep rules decided at creation (domain_keep.h)
 * and the per-triangle targets (stage 1, triopt.h, or a baseline's: job_methods.h), with
 * perceptual's signal-metric targets beside them. Does not: anything that depends on the
 * budget (budget_layout.h). */
#ifndef TEXOPT_DOMAIN_PREPARE_H
#define TEXOPT_DOMAIN_PREPARE_H

#include "job_state.h"

/* Prepares job->domains[d], its statistics in job->stats.domains[d]; progress of stage 1
 * over [from, to] of the job. */
texopt_status job_prepare_domain(texopt_job *job, int d, double from, double to, char *err, size_t err_len);

#endif
