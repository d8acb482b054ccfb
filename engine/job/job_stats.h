/* job_stats.h - the job's statistics (stats.h) filled from what its stages report.
 *
 * Does: record the parameters, the images of a domain, stage 1's and stage 2's reports,
 * distortion and the evaluation into texopt_job_stats, and copy per-domain statistics so
 * that two layouts can each record theirs. Does not: write JSON (stats.h) or measure
 * anything but distortion. */
#ifndef TEXOPT_JOB_STATS_H
#define TEXOPT_JOB_STATS_H

#include "evaluate.h"
#include "meshwise.h"
#include "model.h"
#include "params.h"
#include "scaffold.h"
#include "stats.h"
#include "target.h"
#include "triopt.h"

void job_stats_fill_params(texopt_job_stats *js, const texopt_params *p);

/* The domain's images (name, slot, input size) in ds->images (allocated here). */
texopt_status job_stats_record_images(const texopt_model *model, const texopt_domain *dom, texopt_domain_stats *ds,
                                      char *err, size_t err_len);

/* Stage-1 statistics from the targets: loss at the optimum, area scale, share within eps. */
void job_stats_record_stage1(const texopt_mesh *mesh, const texopt_triangle_target *targets,
                             const texopt_triopt_report *rep, double epsilon, texopt_domain_stats *ds);

void job_stats_record_stage2(const texopt_meshwise_report *rep, texopt_domain_stats *ds);
void job_stats_record_scaffold(const texopt_scaffold_report *rep, texopt_domain_stats *ds);

/* Distortion of the input layout and of texel (input texels); left out when unmeasurable. */
void job_stats_record_distortion(const texopt_mesh *mesh, const double *texel, texopt_domain_stats *ds);

void job_stats_record_evaluation(texopt_job_stats *js, const texopt_evaluation *ev);

/* A copy of the job's per-domain statistics with image arrays of its own (NULL on no memory). */
texopt_domain_stats *job_stats_copy_domains(const texopt_job_stats *js);

/* Frees a copy of job_stats_copy_domains (accepts NULL). */
void job_stats_free_domains(texopt_domain_stats *ds, int n);

#endif
