/* pipeline.h - one whole job: load, optimise every texture domain, re-bake, save.
 *
 * The one entry point the command line and the service share. It knows the stages and their
 * order; it knows nothing of HTTP or terminals. */
#ifndef TEXOPT_PIPELINE_H
#define TEXOPT_PIPELINE_H

#include "monitor.h"
#include "params.h"
#include "status.h"

/* Optimises the model at input_path (.glb or .gltf) with params (resolved and validated
 * inside) and writes output_glb and, when stats_json is not NULL, the statistics as JSON.
 * Both are written to a temporary file, synced and renamed, so a failure or a kill never
 * leaves a partial file under the final name. With budget target_loss the output is the
 * smallest relative cost (searched in [0.01, 1], to 5%) whose whole-mesh loss q is at most
 * params->target_loss; the statistics report the search (target_search) and q. */
texopt_status texopt_optimize_file(const char *input_path, const char *output_glb, const char *stats_json,
                                   const texopt_params *params, const texopt_monitor *monitor, char *err,
                                   size_t err_len);

/* The same job in two parts, for callers that need several budgets of one model (compare.h,
 * the target_loss search): texopt_job_create loads the model and computes everything that
 * does not depend on the budget (meshes, stage 1 or a baseline's targets); each
 * texopt_job_write then allocates, solves stage 2, packs, re-bakes and saves one budget.
 * params as for texopt_optimize_file; its budget fields are ignored by create. The monitor
 * must outlive the job. */
typedef struct texopt_job texopt_job;

typedef struct texopt_job_budget {
    texopt_budget kind;                /* RELATIVE_COST, TEXTURE_SIZE or TARGET_LOSS */
    double relative_cost;              /* with RELATIVE_COST */
    int texture_width, texture_height; /* with TEXTURE_SIZE */
    double target_loss;                /* with TARGET_LOSS */
} texopt_job_budget;

texopt_status texopt_job_create(texopt_job **job, const char *input_path, const texopt_params *params,
                                const texopt_monitor *monitor, char *err, size_t err_len);

/* Writes output_glb (and stats_json when not NULL) for one budget, as texopt_optimize_file
 * does. May be called any number of times on one job. */
texopt_status texopt_job_write(texopt_job *job, const texopt_job_budget *budget, const char *output_glb,
                               const char *stats_json, char *err, size_t err_len);

/* Accepts NULL. */
void texopt_job_destroy(texopt_job *job);

#endif
