/* pipeline.c - one whole job: load, optimise every texture domain, re-bake, save, report.
 *
 * Implements pipeline.h, the product of Sun et al. 2022, "Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen", end to end, in two parts:
 *   job_create (budget-independent): load (io/gltf_io) -> per texture domain: mesh, input
 *     coverage, charts sharing texels, per-triangle targets (domain_prepare.h: stage 1 or a
 *     baseline's, job_methods.h), the keep rules (domain_keep.h);
 *   job_write (per budget): the best layout of the budget (job_candidates.h; each layout a
 *     layout_run through budget_layout.h: allocation, stage 2, packing, re-bake), or the
 *     target_loss search over budgets (loss_search.h) -> the images left to bake
 *     (bake_pool.h) -> [evaluate] -> save .glb -> statistics (stats.h, costs measured on the
 *     written file, file_cost.h).
 * Budgets: a texture size is refused above 4 times the pixels of the images it re-bakes
 * (check_texture_size_budget).
 * With params.evaluate, the whole-mesh loss q (evaluate.h) of the result against the input
 * is measured before saving and written to the statistics.
 * Does not: parse command lines or HTTP, or print. */
#include "pipeline.h"

#include <math.h>
#include <stdlib.h>

#include "bake_pool.h"
#include "budget_layout.h"
#include "domain_keep.h"
#include "domain_prepare.h"
#include "domain_rechart.h"
#include "file_cost.h"
#include "gltf_io.h"
#include "job_candidates.h"
#include "job_evaluate.h"
#include "job_state.h"
#include "job_stats.h"
#include "lit_weight.h"
#include "loss_search.h"

#define EVALUATE_WEIGHT 0.1 /* share of the job taken from the middle when params.evaluate */

/* The most pixels a texture-size budget may write, over those the re-baked images have: the
 * bound relative_cost has (at most 4). A size far above the input adds no detail, and its
 * bakes take memory in proportion (Duck's 512x512 at 16384x16384: 19 GB and over ten
 * minutes before this check). */
#define TEXTURE_SIZE_GROWTH_MAX 4.0

static texopt_status check_texture_size_budget(const texopt_model *model, const texopt_params *p, char *err,
                                               size_t err_len)
{
    if (p->budget != TEXOPT_BUDGET_TEXTURE_SIZE)
        return TEXOPT_OK;
    double had = 0, asked = 0;
    for (int d = 0; d < model->domain_count; d++)
        for (int i = 0; i < model->domains[d].image_count; i++) {
            const texopt_image *img = &model->images[model->domains[d].images[i]];
            had += (double)img->width * img->height;
            asked += (double)p->texture_width * p->texture_height;
        }
    if (!(had > 0) || !(asked > TEXTURE_SIZE_GROWTH_MAX * had))
        return TEXOPT_OK;
    double s = sqrt(TEXTURE_SIZE_GROWTH_MAX * had / asked);
    return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                       "texture_size %dx%d: %.0f times the pixels of the model's re-baked images (%.0f); at most "
                       "%g times (relative_cost's bound), about %dx%d or less at this aspect ratio",
                       p->texture_width, p->texture_height, asked / had, had, TEXTURE_SIZE_GROWTH_MAX,
                       (int)fmax(1, floor(p->texture_width * s)), (int)fmax(1, floor(p->texture_height * s)));
}

static texopt_status check_params(const texopt_params *in, texopt_params *p, char *err, size_t err_len)
{
    if (!in)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params missing");
    *p = *in;
    texopt_params_resolve(p);
    return texopt_params_validate(p, err, err_len);
}

/* job->signal_weights for the loaded model. */
static texopt_status weigh_signals(texopt_job *job, char *err, size_t err_len)
{
    const texopt_model *m = job->model;
    job->signal_weights =
        malloc((m->image_count ? (size_t)m->image_count : 1) * TEXOPT_LIT_WEIGHT_STRIDE * sizeof *job->signal_weights);
    if (!job->signal_weights)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %d images' signal weights", m->image_count);
    return texopt_lit_signal_weights(m, job->signal_weights, err, err_len);
}

texopt_status texopt_job_create(texopt_job **out, const char *input_path, const texopt_params *params,
                                const texopt_monitor *monitor, char *err, size_t err_len)
{
    if (!out || !input_path)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "job: missing result or input path");
    *out = NULL;
    texopt_job *job = calloc(1, sizeof *job);
    if (!job)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the job");
    texopt_status st = check_params(params, &job->params, err, err_len);
    if (st != TEXOPT_OK) {
        free(job);
        return st;
    }
    const texopt_params *p = &job->params;
    job->method = job_method_of(p->method);
    const stage_weights *w = job->method->weights;
    job->budget_from = w->load + w->stage1;
    job_monitor_init(&job->jm, monitor);
    job_stats_fill_params(&job->stats, p);
    job_stage(&job->jm, "load", 0, w->load);
    double t0 = job_now_seconds();
    st = texopt_model_load(&job->model, input_path, NULL, err, err_len);
    job->stats.seconds_load = job_now_seconds() - t0;
    if (st == TEXOPT_OK && job->model->domain_count == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "%s has no textured primitive", input_path);
    if (st == TEXOPT_OK)
        st = check_texture_size_budget(job->model, p, err, err_len);
    if (st == TEXOPT_OK)
        st = weigh_signals(job, err, err_len);
    if (st == TEXOPT_OK) {
        job_stage_done(&job->jm, "load");
        int n = job->model->domain_count;
        job->domains = calloc((size_t)n, sizeof *job->domains);
        job->stats.domains = calloc((size_t)n, sizeof *job->stats.domains);
        job->stats.domain_count = n;
        if (!job->domains || !job->stats.domains)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %d domains", n);
    }
    if (st == TEXOPT_OK && p->charts == TEXOPT_CHARTS_NEW)
        st = job_rechart_model(job, err, err_len);
    double total = st == TEXOPT_OK ? job_total_domain_weight(job) : 0;
    double at = w->load;
    for (int d = 0; st == TEXOPT_OK && d < job->model->domain_count; d++) {
        double share = total > 0 ? w->stage1 * job_domain_weight(job, d) / total : 0;
        st = job_check_cancel(&job->jm, err, err_len);
        if (st == TEXOPT_OK)
            st = job_prepare_domain(job, d, at, at + share, err, err_len);
        at += share;
    }
    if (st == TEXOPT_OK)
        st = job_check_something_laid_out(job, err, err_len);
    if (st != TEXOPT_OK) {
        texopt_job_destroy(job);
        return st;
    }
    *out = job;
    return TEXOPT_OK;
}

void texopt_job_destroy(texopt_job *job)
{
    if (!job)
        return;
    for (int d = 0; job->domains && job->model && d < job->model->domain_count; d++) {
        texopt_mesh_destroy(job->domains[d].mesh);
        texopt_mesh_destroy(job->domains[d].layout);
        texopt_rechart_destroy(job->domains[d].rechart);
        texopt_texel_share_destroy(job->domains[d].share);
        free(job->domains[d].paid);
        free(job->domains[d].targets);
        free(job->domains[d].hessian);
        free(job->domains[d].stretch);
    }
    free(job->domains);
    free(job->signal_weights);
    texopt_job_stats_destroy(&job->stats);
    texopt_model_destroy(job->model);
    free(job);
}

/* The job's parameters with the budget of b. */
static texopt_status budget_params(const texopt_job *job, const texopt_job_budget *b, texopt_params *p, char *err,
                                   size_t err_len)
{
    if (!b)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "job: budget missing");
    *p = job->params;
    p->budget = b->kind;
    p->relative_cost = b->kind == TEXOPT_BUDGET_RELATIVE_COST ? b->relative_cost : 1.0;
    p->texture_width = b->texture_width;
    p->texture_height = b->texture_height;
    p->target_loss = b->target_loss;
    texopt_status st = texopt_params_validate(p, err, err_len);
    return st == TEXOPT_OK ? check_texture_size_budget(job->model, p, err, err_len) : st;
}

texopt_status texopt_job_write(texopt_job *job, const texopt_job_budget *budget, const char *output_glb,
                               const char *stats_json, char *err, size_t err_len)
{
    if (!job || !output_glb)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "job: missing job or output path");
    texopt_params p;
    texopt_status st = budget_params(job, budget, &p, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_job_stats *js = &job->stats;
    job_stats_fill_params(js, &p);
    js->has_search = 0;
    js->has_evaluation = 0;
    const stage_weights *w = job->method->weights;
    /* The target_loss search measures every step's q within its own range. */
    double end = 1.0 - w->save, tail = p.evaluate && p.budget != TEXOPT_BUDGET_TARGET_LOSS ? EVALUATE_WEIGHT : 0;
    double from = job->budget_from;
    job_output out = {0};
    texopt_evaluation ev;
    int evaluated = 0;
    js->has_allocation_choice = 0;
    /* A perceptual job's kept candidate bakes its remaining images from here. */
    double baked = job->method->chooses ? from + 0.85 * (end - tail - from) : end - tail;
    if (p.budget == TEXOPT_BUDGET_TARGET_LOSS) {
        st = job_search_target_loss(job, &p, from, baked, &p, &out, &ev, err, err_len);
        evaluated = st == TEXOPT_OK; /* every step measured its q */
        if (st == TEXOPT_OK && stats_json)
            st = job_measure_chosen_loss_share(job, &out, err, err_len);
    } else {
        st = job_run_best_budget(job, &p, stats_json != NULL, &out, from, baked, err, err_len);
    }
    layout_run rest = {.p = &p, .plan = BAKE_ALL, .domains = js->domains, .out = &out}; /* after the search */
    if (st == TEXOPT_OK)
        st = job_bake_remaining_images(job, &rest, baked, end - tail, err, err_len);
    if (st == TEXOPT_OK)
        st = job_check_cancel(&job->jm, err, err_len);
    if (st == TEXOPT_OK && p.evaluate && !evaluated) {
        job_stage(&job->jm, "evaluate", end - tail, end);
        st = job_evaluate_output(job, &out, &p, &ev, err, err_len);
        evaluated = st == TEXOPT_OK;
    }
    if (st == TEXOPT_OK && p.evaluate)
        job_stats_record_evaluation(js, &ev);
    const job_output *written = &out;
    js->has_q_maps = 0;
    if (st == TEXOPT_OK && p.evaluate && stats_json) {
        st = job_evaluate_maps(job, &written, 1, &p, TEXOPT_CAMERAS_DODECAHEDRON, -1, &js->q_maps, err, err_len);
        js->has_q_maps = st == TEXOPT_OK;
    }
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "save", end, 1.0);
        double t0 = job_now_seconds();
        texopt_model written;
        st = job_output_view(job->model, &out, &written, err, err_len);
        texopt_model_edit edit = {out.uvs ? written.uvs : NULL, out.edit_images, p.lossless_textures};
        if (st == TEXOPT_OK) {
            written.document = job->model->document; /* the file being edited */
            st = texopt_model_save_glb(&written, &edit, output_glb, err, err_len);
            job_output_view_free(job->model, &written);
        }
        js->seconds_save = job_now_seconds() - t0;
    }
    if (st == TEXOPT_OK && stats_json) /* the costs reported are the written file's */
        st = texopt_file_cost_record(output_glb, js, err, err_len);
    js->seconds_total = job_now_seconds() - job->jm.start;
    if (st == TEXOPT_OK && stats_json)
        st = texopt_stats_write(js, stats_json, err, err_len);
    if (st == TEXOPT_OK)
        job_stage_done(&job->jm, "save");
    job_output_destroy(&out, job->model->image_count);
    return st;
}

texopt_status texopt_optimize_file(const char *input_path, const char *output_glb, const char *stats_json,
                                   const texopt_params *params, const texopt_monitor *monitor, char *err,
                                   size_t err_len)
{
    if (!input_path || !output_glb)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "input and output paths are required");
    texopt_params p;
    texopt_status st = check_params(params, &p, err, err_len);
    texopt_job *job = NULL;
    if (st == TEXOPT_OK)
        st = texopt_job_create(&job, input_path, &p, monitor, err, err_len);
    if (st == TEXOPT_OK) {
        texopt_job_budget b = {p.budget, p.relative_cost, p.texture_width, p.texture_height, p.target_loss};
        st = texopt_job_write(job, &b, output_glb, stats_json, err, err_len);
    }
    texopt_job_destroy(job);
    return st;
}
