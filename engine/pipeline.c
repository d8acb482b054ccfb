/* pipeline.c - one whole job: load, optimise every texture domain, re-bake, save, report.
 *
 * Implements engine/pipeline.h, the product of Sun et al. 2022, "Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen", end to end:
 *   load (io/gltf_io) -> per texture domain: mesh -> layout by method -> budget + pack ->
 *   re-bake every image of the domain -> save .glb (io/gltf_io) -> statistics JSON (stats.h).
 * Methods:
 *   "perceptual": stage 1 (triopt.h) + stage 2 (meshwise.h), then budget.h scales the layout
 *     to the requested cost and packs the charts anew (pack.h).
 *   "input": the input layout kept as it is (UVs untouched, seams, overlaps and wrapping
 *     included) and each texture resampled with the prefilter of texture_filter.h to the
 *     budget: a relative cost c_r scales both sides by sqrt(c_r) (rounded to whole texels),
 *     a texture size is taken as given. This is the paper's "input parameterization"
 *     baseline and a useful product on its own (a well-filtered downscale).
 *   "ssp", "tewari", "arap": the baselines of the paper's section 5 (ssp.h, tewari.h,
 *     arap.h targets in place of stage 1, rotation weight 0), then the same stage 2, budget,
 *     packing and re-bake as "perceptual".
 * Normal maps: their tangent-space XY turn with the layout (rebake.h) unless the domain's
 * primitives store TANGENT (io/gltf_tangents.h): stored tangents are kept by the saver, and
 * the map must then stay as it was.
 * Progress: every stage's own stage_fraction is mapped into a fixed share of the job (load,
 * then per domain in proportion to its triangles (perceptual) or texels (input), then save);
 * the ETA extrapolates the elapsed time over that fraction. Cancellation is checked between
 * stages here and inside stages by the stages themselves.
 * With params.evaluate, the whole-mesh loss q (evaluate.h) of the result against the input
 * is measured before saving and written to the statistics.
 * Does not: parse command lines or HTTP, or print. */
#include "pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "arap.h"
#include "budget.h"
#include "coverage.h"
#include "distortion.h"
#include "evaluate.h"
#include "gltf_io.h"
#include "gltf_tangents.h"
#include "mesh.h"
#include "meshwise.h"
#include "meshwise_loss.h"
#include "model.h"
#include "rebake.h"
#include "ssp.h"
#include "stats.h"
#include "tewari.h"
#include "texture_filter.h"
#include "triopt.h"

/* Shares of the job per stage, per method, in order: load, [per domain stages], save. */
typedef struct stage_weights {
    double load, stage1, stage2, pack, bake, save;
} stage_weights;

static const stage_weights input_weights = {0.15, 0, 0, 0, 0.70, 0.15};
static const stage_weights perceptual_weights = {0.02, 0.78, 0.08, 0.03, 0.06, 0.03};
#define EVALUATE_WEIGHT 0.1 /* share of the job taken from the middle when params.evaluate */

/* Wraps the caller's monitor: inner stages report their own stage_fraction, this maps it
 * into [from, to] of the job and adds the ETA. */
typedef struct job_monitor {
    const texopt_monitor *outer;
    texopt_monitor inner;
    double start;
    double from, to;
} job_monitor;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void forward_progress(void *user, const texopt_progress *p)
{
    job_monitor *jm = user;
    texopt_progress q = *p;
    double sf = p->stage_fraction < 0 ? 0 : (p->stage_fraction > 1 ? 1 : p->stage_fraction);
    q.fraction = jm->from + (jm->to - jm->from) * sf;
    double elapsed = now_seconds() - jm->start;
    q.eta_seconds = q.fraction > 0.01 ? elapsed * (1 - q.fraction) / q.fraction : -1;
    texopt_monitor_report(jm->outer, &q);
}

static void job_monitor_init(job_monitor *jm, const texopt_monitor *outer)
{
    memset(jm, 0, sizeof *jm);
    jm->outer = outer;
    jm->start = now_seconds();
    jm->inner.on_progress = forward_progress;
    jm->inner.user = jm;
    jm->inner.cancel = outer ? outer->cancel : NULL;
}

/* Sets the job range of the next stage and reports its start. */
static void job_stage(job_monitor *jm, const char *stage, double from, double to)
{
    jm->from = from;
    jm->to = to;
    texopt_progress p = {.stage = stage, .stage_fraction = 0, .eta_seconds = -1};
    forward_progress(jm, &p);
}

static void job_stage_done(job_monitor *jm, const char *stage)
{
    texopt_progress p = {.stage = stage, .stage_fraction = 1, .eta_seconds = -1};
    forward_progress(jm, &p);
}

static texopt_status check_cancel(const job_monitor *jm, char *err, size_t err_len)
{
    if (texopt_monitor_canceled(&jm->inner))
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "job canceled");
    return TEXOPT_OK;
}

static const char *slot_name(int slot)
{
    static const char *const names[TEXOPT_SLOT_COUNT] = {"baseColor", "normal", "metallicRoughness",
                                                         "occlusion", "emissive"};
    return slot >= 0 && slot < TEXOPT_SLOT_COUNT ? names[slot] : NULL;
}

/* The first material slot (through TEXCOORD_0) that reads image, or -1. */
static int image_slot(const texopt_model *model, int image)
{
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++)
        for (int m = 0; m < model->material_count; m++) {
            const texopt_texture_ref *r = &model->materials[m].slot[s];
            if (r->image == image && r->texcoord == 0)
                return s;
        }
    return -1;
}

/* Wrap modes the image is read with (of the first slot that binds it). */
static void image_wrap(const texopt_model *model, int image, texopt_wrap *ws, texopt_wrap *wt)
{
    *ws = *wt = TEXOPT_WRAP_REPEAT;
    for (int m = 0; m < model->material_count; m++)
        for (int s = 0; s < TEXOPT_SLOT_COUNT; s++) {
            const texopt_texture_ref *r = &model->materials[m].slot[s];
            if (r->image == image && r->texcoord == 0) {
                *ws = r->wrap_s;
                *wt = r->wrap_t;
                return;
            }
        }
}

static int scaled_side(int side, double factor)
{
    long v = lround(side * factor);
    return v < 1 ? 1 : (v > 16384 ? 16384 : (int)v);
}

/* Everything one domain's processing produces for the save step. */
typedef struct job_output {
    texopt_image *images;        /* per model image; empty when kept */
    const texopt_image **edit_images;
    float *uvs;                  /* new TEXCOORD_0 of every model vertex, NULL when unchanged */
} job_output;

static void job_output_destroy(job_output *o, int image_count)
{
    if (o->images)
        for (int i = 0; i < image_count; i++)
            texopt_image_destroy(&o->images[i]);
    free(o->images);
    free(o->edit_images);
    free(o->uvs);
}

static texopt_status record_images(const texopt_model *model, const texopt_domain *dom,
                                   texopt_domain_stats *ds, char *err, size_t err_len)
{
    ds->images = calloc((size_t)(dom->image_count > 0 ? dom->image_count : 1), sizeof *ds->images);
    if (!ds->images)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for image statistics");
    ds->image_count = dom->image_count;
    for (int i = 0; i < dom->image_count; i++) {
        int im = dom->images[i];
        texopt_image_stats *s = &ds->images[i];
        s->image = im;
        s->name = model->image_names ? model->image_names[im] : NULL;
        s->slot = slot_name(image_slot(model, im));
        s->input_width = model->images[im].width;
        s->input_height = model->images[im].height;
    }
    return TEXOPT_OK;
}

/* Output size of one image of the domain: proportional to the domain frame's new size. */
static void image_output_size(const texopt_image *img, const texopt_domain *dom, int out_w,
                              int out_h, int *w, int *h)
{
    *w = scaled_side(img->width, (double)out_w / dom->width);
    *h = scaled_side(img->height, (double)out_h / dom->height);
}

/* Cost of the unchanged layout in its input frame and in the resized frame (the same UVs
 * seen on the new texel grid), with the domain's wrap modes. */
static texopt_status input_layout_costs(const texopt_mesh *mesh, int ow, int oh,
                                        texopt_domain_stats *ds, char *err, size_t err_len)
{
    texopt_coverage in, out;
    texopt_status st = texopt_coverage_measure(mesh, NULL, &in, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double *texel = malloc(sizeof(double) * 2 * (mesh->vertex_count ? mesh->vertex_count : 1));
    if (!texel)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the resized layout");
    double kx = (double)ow / mesh->width, ky = (double)oh / mesh->height;
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        texel[2 * v] = mesh->texel[2 * v] * kx;
        texel[2 * v + 1] = mesh->texel[2 * v + 1] * ky;
    }
    texopt_coverage_options o = {0};
    o.texel = texel;
    o.width = ow;
    o.height = oh;
    st = texopt_coverage_measure(mesh, &o, &out, err, err_len);
    free(texel);
    if (st != TEXOPT_OK)
        return st;
    ds->cost_input = (double)in.covered_texels;
    ds->cost_output = (double)out.covered_texels;
    ds->relative_cost = in.covered_texels ? (double)out.covered_texels / (double)in.covered_texels : 0;
    ds->packing_efficiency_input = in.packing_efficiency;
    ds->packing_efficiency = out.packing_efficiency;
    return TEXOPT_OK;
}

/* params.threads, or every online core when it is 0. */
static int worker_threads(const texopt_params *params)
{
    if (params->threads > 0)
        return params->threads;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

/* Method "input": same UVs, every image of the domain resampled to the budget. */
static texopt_status run_input_method(const texopt_model *model, const texopt_mesh *mesh,
                                      const texopt_params *params, job_output *out,
                                      texopt_domain_stats *ds, job_monitor *jm, double from,
                                      double to, char *err, size_t err_len)
{
    const texopt_domain *dom = &model->domains[mesh->domain];
    int ow, oh;
    if (params->budget == TEXOPT_BUDGET_TEXTURE_SIZE) {
        ow = params->texture_width;
        oh = params->texture_height;
    } else {
        double s = sqrt(params->relative_cost);
        ow = scaled_side(dom->width, s);
        oh = scaled_side(dom->height, s);
    }
    ds->output_width = ow;
    ds->output_height = oh;
    double t0 = now_seconds();
    for (int i = 0; i < dom->image_count; i++) {
        int im = dom->images[i];
        const texopt_image *src = &model->images[im];
        texopt_image_stats *is = &ds->images[i];
        job_stage(jm, "bake", from + (to - from) * i / dom->image_count,
                  from + (to - from) * (i + 1) / dom->image_count);
        texopt_status st = check_cancel(jm, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        int w, h;
        image_output_size(src, dom, ow, oh, &w, &h);
        is->output_width = w;
        is->output_height = h;
        if (w == src->width && h == src->height)
            continue; /* the identity: keep the file's own bytes */
        if (!src->pixels)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "image %d (%s) was not decoded", im,
                               is->name ? is->name : "unnamed");
        texopt_wrap ws, wt;
        image_wrap(model, im, &ws, &wt);
        st = texopt_image_create(&out->images[im], w, h, src->channels, err, err_len);
        if (st == TEXOPT_OK)
            st = texopt_texture_resize(src, ws, wt, &out->images[im], worker_threads(params), err, err_len);
        if (st != TEXOPT_OK)
            return st;
        out->edit_images[im] = &out->images[im];
        is->rewritten = 1;
    }
    ds->seconds_bake = now_seconds() - t0;
    return input_layout_costs(mesh, ow, oh, ds, err, err_len);
}

/* A copy of the model's TEXCOORD_0 (zeros where it has none) that domains overwrite. */
static texopt_status alloc_uvs(const texopt_model *model, float **uvs, char *err, size_t err_len)
{
    size_t n = 2 * (model->vertex_count > 0 ? model->vertex_count : 1);
    *uvs = calloc(n, sizeof **uvs);
    if (!*uvs)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for new UVs");
    if (model->uvs)
        memcpy(*uvs, model->uvs, 2 * model->vertex_count * sizeof **uvs);
    return TEXOPT_OK;
}

/* Stage-1 statistics from the targets: loss at the optimum, area scale, share within eps. */
static void record_stage1(const texopt_mesh *mesh, const texopt_triangle_target *targets,
                          const texopt_triopt_report *rep, double epsilon, texopt_domain_stats *ds)
{
    double sum = 0, max = 0, area = 0;
    size_t n = 0, within = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (targets[t].evaluations <= 0)
            continue;
        n++;
        sum += targets[t].loss;
        max = fmax(max, targets[t].loss);
        area += targets[t].lambda1 * targets[t].lambda2;
        within += targets[t].loss <= epsilon;
    }
    ds->has_stage1 = 1;
    ds->loss_mean = n ? sum / n : 0;
    ds->loss_max = max;
    ds->area_scale_mean = n ? area / n : 0;
    ds->within_epsilon_share = n ? (double)within / n : 0;
    ds->evaluations = rep->evaluations;
}

static void record_stage2(const texopt_meshwise_report *rep, texopt_domain_stats *ds)
{
    ds->has_stage2 = 1;
    ds->stage2_iterations = rep->iterations;
    ds->energy_initial = rep->energy_initial;
    ds->energy_final = rep->energy_final;
    ds->flipped = (size_t)rep->flipped;
}

static void record_distortion(const texopt_mesh *mesh, const double *texel, texopt_domain_stats *ds)
{
    texopt_distortion in, out;
    /* Distortion is a report, not a product: a layout it cannot measure (every triangle
     * degenerate) still bakes, and the JSON then leaves the field out. */
    if (texopt_distortion_measure(mesh, NULL, &in, NULL, 0) == TEXOPT_OK &&
        texopt_distortion_measure(mesh, texel, &out, NULL, 0) == TEXOPT_OK) {
        ds->has_distortion = 1;
        ds->distortion_input = in.symmetric_dirichlet;
        ds->distortion_output = out.symmetric_dirichlet;
    }
}

/* The per-triangle targets stage 2 follows: the perceptual stage 1 (triopt.h), or the
 * baselines' metric targets (ssp.h, tewari.h, arap.h; rotation weight 0). */
static texopt_status baseline_or_perceptual_targets(const texopt_model *model, const texopt_mesh *mesh,
                                                    const texopt_params *params,
                                                    const texopt_triopt_options *topt,
                                                    texopt_triangle_target *targets,
                                                    texopt_triopt_report *trep, job_monitor *jm,
                                                    char *err, size_t err_len)
{
    switch (params->method) {
    case TEXOPT_METHOD_SSP:
        return texopt_ssp_targets(model, mesh, params->lambda_min, targets, err, err_len);
    case TEXOPT_METHOD_TEWARI:
        return texopt_tewari_targets(model, mesh, params->lambda_min, targets, err, err_len);
    case TEXOPT_METHOD_ARAP:
        return texopt_arap_targets(mesh, targets, err, err_len);
    default:
        return texopt_triopt_run(model, mesh, topt, targets, trep, &jm->inner, err, err_len);
    }
}

/* Stage 1 (or a baseline's targets) then stage 2: the new layout in input texel units. */
static texopt_status optimise_layout(const texopt_model *model, const texopt_mesh *mesh,
                                     const texopt_params *params, double *texel_new,
                                     texopt_domain_stats *ds, job_monitor *jm, double from,
                                     double to, char *err, size_t err_len)
{
    const stage_weights *w = &perceptual_weights;
    double span = (to - from) / (w->stage1 + w->stage2 + w->pack + w->bake);
    texopt_triangle_target *targets = calloc(mesh->triangle_count ? mesh->triangle_count : 1, sizeof *targets);
    if (!targets)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu triangle targets", mesh->triangle_count);
    texopt_triopt_options topt = {0};
    topt.epsilon = params->epsilon;
    topt.iterations = params->iterations;
    topt.lambda_min = params->lambda_min;
    topt.threads = params->threads;
    topt.seed = params->seed;
    texopt_triopt_report trep = {0};
    job_stage(jm, "stage1", from, from + span * w->stage1);
    double t0 = now_seconds();
    texopt_status st = baseline_or_perceptual_targets(model, mesh, params, &topt, targets, &trep,
                                                      jm, err, err_len);
    ds->seconds_stage1 = now_seconds() - t0;
    if (st == TEXOPT_OK) {
        if (params->method == TEXOPT_METHOD_PERCEPTUAL)
            record_stage1(mesh, targets, &trep, params->epsilon, ds);
        job_stage_done(jm, "stage1");
        st = check_cancel(jm, err, err_len);
    }
    if (st == TEXOPT_OK) {
        texopt_meshwise_options mopt = {0};
        mopt.threads = params->threads > 0 ? params->threads : 2;
        texopt_meshwise_report mrep;
        job_stage(jm, "stage2", from + span * w->stage1, from + span * (w->stage1 + w->stage2));
        t0 = now_seconds();
        st = texopt_meshwise_solve(mesh, targets, NULL, &mopt, texel_new, &mrep, &jm->inner, err, err_len);
        ds->seconds_stage2 = now_seconds() - t0;
        if (st == TEXOPT_OK)
            record_stage2(&mrep, ds);
        /* Paper Fig. 16: the share of triangles whose loss under the solved layout (before
         * the budget scales it) still meets eps. One loss evaluation per triangle: about 1%
         * of stage 1, but the bulk of a baseline's run, so baselines pay it only when the
         * job asks for an evaluation. */
        int want_share = params->method == TEXOPT_METHOD_PERCEPTUAL || params->evaluate;
        texopt_loss_share share;
        t0 = now_seconds();
        if (st == TEXOPT_OK && want_share)
            st = texopt_meshwise_loss_share(model, mesh, texel_new, params->epsilon, params->threads, 0,
                                            NULL, &share, &jm->inner, err, err_len);
        if (st == TEXOPT_OK && want_share) {
            ds->has_loss_share = 1;
            ds->solved_within_epsilon_share = share.share;
            ds->solved_loss_mean = share.mean_loss;
            ds->solved_loss_max = share.max_loss;
            ds->seconds_loss_share = now_seconds() - t0;
        }
    }
    free(targets);
    return st;
}

/* Writes the new UVs of the domain's model vertices (output texels / output size). */
static void write_domain_uvs(const texopt_model *model, const texopt_mesh *mesh, const double *texel,
                             int width, int height, float *uvs)
{
    const texopt_domain *dom = &model->domains[mesh->domain];
    size_t local = 0;
    for (int i = 0; i < dom->primitive_count; i++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[i]];
        for (size_t k = 0; k < prim->vertex_count && local < mesh->model_vertex_count; k++, local++) {
            uint32_t v = mesh->vertex_of_model_vertex[local];
            uvs[2 * (prim->first_vertex + k)] = (float)(texel[2 * v] / width);
            uvs[2 * (prim->first_vertex + k) + 1] = (float)(texel[2 * v + 1] / height);
        }
    }
}

/* Whether the bake must turn the image's tangent-space XY with the layout (rebake.h): only
 * for a normal map of a domain whose primitives leave tangents to the renderer. */
static int normal_map_needs_rotation(const texopt_model *model, const texopt_domain *dom, int image)
{
    int normal = 0;
    for (int m = 0; m < model->material_count; m++)
        normal |= model->materials[m].slot[TEXOPT_SLOT_NORMAL].image == image;
    for (int i = 0; normal && i < dom->primitive_count; i++)
        if (texopt_primitive_has_tangents(model, dom->primitives[i]))
            return 0;
    return normal;
}

/* Re-bakes every image of the domain from the input layout into the packed one. */
static texopt_status rebake_domain(const texopt_model *model, const texopt_mesh *mesh,
                                   const double *packed, int width, int height, int threads,
                                   job_output *out, texopt_domain_stats *ds, job_monitor *jm,
                                   double from, double to, char *err, size_t err_len)
{
    const texopt_domain *dom = &model->domains[mesh->domain];
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    double *uv_in = malloc(n * sizeof *uv_in), *uv_out = malloc(n * sizeof *uv_out);
    if (!uv_in || !uv_out) {
        free(uv_in);
        free(uv_out);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the bake layouts");
    }
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        uv_in[2 * v] = mesh->texel[2 * v] / mesh->width;
        uv_in[2 * v + 1] = mesh->texel[2 * v + 1] / mesh->height;
        uv_out[2 * v] = packed[2 * v] / width;
        uv_out[2 * v + 1] = packed[2 * v + 1] / height;
    }
    texopt_rebake_layout layout = {mesh->triangle_count, mesh->triangle, uv_in, uv_out, threads};
    texopt_status st = TEXOPT_OK;
    for (int i = 0; i < dom->image_count && st == TEXOPT_OK; i++) {
        int im = dom->images[i];
        const texopt_image *src = &model->images[im];
        texopt_image_stats *is = &ds->images[i];
        job_stage(jm, "bake", from + (to - from) * i / dom->image_count,
                  from + (to - from) * (i + 1) / dom->image_count);
        if (!src->pixels) {
            st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "image %d (%s) was not decoded", im,
                             is->name ? is->name : "unnamed");
            break;
        }
        int w, h;
        image_output_size(src, dom, width, height, &w, &h);
        is->output_width = w;
        is->output_height = h;
        texopt_wrap ws, wt;
        image_wrap(model, im, &ws, &wt);
        st = texopt_image_create(&out->images[im], w, h, src->channels, err, err_len);
        if (st == TEXOPT_OK)
            st = texopt_rebake_image(src, ws, wt, normal_map_needs_rotation(model, dom, im), &layout,
                                     &out->images[im], NULL, &jm->inner, err, err_len);
        if (st == TEXOPT_OK) {
            out->edit_images[im] = &out->images[im];
            is->rewritten = 1;
        }
    }
    free(uv_in);
    free(uv_out);
    return st;
}

/* Methods "perceptual" and the baselines: targets, stage 2, budget + pack, re-bake. */
static texopt_status run_optimised_method(const texopt_model *model, const texopt_mesh *mesh,
                                          const texopt_params *params, job_output *out,
                                          texopt_domain_stats *ds, job_monitor *jm, double from,
                                          double to, char *err, size_t err_len)
{
    const stage_weights *w = &perceptual_weights;
    double span = (to - from) / (w->stage1 + w->stage2 + w->pack + w->bake);
    double pack_from = from + span * (w->stage1 + w->stage2), bake_from = pack_from + span * w->pack;
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    double *texel_new = malloc(n * sizeof(double)), *packed = malloc(n * sizeof(double));
    texopt_coverage in_cov;
    texopt_status st = texel_new && packed ? TEXOPT_OK
                                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the new layout");
    if (st == TEXOPT_OK)
        st = texopt_coverage_measure(mesh, NULL, &in_cov, err, err_len);
    if (st == TEXOPT_OK)
        st = optimise_layout(model, mesh, params, texel_new, ds, jm, from, pack_from, err, err_len);
    if (st == TEXOPT_OK)
        st = check_cancel(jm, err, err_len);
    texopt_budget_result br = {0};
    if (st == TEXOPT_OK) {
        job_stage(jm, "pack", pack_from, bake_from);
        record_distortion(mesh, texel_new, ds);
        texopt_budget_request req = {0};
        req.kind = params->budget;
        req.relative_cost = params->relative_cost;
        req.texture_width = params->texture_width;
        req.texture_height = params->texture_height;
        req.input_cost = (double)in_cov.covered_texels;
        req.input_width = mesh->width;
        req.input_height = mesh->height;
        req.monitor = &jm->inner;
        double t0 = now_seconds();
        st = texopt_budget_fit(mesh, texel_new, &req, packed, &br, err, err_len);
        ds->seconds_pack = now_seconds() - t0;
        job_stage_done(jm, "pack");
    }
    if (st == TEXOPT_OK) {
        ds->output_width = br.width;
        ds->output_height = br.height;
        ds->cost_input = (double)in_cov.covered_texels;
        ds->cost_output = br.cost;
        ds->relative_cost = br.relative_cost;
        ds->packing_efficiency_input = in_cov.packing_efficiency;
        ds->packing_efficiency = br.packing_efficiency;
        ds->repacked = 1;
        double t0 = now_seconds();
        st = rebake_domain(model, mesh, packed, br.width, br.height, worker_threads(params), out, ds,
                           jm, bake_from, to, err, err_len);
        ds->seconds_bake = now_seconds() - t0;
    }
    if (st == TEXOPT_OK)
        write_domain_uvs(model, mesh, packed, br.width, br.height, out->uvs);
    free(texel_new);
    free(packed);
    return st;
}

static texopt_status run_domain(const texopt_model *model, int d, const texopt_params *params,
                                job_output *out, texopt_domain_stats *ds, job_monitor *jm,
                                double from, double to, char *err, size_t err_len)
{
    const texopt_domain *dom = &model->domains[d];
    ds->domain = d;
    ds->input_width = dom->width;
    ds->input_height = dom->height;
    ds->relative_cost_requested = params->budget == TEXOPT_BUDGET_RELATIVE_COST ? params->relative_cost : -1;
    texopt_status st = record_images(model, dom, ds, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double t0 = now_seconds();
    texopt_mesh *mesh = NULL;
    st = texopt_mesh_create(&mesh, model, d, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    ds->seconds_mesh = now_seconds() - t0;
    ds->triangles = mesh->triangle_count;
    ds->charts = mesh->chart_count;
    if (params->method == TEXOPT_METHOD_INPUT)
        st = run_input_method(model, mesh, params, out, ds, jm, from, to, err, err_len);
    else
        st = run_optimised_method(model, mesh, params, out, ds, jm, from, to, err, err_len);
    texopt_mesh_destroy(mesh);
    return st;
}

static texopt_status prepare(const texopt_params *in, texopt_params *p, char *err, size_t err_len)
{
    if (!in)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params missing");
    *p = *in;
    texopt_params_resolve(p);
    texopt_status st = texopt_params_validate(p, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    if (p->budget == TEXOPT_BUDGET_TARGET_LOSS)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "budget target_loss is not implemented yet; use relative_cost or texture_size");
    return TEXOPT_OK;
}

static void fill_job_params(texopt_job_stats *js, const texopt_params *p)
{
    js->method = texopt_method_name(p->method);
    js->budget = p->budget == TEXOPT_BUDGET_TEXTURE_SIZE ? "texture_size" : "relative_cost";
    js->relative_cost = p->relative_cost;
    if (p->budget == TEXOPT_BUDGET_TEXTURE_SIZE) {
        js->texture_width = p->texture_width;
        js->texture_height = p->texture_height;
    }
    js->epsilon = p->epsilon;
    js->lambda_min = p->lambda_min;
    js->iterations = p->iterations;
    js->threads = p->threads;
    js->seed = (unsigned long long)p->seed;
}

/* The domains' share of the middle of the job: by triangles (perceptual) or texels (input). */
static double domain_weight(const texopt_model *model, int d, int method)
{
    if (method == TEXOPT_METHOD_INPUT)
        return (double)model->domains[d].width * model->domains[d].height;
    double n = 0;
    for (int i = 0; i < model->domains[d].primitive_count; i++)
        n += (double)model->primitives[model->domains[d].primitives[i]].triangle_count;
    return n;
}

static texopt_status alloc_output(const texopt_model *model, job_output *out, char *err, size_t err_len)
{
    size_t n = (size_t)(model->image_count > 0 ? model->image_count : 1);
    out->images = calloc(n, sizeof *out->images);
    out->edit_images = calloc(n, sizeof *out->edit_images);
    if (!out->images || !out->edit_images)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the output images");
    return TEXOPT_OK;
}

static texopt_status run_domains(const texopt_model *model, const texopt_params *p, job_output *out,
                                 texopt_job_stats *js, job_monitor *jm, const stage_weights *w,
                                 double tail, char *err, size_t err_len)
{
    js->domains = calloc((size_t)(model->domain_count > 0 ? model->domain_count : 1), sizeof *js->domains);
    if (!js->domains)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for domain statistics");
    js->domain_count = model->domain_count;
    double total = 0;
    for (int d = 0; d < model->domain_count; d++)
        total += domain_weight(model, d, p->method);
    double middle = 1.0 - w->load - w->save - tail, at = w->load;
    for (int d = 0; d < model->domain_count; d++) {
        double share = total > 0 ? middle * domain_weight(model, d, p->method) / total : 0;
        texopt_status st = check_cancel(jm, err, err_len);
        if (st == TEXOPT_OK) {
            jm->from = at;
            jm->to = at + share;
            st = run_domain(model, d, p, out, &js->domains[d], jm, at, at + share, err, err_len);
        }
        if (st != TEXOPT_OK)
            return st;
        at += share;
    }
    return TEXOPT_OK;
}

/* The whole-mesh loss q (evaluate.h) of the result against the input, before saving: the
 * candidate is the input model seen through the new UVs and images (a shallow view that
 * owns nothing). */
static texopt_status evaluate_result(const texopt_model *model, const job_output *out,
                                     const texopt_params *p, texopt_job_stats *js, job_monitor *jm,
                                     char *err, size_t err_len)
{
    texopt_image *images = calloc((size_t)(model->image_count > 0 ? model->image_count : 1), sizeof *images);
    float *uvs = out->uvs;
    if (!images)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the evaluation");
    for (int i = 0; i < model->image_count; i++)
        images[i] = out->edit_images[i] ? *out->edit_images[i] : model->images[i];
    texopt_model candidate = *model;
    candidate.images = images;
    if (uvs)
        candidate.uvs = uvs;
    candidate.document = NULL;
    candidate.destroy_document = NULL;
    texopt_evaluate_options opt = {0};
    opt.resolution = p->eval_resolution;
    opt.threads = p->threads > 0 ? p->threads : 2;
    opt.monitor = &jm->inner;
    texopt_evaluation ev;
    texopt_status st = texopt_evaluate(model, &candidate, &opt, &ev, err, err_len);
    free(images);
    if (st == TEXOPT_OK) {
        js->has_evaluation = 1;
        js->q = ev.q;
        js->eval_resolution = ev.resolution;
        js->seconds_evaluate = ev.seconds;
    }
    return st;
}

texopt_status texopt_optimize_file(const char *input_path, const char *output_glb,
                                   const char *stats_json, const texopt_params *params,
                                   const texopt_monitor *monitor, char *err, size_t err_len)
{
    if (!input_path || !output_glb)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "input and output paths are required");
    texopt_params p;
    texopt_status st = prepare(params, &p, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const stage_weights *w = p.method == TEXOPT_METHOD_INPUT ? &input_weights : &perceptual_weights;
    double tail = p.evaluate ? EVALUATE_WEIGHT : 0;
    job_monitor jm;
    job_monitor_init(&jm, monitor);
    texopt_job_stats js = {0};
    fill_job_params(&js, &p);
    texopt_model *model = NULL;
    job_output out = {0};

    job_stage(&jm, "load", 0, w->load);
    double t0 = now_seconds();
    st = texopt_model_load(&model, input_path, NULL, err, err_len);
    js.seconds_load = now_seconds() - t0;
    if (st == TEXOPT_OK && model->domain_count == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "%s has no textured primitive", input_path);
    if (st == TEXOPT_OK) {
        job_stage_done(&jm, "load");
        st = alloc_output(model, &out, err, err_len);
    }
    if (st == TEXOPT_OK && p.method != TEXOPT_METHOD_INPUT)
        st = alloc_uvs(model, &out.uvs, err, err_len);
    if (st == TEXOPT_OK)
        st = run_domains(model, &p, &out, &js, &jm, w, tail, err, err_len);
    if (st == TEXOPT_OK)
        st = check_cancel(&jm, err, err_len);
    if (st == TEXOPT_OK && p.evaluate) {
        job_stage(&jm, "evaluate", 1.0 - w->save - EVALUATE_WEIGHT, 1.0 - w->save);
        st = evaluate_result(model, &out, &p, &js, &jm, err, err_len);
    }
    if (st == TEXOPT_OK) {
        job_stage(&jm, "save", 1.0 - w->save, 1.0);
        t0 = now_seconds();
        texopt_model_edit edit = {out.uvs, out.edit_images};
        st = texopt_model_save_glb(model, &edit, output_glb, err, err_len);
        js.seconds_save = now_seconds() - t0;
    }
    js.seconds_total = now_seconds() - jm.start;
    if (st == TEXOPT_OK && stats_json)
        st = texopt_stats_write(&js, stats_json, err, err_len);
    if (st == TEXOPT_OK)
        job_stage_done(&jm, "save");
    job_output_destroy(&out, model ? model->image_count : 0);
    texopt_job_stats_destroy(&js);
    texopt_model_destroy(model);
    return st;
}
