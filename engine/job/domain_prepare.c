/* domain_prepare.c - the budget-independent part of one texture domain (domain_prepare.h). */
#include "domain_prepare.h"

#include <stdlib.h>

#include "domain_keep.h"
#include "domain_rechart.h"
#include "domain_unfold.h"
#include "job_stats.h"
#include "ssp.h"
#include "tewari.h"

/* The signal metrics' targets perceptual uses beside stage 1 (params.h): the Hessian
 * metric's (tewari.h) for the floor, both it and the signal-stretch metric's (ssp.h) as
 * candidate layouts (job_candidates.h). Stage 1's targets are raised to the floor
 * (TEXOPT_DEFAULT_HESSIAN_FLOOR): the slivers whose one-ring hides their detail from stage 1
 * get at least k^2 of tewari's area. *raised: how many targets it raised. */
static texopt_status add_metric_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *params,
                                        const double *signal_weights, job_domain *jd, size_t *raised, char *err,
                                        size_t err_len)
{
    *raised = 0;
    size_t n = mesh->triangle_count;
    int floor = params->hessian_floor > 0, candidates = params->metric_candidates > 0;
    if ((!floor && !candidates) || n == 0)
        return TEXOPT_OK;
    jd->hessian = calloc(n, sizeof *jd->hessian);
    jd->stretch = candidates ? calloc(n, sizeof *jd->stretch) : NULL;
    if (!jd->hessian || (candidates && !jd->stretch))
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the signal metrics of %zu triangles", n);
    int threads = job_worker_threads(params);
    texopt_status st = texopt_tewari_targets_every_map(model, mesh, params->lambda_min, signal_weights, threads,
                                                       jd->hessian, err, err_len);
    if (st == TEXOPT_OK && candidates)
        st = texopt_ssp_targets_every_map(model, mesh, params->lambda_min, signal_weights, threads, jd->stretch, err,
                                          err_len);
    if (st == TEXOPT_OK && floor)
        *raised = texopt_targets_raise_to_floor(jd->targets, jd->hessian, n, params->hessian_floor);
    return st;
}

/* jd->paid (texel_share.h texopt_texel_share_paid), left NULL when every triangle pays. */
static texopt_status find_paid_shares(job_domain *jd, char *err, size_t err_len)
{
    size_t n = jd->mesh->triangle_count;
    if (n == 0)
        return TEXOPT_OK;
    if (!(jd->paid = malloc(n * sizeof *jd->paid)))
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the texel shares");
    if (texopt_texel_share_paid(jd->share, jd->mesh, jd->paid) == 0) {
        free(jd->paid);
        jd->paid = NULL;
    }
    return TEXOPT_OK;
}

/* The domain's layout mesh on its new charts (domain_rechart.h); the input's sharing groups
 * and paid shares, which the keep rules read, do not apply to new charts. */
static texopt_status new_charts(texopt_job *job, int d, char *err, size_t err_len)
{
    job_domain *jd = &job->domains[d];
    texopt_domain_stats *ds = &job->stats.domains[d];
    texopt_status st = job_rechart_layout_mesh(job, d, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_texel_share_destroy(jd->share);
    jd->share = NULL;
    free(jd->paid);
    jd->paid = NULL;
    ds->new_charts = jd->rechart->chart_count;
    ds->new_chart_fallbacks = jd->rechart->fallback_charts;
    return TEXOPT_OK;
}

/* Stage 1 (or a baseline's targets) for the domain, with perceptual's metric targets. */
static texopt_status domain_targets(texopt_job *job, int d, double from, double to, char *err, size_t err_len)
{
    const texopt_params *params = &job->params;
    job_domain *jd = &job->domains[d];
    texopt_domain_stats *ds = &job->stats.domains[d];
    size_t n = jd->mesh->triangle_count ? jd->mesh->triangle_count : 1;
    jd->targets = calloc(n, sizeof *jd->targets);
    if (!jd->targets)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu triangle targets", n);
    texopt_triopt_report trep = {0};
    job_stage(&job->jm, "stage1", from, to);
    double t0 = job_now_seconds();
    texopt_status st = job->method->targets(job->model, jd->mesh, params, job->signal_weights, jd->targets, &trep,
                                            &job->jm.inner, err, err_len);
    if (st == TEXOPT_OK && job->method->chooses)
        st = add_metric_targets(job->model, jd->mesh, params, job->signal_weights, jd, &ds->hessian_floor_triangles,
                                err, err_len);
    ds->seconds_stage1 = job_now_seconds() - t0;
    if (st == TEXOPT_OK && (job->method->chooses || trep.optimised > 0))
        job_stats_record_stage1(jd->mesh, jd->targets, &trep, params->epsilon, ds);
    if (st == TEXOPT_OK && jd->layout) {
        job_rechart_targets(jd, jd->targets);
        job_rechart_targets(jd, jd->hessian);
        job_rechart_targets(jd, jd->stretch);
    }
    if (st == TEXOPT_OK)
        job_stage_done(&job->jm, "stage1");
    return st;
}

texopt_status job_prepare_domain(texopt_job *job, int d, double from, double to, char *err, size_t err_len)
{
    const texopt_model *model = job->model;
    job_domain *jd = &job->domains[d];
    texopt_domain_stats *ds = &job->stats.domains[d];
    const texopt_domain *dom = &model->domains[d];
    ds->domain = d;
    ds->input_width = dom->width;
    ds->input_height = dom->height;
    texopt_status st = job_stats_record_images(model, dom, ds, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double t0 = job_now_seconds();
    st = texopt_mesh_create(&jd->mesh, model, d, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    ds->seconds_mesh = job_now_seconds() - t0;
    ds->triangles = jd->mesh->triangle_count;
    ds->charts = jd->mesh->chart_count;
    if (!job->method->targets || job_keep_if_flat(jd, ds))
        return TEXOPT_OK;
    st = texopt_coverage_measure(jd->mesh, NULL, &jd->input_coverage, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    if (job_keep_if_no_texels(dom, jd, ds) || job_keep_if_nearest(model, dom, jd, ds))
        return TEXOPT_OK;
    st = texopt_texel_share_create(&jd->share, jd->mesh, err, err_len);
    if (st == TEXOPT_OK)
        st = find_paid_shares(jd, err, err_len);
    /* New charts unroll a repeating (or overlapping) layout: the user asked for that. */
    if (st != TEXOPT_OK || (!jd->rechart && job_keep_if_tiling(dom, jd, ds)))
        return st;
    if (jd->rechart)
        st = new_charts(job, d, err, err_len);
    else if (job->params.bijective)
        st = job_unfold_domain(job, d, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    return domain_targets(job, d, from, to, err, err_len);
}
