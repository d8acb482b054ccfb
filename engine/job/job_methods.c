/* job_methods.c - the layout methods of a job, one table (job_methods.h). */
#include "job_methods.h"

#include <string.h>

#include "arap.h"
#include "ssp.h"
#include "tewari.h"

static const stage_weights input_weights = {0.15, 0, 0, 0, 0.70, 0.15};
static const stage_weights layout_weights = {0.02, 0.78, 0.08, 0.03, 0.06, 0.03};

/* Stage 1's options from the job's parameters. */
static texopt_triopt_options stage1_options(const texopt_params *params, const double *signal_weights)
{
    texopt_triopt_options topt;
    memset(&topt, 0, sizeof topt);
    topt.epsilon = params->epsilon;
    topt.iterations = params->iterations;
    topt.lambda_min = params->lambda_min;
    topt.threads = params->threads;
    topt.seed = params->seed;
    topt.signal_weights = signal_weights;
    return topt;
}

static texopt_status stage1_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                    const double *signal_weights, texopt_triangle_target *targets,
                                    texopt_triopt_report *trep, const texopt_monitor *monitor, char *err,
                                    size_t err_len)
{
    texopt_triopt_options topt = stage1_options(params, signal_weights);
    return texopt_triopt_run(model, mesh, &topt, targets, trep, monitor, err, err_len);
}

/* Sun et al. 2022 as written (docs/method.md "The paper's method as written"): the paper's
 * window and plain Bayesian optimisation, at the job's epsilon and iterations (the paper's
 * 0.01 and 100 unless the user gives others: params.h). */
static texopt_status paper_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                   const double *signal_weights, texopt_triangle_target *targets,
                                   texopt_triopt_report *trep, const texopt_monitor *monitor, char *err, size_t err_len)
{
    texopt_triopt_options topt = stage1_options(params, signal_weights);
    topt.plain = 1;
    topt.paper_window = 1;
    return texopt_triopt_run(model, mesh, &topt, targets, trep, monitor, err, err_len);
}

static texopt_status ssp_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                 const double *signal_weights, texopt_triangle_target *targets,
                                 texopt_triopt_report *trep, const texopt_monitor *monitor, char *err, size_t err_len)
{
    (void)signal_weights, (void)trep, (void)monitor;
    return texopt_ssp_targets(model, mesh, params->lambda_min, targets, err, err_len);
}

static texopt_status tewari_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                    const double *signal_weights, texopt_triangle_target *targets,
                                    texopt_triopt_report *trep, const texopt_monitor *monitor, char *err,
                                    size_t err_len)
{
    (void)signal_weights, (void)trep, (void)monitor;
    return texopt_tewari_targets(model, mesh, params->lambda_min, targets, err, err_len);
}

static texopt_status arap_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                  const double *signal_weights, texopt_triangle_target *targets,
                                  texopt_triopt_report *trep, const texopt_monitor *monitor, char *err, size_t err_len)
{
    (void)model, (void)params, (void)signal_weights, (void)trep, (void)monitor;
    return texopt_arap_targets(mesh, targets, err, err_len);
}

static const job_method methods[TEXOPT_METHOD_COUNT] = {
    [TEXOPT_METHOD_PERCEPTUAL] = {&layout_weights, stage1_targets, 1},
    [TEXOPT_METHOD_INPUT] = {&input_weights, NULL, 0},
    [TEXOPT_METHOD_SSP] = {&layout_weights, ssp_targets, 0},
    [TEXOPT_METHOD_TEWARI] = {&layout_weights, tewari_targets, 0},
    [TEXOPT_METHOD_ARAP] = {&layout_weights, arap_targets, 0},
    [TEXOPT_METHOD_PAPER] = {&layout_weights, paper_targets, 0},
};

const job_method *job_method_of(texopt_method m)
{
    return &methods[m];
}
