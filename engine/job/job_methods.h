/* job_methods.h - the layout methods of a job, one table.
 *
 * Does: say for each method (params.h texopt_method) what a job does with it: the shares of
 * the job its stages take, where its per-triangle targets come from and whether it makes
 * and chooses between candidate layouts. Methods:
 *   "perceptual": stage 1's targets (triopt.h); up to five candidate layouts per budget,
 *     refined in closed loop and chosen by their whole-mesh loss (job_candidates.h).
 *   "input": the input layout kept as it is (UVs untouched, seams, overlaps and wrapping
 *     included) and each texture resized with Lanczos-3 (input_method.h). This is the
 *     paper's "input parameterization" baseline, the resize an asset pipeline would do.
 *   "ssp", "tewari", "arap": the baselines of the paper's section 5 (ssp.h, tewari.h, arap.h
 *     targets in place of stage 1, rotation weight 0), solved as they are, then the same
 *     stage 2, budget (a uniform scale), packing and re-bake as "perceptual".
 *   "paper": Sun et al. 2022 as written (triopt.h plain plan, the appendix A window,
 *     the job's epsilon and iterations, by default the paper's 0.01 and 100), then the
 *     same stage 2, budget, packing and re-bake as "ssp": no candidates, no refinement, no
 *     Hessian floor, no resize check.
 * Does not: run any stage itself. */
#ifndef TEXOPT_JOB_METHODS_H
#define TEXOPT_JOB_METHODS_H

#include <stddef.h>

#include "mesh.h"
#include "model.h"
#include "monitor.h"
#include "params.h"
#include "target.h"
#include "triopt.h"

/* Shares of the job per stage, in order: load, [per domain stages], save. */
typedef struct stage_weights {
    double load, stage1, stage2, pack, bake, save;
} stage_weights;

/* The per-triangle targets stage 2 follows, for every triangle of mesh. signal_weights:
 * per image, how much of each signal a lit render shows (lit_weight.h). trep is filled by
 * stage 1 only. */
typedef texopt_status (*job_targets_fn)(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                        const double *signal_weights, texopt_triangle_target *targets,
                                        texopt_triopt_report *trep, const texopt_monitor *monitor, char *err,
                                        size_t err_len);

typedef struct job_method {
    const stage_weights *weights;
    job_targets_fn targets; /* NULL: no new layout (method "input") */
    int chooses;            /* makes candidate layouts, refines and chooses them (perceptual);
                               always records the loss share */
} job_method;

/* The row of method m (a valid method: params validated). */
const job_method *job_method_of(texopt_method m);

#endif
