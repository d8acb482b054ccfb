/* job_state.h - what a job holds, and one run of its budget's layout.
 *
 * Does: define struct texopt_job (pipeline.h's opaque job: the model, per texture domain
 * what does not depend on the budget, the statistics) and layout_run, the explicit state of
 * one layout of every domain at one budget (a candidate, a refinement round, a target-loss
 * step or the plain run), passed down to every stage it runs. Does not: run anything. */
#ifndef TEXOPT_JOB_STATE_H
#define TEXOPT_JOB_STATE_H

#include "coverage.h"
#include "job_methods.h"
#include "job_output.h"
#include "job_progress.h"
#include "mesh.h"
#include "model.h"
#include "params.h"
#include "pipeline.h"
#include "rechart.h"
#include "stats.h"
#include "target.h"
#include "texel_share.h"

/* The targets a layout starts from: stage 1's (or a baseline's), or a signal metric's
 * (perceptual's metric candidates). */
typedef enum target_source { SOURCE_STAGE1 = 0, SOURCE_HESSIAN, SOURCE_STRETCH } target_source;

/* What a layout method does with a domain (domain_keep.h). */
typedef enum domain_keep {
    DOMAIN_LAID_OUT = 0,
    DOMAIN_KEPT_AS_IS,    /* nothing to lay out or see: UVs and images as they are */
    DOMAIN_INPUT_RESIZED, /* a tiling texture: the input layout, resized as by method "input" */
} domain_keep;

/* One texture domain of a job: what does not depend on the budget. */
typedef struct job_domain {
    texopt_mesh *mesh;
    texopt_triangle_target *targets; /* stage 1 or a baseline; NULL for method "input" */
    texopt_triangle_target *hessian; /* perceptual: the Hessian metric's targets (tewari.h), the
                                        floor's and a candidate's; NULL when neither is asked for */
    texopt_triangle_target *stretch; /* perceptual: the signal-stretch metric's (ssp.h), a
                                        candidate's; NULL when not asked for */
    texopt_coverage input_coverage;
    texopt_texel_share *share; /* charts sharing texels; NULL for method "input" */
    double *paid;              /* per triangle, the share of its texels it pays for (target_allocation.h); NULL
                     when every triangle pays for all of its own */
    domain_keep kept;          /* laid out, or the input layout kept (and why: stats input_layout_kept) */
    texopt_rechart *rechart;   /* params.charts new: the domain's new charts (domain_rechart.h); else NULL */
    texopt_mesh *layout;       /* params.charts new: the mesh laid out (the new charts); NULL: mesh */
} job_domain;

struct texopt_job {
    texopt_params params;
    const job_method *method; /* params.method's row */
    texopt_model *model;
    job_domain *domains; /* model->domain_count */
    texopt_job_stats stats;
    job_monitor jm;
    double budget_from;     /* the job's progress where the budget's part begins */
    double *signal_weights; /* per image, how much of each signal a lit render shows
                                  (lit_weight.h): stage 1's loss compares them so scaled */
};

/* Which images a run bakes. A candidate bakes only what the evaluation that judges it reads;
 * the images left out are baked for the kept layout alone (job_bake_remaining_images). Every
 * bake is the fit's: the lit refinement's rounds read every image and are mostly thrown away,
 * but rounds judged on cheaper drafts (the prefilter alone) chose worse layouts, normal maps'
 * 1-6% higher in lit q on DamagedHelmet (BENCHMARKS.md@9f788a8 "Cheaper lit refinement"), and
 * every map's once the fit kept a reduced map's detail (docs/benchmarks.md "The re-bake's
 * reduction against a Lanczos-3 resize"). */
typedef enum bake_plan {
    BAKE_ALL = 0,   /* every image not baked yet */
    BAKE_EVALUATED, /* the images base colour's evaluation reads */
} bake_plan;

/* One layout of every domain at one budget. */
typedef struct layout_run {
    const texopt_params *p;                 /* the job's parameters with this budget */
    target_source source;                   /* the targets the layouts start from */
    double allocating;                      /* > 0: the targets are allocated to the budget (target_allocation.h),
                                   singular values capped at this */
    texopt_triangle_target *const *refined; /* per domain, when not NULL: these targets are
                                               solved as they are (job_refine.h) */
    bake_plan plan;                         /* which images the run bakes, and how */
    int with_stats;                         /* measure what only written statistics report (loss share) */
    texopt_domain_stats *domains;           /* where the run records, per domain */
    job_output *out;                        /* what it produces */
} layout_run;

/* The sharing groups stage 2 and the budget work with, NULL when no chart shares another's
 * texels (the layout is then exactly what it is without them). */
const texopt_texel_share *job_sharing(const job_domain *jd);

/* The targets a layout from source starts with (stage 1's when the domain has no metric
 * targets). */
const texopt_triangle_target *job_source_targets(const job_domain *jd, target_source source);

/* The targets the run solves domain d from: refined ones when it has them, else its source's. */
const texopt_triangle_target *job_run_targets(const layout_run *run, const job_domain *jd, int d);

/* params.threads, or every online core when it is 0. */
int job_worker_threads(const texopt_params *params);

#endif
