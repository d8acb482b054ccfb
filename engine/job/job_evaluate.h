/* job_evaluate.h - the whole-mesh loss q (evaluate.h) of a job's layouts, in memory.
 *
 * Does: show the input model through a run's new UVs and images (a shallow view that owns
 * nothing) and measure q against the input, several layouts in one pass over the views.
 * Every rendering of a job (the candidates' choice, the refinement's screens, the target-loss
 * steps, the reported q) uses the lookups of params.mipmapped: a layout tuned on bilinear
 * screens spends texels on matching the input's unfiltered minification, which a mip-mapped
 * renderer does not show (BENCHMARKS.md@9f788a8 "Tuned for the lookups it is judged with").
 * Does not: choose between layouts (job_candidates.h). */
#ifndef TEXOPT_JOB_EVALUATE_H
#define TEXOPT_JOB_EVALUATE_H

#include "evaluate.h"
#include "job_state.h"
#include "map_check.h"

#define JOB_MAX_EVALUATED_OUTPUTS 5 /* job_candidates.h's candidates */

/* The views perceptual chooses its layout on (candidates, refinement, resize check): the
 * icosahedron's 12, not the dodecahedron's 20 that the reported q is measured on
 * (job_evaluate_output), so that q is judged on views the choice never saw. */
#define CHOICE_CAMERAS TEXOPT_CAMERAS_ICOSAHEDRON

/* What an evaluation looks at and what it hands back besides q. */
typedef struct job_screen {
    texopt_camera_set cameras;
    int lit;                                          /* evaluate.h `lit`: every map under one light */
    const texopt_evaluate_reference *reference_views; /* the input's kept views, or NULL */
    double *triangle_error;                           /* per model triangle, or NULL */
} job_screen;

/* The options of the job's evaluations: q's resolution, the job's threads, its monitor. */
texopt_evaluate_options job_evaluation_options(const texopt_params *p, texopt_camera_set cameras, int lit,
                                               job_monitor *jm);

/* q of each of n outputs (at most JOB_MAX_EVALUATED_OUTPUTS) against the input, in one pass
 * over the views of screen (the input rendered once for all, or read from its kept views). */
texopt_status job_evaluate_outputs(texopt_job *job, const job_output *const *outs, int n, const texopt_params *p,
                                   const job_screen *screen, texopt_evaluation *ev, char *err, size_t err_len);

/* q of every map (map_check.h) that shows domain (< 0: the whole model), for each of n
 * outputs, on cameras. */
texopt_status job_evaluate_maps(texopt_job *job, const job_output *const *outs, int n, const texopt_params *p,
                                texopt_camera_set cameras, int domain, texopt_map_q *q, char *err, size_t err_len);

/* The reported q, as the paper and the benchmark define it: the dodecahedron's 20 views. */
texopt_status job_evaluate_output(texopt_job *job, const job_output *out, const texopt_params *p, texopt_evaluation *ev,
                                  char *err, size_t err_len);

#endif
