/* budget_layout.h - every domain of a job laid out at one budget (one layout_run).
 *
 * Does: per domain: target_allocation.h rescales the targets to the budget (when the run allocates) ->
 * stage 2 (meshwise.h, each sharing group's secondaries tied to its primary) -> budget.h
 * packs the charts anew, a sharing group as one, and corrects the scale -> the per-budget
 * keep rules (domain_keep.h) -> re-bake (bake_pool.h); or method "input"'s resize
 * (input_method.h). Budgets: a relative cost is allocated as asked; a texture size at the
 * cost it is expected to reach (texels x typical packing efficiency), solved again once at
 * the cost reached when that misses by more than 10%. Does not: choose between layouts
 * (job_candidates.h) or save. */
#ifndef TEXOPT_BUDGET_LAYOUT_H
#define TEXOPT_BUDGET_LAYOUT_H

#include "job_state.h"
#include "target_allocation.h"

/* The perceptual targets' allocation for one domain with singular values capped at cap. */
texopt_allocate_options job_domain_allocation(const job_domain *jd, double cap);

/* Paper Fig. 16: the share of triangles whose loss under the solved layout texel_new (on
 * `cut`, the domain's cut mesh, or NULL: its mesh) still meets eps, into ds. Measured only
 * for the methods that choose or when the job evaluates. */
texopt_status job_measure_loss_share(texopt_job *job, int d, const texopt_mesh *cut, const double *texel_new,
                                     texopt_domain_stats *ds, char *err, size_t err_len);

/* The domains' share of a part of the job: by triangles (layout methods) or texels (input). */
double job_domain_weight(const texopt_job *job, int d);
double job_total_domain_weight(const texopt_job *job);

/* Every domain at the budget of run->p (relative cost or texture size) into run->out
 * (allocated here), with its statistics in run->domains; progress over [from, to] of the
 * job. */
texopt_status job_run_budget(texopt_job *job, const layout_run *run, double from, double to, char *err, size_t err_len);

#endif
