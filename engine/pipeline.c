/* pipeline.c - one whole job: load, optimise every texture domain, re-bake, save, report.
 *
 * Implements engine/pipeline.h, the product of Sun et al. 2022, "Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen", end to end, in two parts:
 *   job_create (budget-independent): load (io/gltf_io) -> per texture domain: mesh, input
 *     coverage, charts sharing texels (texel_share.h), per-triangle targets (stage 1,
 *     triopt.h, or a baseline's);
 *   job_write (per budget): per domain: allocate.h rescales the targets to the budget
 *     (perceptual) ->
 *     stage 2 (meshwise.h, each sharing group's secondaries tied to its primary) ->
 *     budget.h packs the charts anew, a sharing group as one, and corrects the scale ->
 *     re-bake every image of the domain -> [evaluate] -> save .glb -> statistics (stats.h).
 * Methods:
 *   "perceptual": stage 1 targets; up to five candidate layouts per budget, the targets
 *     allocated to the budget (allocate.h) up to input density and up to 1.5x it, the
 *     targets as they are (a uniform scale by the budget), and the signal metrics' targets
 *     (tewari.h, ssp.h) as those methods lay them out. The candidates bake only base colour
 *     (all q looks at) and are evaluated in one pass (whole-mesh loss q, evaluate.h, on the
 *     icosahedron's 12 views, not on the 20 the reported q uses: CHOICE_CAMERAS); the
 *     best of stage 1's, and the best metric one when its q is lower, are refined in closed
 *     loop from their on-screen error per triangle (refine_best, refine_kept, on the same
 *     views; with params.refine_lit lit, every image baked, when the material has maps a
 *     light reads), the one lower after its rounds is kept and its other images are baked
 *     after that.
 *   "input": the input layout kept as it is (UVs untouched, seams, overlaps and wrapping
 *     included) and each texture resized with Lanczos-3 (lanczos.h, Pillow's rules) to the
 *     budget: a relative cost c_r scales both sides by sqrt(c_r) (rounded to whole texels),
 *     a texture size is taken as given. This is the paper's "input parameterization"
 *     baseline, the resize an asset pipeline would do, and a useful product on its own.
 *   "ssp", "tewari", "arap": the baselines of the paper's section 5 (ssp.h, tewari.h,
 *     arap.h targets in place of stage 1, rotation weight 0), solved as they are, then the
 *     same stage 2, budget (a uniform scale), packing and re-bake as "perceptual".
 * A domain whose layout covers no texel centre (UVs picking a colour from a palette), none
 * of whose triangles has an area in 3D, or one of whose textures is magnified NEAREST (pixel
 * art, whose texel blocks no new layout keeps on their grid) is kept as it is by every layout
 * method (keep_domain); a model with no other domain is refused. A domain whose UVs repeat its
 * texture (a tiling texture, layout_repeats) keeps its input layout resized as by method
 * "input": an atlas would need the repeats' texels. A domain whose new layout would pack into
 * over twice the pixels of its input layout resized to the budget, or fit a texture size at
 * no scale (charts of a texel or less, mostly gutter), keeps its input layout resized as by
 * method "input" (input_layout_packs_better); so does one whose new layout fails the layout
 * check (layout_check.h: overlap, fold-over or a triangle far above its target;
 * layout_fails_check). The statistics' costs are measured on the written file (file_cost.h).
 * Budgets: a relative cost is allocated as asked; a texture size at the cost it is expected
 * to reach (texels x typical packing efficiency), solved again once at the cost reached
 * when that misses by more than 10%, and refused above 4 times the pixels of the images it
 * re-bakes (check_texture_size_budget); target_loss searches the relative cost (compare.h,
 * bisection on log c_r) repeating only the per-budget part, each step evaluated in memory.
 * Normal maps: their tangent-space XY turn with the layout (rebake.h) unless the domain's
 * primitives store TANGENT (io/gltf_tangents.h): stored tangents are kept by the saver, and
 * the map must then stay as it was.
 * Progress: every stage's own stage_fraction is mapped into a fixed share of the job (load,
 * then per domain in proportion to its triangles (perceptual) or texels (input), then save);
 * the ETA extrapolates the elapsed time over that fraction. Cancellation is checked between
 * stages here and inside stages by the stages themselves.
 * With params.evaluate, the whole-mesh loss q (evaluate.h) of the result against the input
 * is measured before saving and written to the statistics.
 * Every rendering here (the candidates' choice, the refinement's screens, target_loss's steps,
 * evaluate) uses the lookups of params.mipmapped: a layout tuned on bilinear screens spends
 * texels on matching the input's unfiltered minification, which a mip-mapped renderer does
 * not show (BENCHMARKS.md@9f788a8 "Tuned for the lookups it is judged with").
 * Does not: parse command lines or HTTP, or print. */
#include "pipeline.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "allocate.h"
#include "arap.h"
#include "budget.h"
#include "compare.h"
#include "coverage.h"
#include "distortion.h"
#include "evaluate.h"
#include "file_cost.h"
#include "gltf_io.h"
#include "gltf_tangents.h"
#include "lanczos.h"
#include "layout_check.h"
#include "lit_shade.h"
#include "lit_weight.h"
#include "map_check.h"
#include "mesh.h"
#include "meshwise.h"
#include "meshwise_loss.h"
#include "model.h"
#include "parallel.h"
#include "rebake.h"
#include "ssp.h"
#include "stats.h"
#include "tewari.h"
#include "texel_share.h"
#include "texture_filter.h"
#include "triopt.h"

/* Shares of the job per stage, per method, in order: load, [per domain stages], save. */
typedef struct stage_weights {
    double load, stage1, stage2, pack, bake, save;
} stage_weights;

static const stage_weights input_weights = {0.15, 0, 0, 0, 0.70, 0.15};
static const stage_weights perceptual_weights = {0.02, 0.78, 0.08, 0.03, 0.06, 0.03};
#define MAX_BAKE_WORKERS 8 /* images of one domain baked at once, at most */
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

/* The name of the first binding, in slot order then extension textures, that reads image
 * through TEXCOORD_0 in any material, or NULL. */
static const char *image_binding_name(const texopt_model *model, int image)
{
    for (int b = 0; b < TEXOPT_SLOT_COUNT + TEXOPT_EXTRA_TEXTURES_MAX; b++)
        for (int m = 0; m < model->material_count; m++) {
            const texopt_material *mat = &model->materials[m];
            if (b >= texopt_material_binding_count(mat))
                continue;
            const texopt_texture_ref *r = texopt_material_binding(mat, b);
            if (r->image == image && r->texcoord == 0)
                return texopt_material_binding_name(mat, b);
        }
    return NULL;
}

/* Wrap modes the image is read with (of the first binding that reads it). */
static void image_wrap(const texopt_model *model, int image, texopt_wrap *ws, texopt_wrap *wt)
{
    *ws = *wt = TEXOPT_WRAP_REPEAT;
    for (int m = 0; m < model->material_count; m++) {
        const texopt_material *mat = &model->materials[m];
        for (int b = 0; b < texopt_material_binding_count(mat); b++) {
            const texopt_texture_ref *r = texopt_material_binding(mat, b);
            if (r->image == image && r->texcoord == 0) {
                *ws = r->wrap_s;
                *wt = r->wrap_t;
                return;
            }
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
    int domain_count;
    double **solved;             /* per domain: stage 2's layout in input texels (kept for
                                    the loss share of a chosen candidate), NULL when none */
    double **packed;             /* per domain: the packed layout in output texels (kept to
                                    bake a chosen candidate's remaining images), NULL when none */
    int *packed_size;            /* per domain: its output width and height */
    unsigned char *draft;        /* per model image: baked with the prefilter only (bake_plan
                                    BAKE_DRAFT_REST), to be baked again before it is saved */
} job_output;

static void job_output_destroy(job_output *o, int image_count)
{
    if (o->images)
        for (int i = 0; i < image_count; i++)
            texopt_image_destroy(&o->images[i]);
    free(o->images);
    free(o->edit_images);
    free(o->draft);
    free(o->uvs);
    for (int d = 0; d < o->domain_count; d++) {
        free(o->solved[d]);
        free(o->packed[d]);
    }
    free(o->solved);
    free(o->packed);
    free(o->packed_size);
    memset(o, 0, sizeof *o);
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
        s->slot = image_binding_name(model, im);
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

/* The domain frame's size under method "input" at the budget of params. */
static void input_method_frame(const texopt_domain *dom, const texopt_params *params, int *ow, int *oh)
{
    if (params->budget == TEXOPT_BUDGET_TEXTURE_SIZE) {
        *ow = params->texture_width;
        *oh = params->texture_height;
    } else {
        double s = sqrt(params->relative_cost);
        *ow = scaled_side(dom->width, s);
        *oh = scaled_side(dom->height, s);
    }
}

/* Method "input": same UVs, every image of the domain resized to the budget with Lanczos-3
 * (lanczos.h), as an asset pipeline would resize it. */
static texopt_status run_input_method(const texopt_model *model, const texopt_mesh *mesh,
                                      const texopt_params *params, job_output *out,
                                      texopt_domain_stats *ds, job_monitor *jm, double from,
                                      double to, char *err, size_t err_len)
{
    const texopt_domain *dom = &model->domains[mesh->domain];
    int ow, oh;
    input_method_frame(dom, params, &ow, &oh);
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
        st = texopt_image_create(&out->images[im], w, h, src->channels, err, err_len);
        if (st == TEXOPT_OK)
            st = texopt_lanczos_resize(src, &out->images[im], worker_threads(params), err, err_len);
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
    ds->close_up_triangles = rep->close_up_triangles;
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
        ds->distortion_in = in;
        ds->distortion_out = out;
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

/* The targets a layout starts from: stage 1's (or a baseline's), or a signal metric's
 * (perceptual's metric candidates). */
typedef enum target_source { SOURCE_STAGE1 = 0, SOURCE_HESSIAN, SOURCE_STRETCH } target_source;

/* What a layout method does with a domain. */
typedef enum domain_keep {
    DOMAIN_LAID_OUT = 0,
    DOMAIN_KEPT_AS_IS,    /* nothing to lay out or see (keep_domain): UVs and images as they are */
    DOMAIN_INPUT_RESIZED, /* a tiling texture (layout_repeats): the input layout, resized as by
                             method "input" */
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
    double *paid; /* per triangle, the share of its texels it pays for (allocate.h); NULL
                     when every triangle pays for all of its own */
    domain_keep kept; /* laid out, or the input layout kept (and why: stats input_layout_kept) */
} job_domain;

/* The sharing groups stage 2 and the budget work with, NULL when no chart shares another's
 * texels (the layout is then exactly what it is without them). */
static const texopt_texel_share *sharing(const job_domain *jd)
{
    return jd->share && jd->share->secondary_count > 0 ? jd->share : NULL;
}

/* Which images a run bakes, and how. A candidate bakes only what the evaluation that
 * judges it reads; the images left out are baked for the kept layout alone
 * (bake_remaining_images). The lit refinement's rounds read every image and are mostly
 * thrown away: BAKE_DRAFT_REST drafts the maps base colour's evaluation does not read with
 * the prefilter alone (rebake.h; a fraction of the least-squares fit's time), to be baked
 * again with the fit for the saved layout. Normal maps are fitted even then: their detail
 * shows in every highlight, and rounds judged on blurred normal drafts ended 1-6% higher in
 * lit q on DamagedHelmet (BENCHMARKS.md@9f788a8 "Cheaper lit refinement"). */
typedef enum bake_plan {
    BAKE_ALL = 0,    /* every image not baked yet or drafted, with the fit */
    BAKE_EVALUATED,  /* the images base colour's evaluation reads */
    BAKE_DRAFT_REST, /* those and normal maps with the fit, the others drafted */
} bake_plan;

struct texopt_job {
    texopt_params params;
    texopt_model *model;
    job_domain *domains;       /* model->domain_count */
    texopt_job_stats stats;
    job_monitor jm;
    double budget_from;        /* the job's progress where the budget's part begins */
    const stage_weights *weights;
    double allocating;         /* > 0: the run in progress allocates the targets (allocate.h),
                                  singular values capped at this */
    bake_plan plan;            /* which images the run in progress bakes, and how */
    texopt_triangle_target **refined; /* per domain, when not NULL: the run in progress solves
                                         these targets as they are (refine_kept) */
    target_source source;      /* the targets the run in progress starts from */
    double *signal_weights;    /* per image, how much of each signal a lit render shows
                                  (lit_weight.h): stage 1's loss compares them so scaled */
};

static void stage1_options(const texopt_params *params, texopt_triopt_options *topt)
{
    memset(topt, 0, sizeof *topt);
    topt->epsilon = params->epsilon;
    topt->iterations = params->iterations;
    topt->lambda_min = params->lambda_min;
    topt->threads = params->threads;
    topt->seed = params->seed;
}

/* The signal metrics' targets perceptual uses beside stage 1 (params.h): the Hessian
 * metric's (tewari.h) for the floor, both it and the signal-stretch metric's (ssp.h) as
 * candidate layouts (run_best_budget). Stage 1's targets are raised to the floor
 * (TEXOPT_DEFAULT_HESSIAN_FLOOR): the slivers whose one-ring hides their detail from stage 1
 * get at least k^2 of tewari's area. *raised: how many targets it raised. */
static texopt_status add_metric_targets(const texopt_model *model, const texopt_mesh *mesh,
                                        const texopt_params *params, job_domain *jd, size_t *raised, char *err,
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
    texopt_status st = texopt_tewari_targets(model, mesh, params->lambda_min, jd->hessian, err, err_len);
    if (st == TEXOPT_OK && candidates)
        st = texopt_ssp_targets(model, mesh, params->lambda_min, jd->stretch, err, err_len);
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

/* How many times over a domain's layout reads its texels: the texel area its triangles pay
 * for (texel_share.h: mirrored twins and folds pay once) over the texels they cover. 1.000 to
 * 1.005 on the sample assets; a texture tiled 4 x 4 times gives 16. */
static double layout_repeats(const job_domain *jd)
{
    double paid_area = 0;
    for (size_t t = 0; t < jd->mesh->triangle_count; t++)
        paid_area += fabs(jd->mesh->area_texel[t]) * (jd->paid ? jd->paid[t] : 1.0);
    return paid_area / (double)jd->input_coverage.covered_texels;
}

/* A domain whose layout reads its texels more than this many times over keeps its input
 * layout (DOMAIN_INPUT_RESIZED): unrolled into an atlas, a texture tiled R times needs R times
 * its texels for the same look, so at an equal budget every layout method's result is far
 * worse than the tiling (a 64x64 checker tiled 4 x 4 at c_r 0.5: q 0.0160 laid out anew,
 * 0.0009 resized in its layout). */
#define REPEATS_LIMIT 1.5

/* Whether every triangle of the mesh is degenerate in 3D (mesh.h). */
static int flat_in_3d(const texopt_mesh *mesh)
{
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (!(mesh->flags[t] & TEXOPT_TRI_DEGENERATE_3D))
            return 0;
    return 1;
}

/* The budget-independent part of one domain: mesh, input coverage, targets (stage 1). */
static texopt_status prepare_domain(texopt_job *job, int d, double from, double to, char *err,
                                    size_t err_len)
{
    const texopt_model *model = job->model;
    const texopt_params *params = &job->params;
    job_domain *jd = &job->domains[d];
    texopt_domain_stats *ds = &job->stats.domains[d];
    const texopt_domain *dom = &model->domains[d];
    ds->domain = d;
    ds->input_width = dom->width;
    ds->input_height = dom->height;
    texopt_status st = record_images(model, dom, ds, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double t0 = now_seconds();
    st = texopt_mesh_create(&jd->mesh, model, d, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    ds->seconds_mesh = now_seconds() - t0;
    ds->triangles = jd->mesh->triangle_count;
    ds->charts = jd->mesh->chart_count;
    if (params->method == TEXOPT_METHOD_INPUT)
        return TEXOPT_OK;
    if (flat_in_3d(jd->mesh)) {
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "its %zu triangles have no area in 3D (every vertex on a line or a point), so nothing of it can be "
                 "seen and no layout judged", jd->mesh->triangle_count);
        jd->kept = DOMAIN_KEPT_AS_IS;
        return TEXOPT_OK;
    }
    st = texopt_coverage_measure(jd->mesh, NULL, &jd->input_coverage, err, err_len);
    if (st == TEXOPT_OK && jd->input_coverage.covered_texels == 0) {
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "its layout covers no texel centre of its %dx%d texture, so it has no texels to lay out (a texture "
                 "of one texel, or UVs inside one texel)", dom->width, dom->height);
        jd->kept = DOMAIN_KEPT_AS_IS;
        return TEXOPT_OK;
    }
    if (st == TEXOPT_OK && dom->nearest_image >= 0) {
        /* The loader names an image without URI or name "image N": said once, not twice. */
        const char *name = model->image_names ? model->image_names[dom->nearest_image] : NULL;
        char label[160];
        snprintf(label, sizeof label, name && strncmp(name, "image ", 6) != 0 ? "image %d (%s)" : "image %d",
                 dom->nearest_image, name);
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "its %s is magnified NEAREST (sampler magFilter, pixel art): its texels show as blocks, which a new "
                 "layout would resample off their grid, blurred and misaligned", label);
        jd->kept = DOMAIN_KEPT_AS_IS;
        return TEXOPT_OK;
    }
    if (st == TEXOPT_OK)
        st = texopt_texel_share_create(&jd->share, jd->mesh, err, err_len);
    if (st == TEXOPT_OK)
        st = find_paid_shares(jd, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double repeats = layout_repeats(jd);
    if (repeats > REPEATS_LIMIT) {
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "its UVs repeat its %dx%d texture %.1f times over (a tiling texture): a layout without repeats "
                 "would need that many times its texels; the input layout is kept, its images resized to the "
                 "budget", dom->width, dom->height, repeats);
        jd->kept = DOMAIN_INPUT_RESIZED;
        return TEXOPT_OK;
    }
    size_t n = jd->mesh->triangle_count ? jd->mesh->triangle_count : 1;
    jd->targets = calloc(n, sizeof *jd->targets);
    if (!jd->targets)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu triangle targets", n);
    texopt_triopt_options topt;
    stage1_options(params, &topt);
    texopt_triopt_report trep = {0};
    job_stage(&job->jm, "stage1", from, to);
    t0 = now_seconds();
    topt.signal_weights = job->signal_weights;
    st = baseline_or_perceptual_targets(model, jd->mesh, params, &topt, jd->targets, &trep, &job->jm,
                                        err, err_len);
    if (st == TEXOPT_OK && params->method == TEXOPT_METHOD_PERCEPTUAL)
        st = add_metric_targets(model, jd->mesh, params, jd, &ds->hessian_floor_triangles, err, err_len);
    ds->seconds_stage1 = now_seconds() - t0;
    if (st == TEXOPT_OK && params->method == TEXOPT_METHOD_PERCEPTUAL)
        record_stage1(jd->mesh, jd->targets, &trep, params->epsilon, ds);
    if (st == TEXOPT_OK)
        job_stage_done(&job->jm, "stage1");
    return st;
}

/* The perceptual targets' allocation (allocate.h), the best of the variants measured with
 * the whole-mesh evaluation (BENCHMARKS.md@9f788a8 "Quality"): lossless optima (flat colour at
 * lambda_min) grow only by sqrt(s) (kept at lambda_min, q rose with the cost). The cap is
 * the candidate's (run_best_budget). */
static const texopt_allocate_options perceptual_allocation = {1, 1e-6, 1.0, 0.5, NULL};

/* perceptual_allocation for one domain with singular values capped at cap: its triangles
 * lying on texels others pay for (folds, sharing groups) cost nothing, so the targets add up
 * to covered texels, the budget's unit (without it DamagedHelmet's allocation saw half its
 * budget). */
static texopt_allocate_options domain_allocation(const job_domain *jd, double cap)
{
    texopt_allocate_options o = perceptual_allocation;
    o.cap = cap;
    o.paid = jd->paid;
    return o;
}

/* The targets the run in progress starts from (job->source). */
static const texopt_triangle_target *source_targets(const texopt_job *job, const job_domain *jd)
{
    if (job->source == SOURCE_HESSIAN && jd->hessian)
        return jd->hessian;
    if (job->source == SOURCE_STRETCH && jd->stretch)
        return jd->stretch;
    return jd->targets;
}

/* The targets, rescaled to relative cost c_r when job->allocating (allocate.h, a
 * perceptual candidate), solved by stage 2 into texel_new (input texel units). The baselines' targets are solved as they are
 * and the budget scales the result uniformly: for ssp and tewari (whose largest targets are
 * normalised to 1, not to "needs input density") the allocation measured worse or no
 * better (BENCHMARKS.md@9f788a8 "Quality"); arap's are isometric. */
static texopt_status solve_layout(const texopt_job *job, int d, double relative_cost, double *texel_new,
                                  texopt_domain_stats *ds, job_monitor *jm, char *err, size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    const texopt_mesh *mesh = jd->mesh;
    const texopt_params *params = &job->params;
    const texopt_triangle_target *targets = source_targets(job, jd);
    texopt_triangle_target *allocated = NULL;
    texopt_status st = TEXOPT_OK;
    double t0 = now_seconds();
    ds->has_allocation = 0;
    if (job->refined && job->refined[d])
        targets = job->refined[d];
    else if (job->allocating) {
        allocated = malloc((mesh->triangle_count ? mesh->triangle_count : 1) * sizeof *allocated);
        if (!allocated)
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the allocated targets");
        texopt_allocation rep;
        double area = relative_cost * (double)jd->input_coverage.covered_texels;
        texopt_allocate_options o = domain_allocation(jd, job->allocating);
        st = texopt_allocate_targets(mesh, targets, area > 0 ? area : 1, &o, allocated, &rep, err, err_len);
        if (st == TEXOPT_OK) {
            size_t n = mesh->triangle_count ? mesh->triangle_count : 1;
            ds->has_allocation = 1;
            ds->allocation_scale = rep.scale;
            ds->allocation_capped_share = (double)rep.capped / (double)n;
            ds->allocation_lossless_share = (double)rep.lossless / (double)n;
            targets = allocated;
        }
    }
    if (st == TEXOPT_OK) {
        texopt_meshwise_options mopt = {0};
        mopt.threads = params->threads > 0 ? params->threads : 2;
        mopt.share = sharing(jd);
        texopt_meshwise_report mrep;
        st = texopt_meshwise_solve(mesh, targets, NULL, &mopt, texel_new, &mrep, &jm->inner, err, err_len);
        if (st == TEXOPT_OK)
            record_stage2(&mrep, ds);
    }
    ds->seconds_stage2 = now_seconds() - t0;
    free(allocated);
    return st;
}

/* Paper Fig. 16: the share of triangles whose loss under the solved layout still meets eps.
 * One loss evaluation per triangle: about 1% of stage 1 but the bulk of a baseline's run,
 * so it is measured only for statistics that are written, and for baselines only when the
 * job asks for an evaluation. */
static texopt_status measure_loss_share(const texopt_job *job, int d, const double *texel_new,
                                        texopt_domain_stats *ds, job_monitor *jm, char *err, size_t err_len)
{
    const texopt_params *params = &job->params;
    if (params->method != TEXOPT_METHOD_PERCEPTUAL && !params->evaluate)
        return TEXOPT_OK;
    texopt_loss_share share;
    double t0 = now_seconds();
    texopt_status st =
        texopt_meshwise_loss_share(job->model, job->domains[d].mesh, texel_new, job->signal_weights, params->epsilon,
                                   params->threads, 0, NULL, &share, &jm->inner, err, err_len);
    if (st == TEXOPT_OK) {
        ds->has_loss_share = 1;
        ds->solved_within_epsilon_share = share.share;
        ds->solved_loss_mean = share.mean_loss;
        ds->solved_loss_max = share.max_loss;
        ds->seconds_loss_share = now_seconds() - t0;
    }
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

/* Whether a binding reads the image as a tangent-space normal map (the normal slot, or an
 * extension's such as clearcoatNormalTexture). */
static int image_is_normal_map(const texopt_model *model, int image)
{
    for (int m = 0; m < model->material_count; m++) {
        const texopt_material *mat = &model->materials[m];
        for (int b = 0; b < texopt_material_binding_count(mat); b++)
            if (texopt_material_binding(mat, b)->image == image &&
                texopt_material_binding_kind(mat, b) == TEXOPT_TEXTURE_NORMAL)
                return 1;
    }
    return 0;
}

/* Whether the bake must turn the image's tangent-space XY with the layout (rebake.h): only
 * for a normal map of a domain whose primitives leave tangents to the renderer. */
static int normal_map_needs_rotation(const texopt_model *model, const texopt_domain *dom, int image)
{
    int normal = image_is_normal_map(model, image);
    for (int i = 0; normal && i < dom->primitive_count; i++)
        if (texopt_primitive_has_tangents(model, dom->primitives[i]))
            return 0;
    return normal;
}

/* Whether the whole-mesh evaluation (meshrender.h) reads the image: a base colour bound
 * through TEXCOORD_0. */
static int image_is_evaluated(const texopt_model *model, int image)
{
    for (int m = 0; m < model->material_count; m++) {
        const texopt_texture_ref *r = &model->materials[m].slot[TEXOPT_SLOT_BASE_COLOR];
        if (r->image == image && r->texcoord == 0)
            return 1;
    }
    return 0;
}

/* Whether the plan bakes image im (not baked yet, or a draft to bake again). */
static int plan_bakes(const texopt_model *model, bake_plan plan, const job_output *out, int im)
{
    if (plan == BAKE_ALL)
        return !out->edit_images[im] || out->draft[im];
    return !out->edit_images[im] && (plan == BAKE_DRAFT_REST || image_is_evaluated(model, im));
}

/* Bakes image i of the domain (its output size already in the statistics) into out, a
 * draft of it where BAKE_DRAFT_REST says so. */
static texopt_status bake_image(const texopt_model *model, const texopt_domain *dom, int i, bake_plan plan,
                                const texopt_rebake_layout *layout, job_output *out, texopt_domain_stats *ds,
                                const texopt_monitor *monitor, char *err, size_t err_len)
{
    int im = dom->images[i];
    const texopt_image *src = &model->images[im];
    texopt_image_stats *is = &ds->images[i];
    int draft = plan == BAKE_DRAFT_REST && !image_is_evaluated(model, im) && !image_is_normal_map(model, im);
    texopt_wrap ws, wt;
    image_wrap(model, im, &ws, &wt);
    out->edit_images[im] = NULL;
    out->draft[im] = 0;
    texopt_image_destroy(&out->images[im]);
    texopt_status st = texopt_image_create(&out->images[im], is->output_width, is->output_height, src->channels,
                                           err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_rebake_image_fit(src, ws, wt, normal_map_needs_rotation(model, dom, im), layout,
                                     draft ? TEXOPT_REBAKE_FIT_PREFILTER : TEXOPT_REBAKE_FIT_DEFAULT,
                                     &out->images[im], NULL, monitor, err, err_len);
    if (st == TEXOPT_OK) {
        out->edit_images[im] = &out->images[im];
        out->draft[im] = (unsigned char)draft;
        is->rewritten = 1;
    }
    return st;
}

/* Several images of a domain baked at once, one thread each: a bake scales about 1.5x on
 * two threads (BENCHMARKS.md@9f788a8 "End to end"), whole images side by side nearly 2x, and the
 * re-bake's result does not depend on its thread count. Progress per finished image. */
typedef struct bake_pool {
    const texopt_model *model;
    const texopt_domain *dom;
    const texopt_rebake_layout *layout; /* threads = 1 */
    bake_plan plan;
    job_output *out;
    texopt_domain_stats *ds;
    const int *todo; /* image indices within the domain */
    int count;
    atomic_int next;
    texopt_monitor cancel_only; /* the job's cancel flag, no progress (reported here) */
    job_monitor *jm;
    double from, to;
    pthread_mutex_t lock; /* guards done, status, err and the job monitor */
    int done;
    texopt_status status;
    char err[512];
} bake_pool;

static void *bake_pool_worker(void *arg)
{
    bake_pool *bp = arg;
    char err[512] = "";
    for (;;) {
        int k = atomic_fetch_add(&bp->next, 1);
        if (k >= bp->count)
            break;
        texopt_status st = bake_image(bp->model, bp->dom, bp->todo[k], bp->plan, bp->layout, bp->out, bp->ds,
                                      &bp->cancel_only, err, sizeof err);
        pthread_mutex_lock(&bp->lock);
        if (st != TEXOPT_OK && bp->status == TEXOPT_OK) {
            bp->status = st;
            snprintf(bp->err, sizeof bp->err, "%s", err);
        }
        bp->done++;
        job_stage(bp->jm, "bake", bp->from + (bp->to - bp->from) * bp->done / bp->count, bp->to);
        pthread_mutex_unlock(&bp->lock);
        if (st != TEXOPT_OK) {
            atomic_store(&bp->next, bp->count);
            break;
        }
    }
    return NULL;
}

static texopt_status bake_images_side_by_side(bake_pool *bp, int workers, char *err, size_t err_len)
{
    atomic_init(&bp->next, 0);
    pthread_mutex_init(&bp->lock, NULL);
    texopt_parallel_run(bake_pool_worker, bp, 0, workers);
    pthread_mutex_destroy(&bp->lock);
    if (bp->status != TEXOPT_OK)
        return texopt_fail(err, err_len, bp->status, "%s", bp->err);
    return TEXOPT_OK;
}

/* Re-bakes the images of the domain that the plan names from the input layout into the
 * packed one. */
static texopt_status rebake_domain(const texopt_model *model, const texopt_mesh *mesh,
                                   const double *packed, int width, int height, int threads,
                                   bake_plan plan, job_output *out, texopt_domain_stats *ds,
                                   job_monitor *jm, double from, double to, char *err, size_t err_len)
{
    const texopt_domain *dom = &model->domains[mesh->domain];
    int *todo = malloc((size_t)(dom->image_count > 0 ? dom->image_count : 1) * sizeof *todo), count = 0;
    if (!todo)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the bake list");
    for (int i = 0; i < dom->image_count; i++) {
        int im = dom->images[i];
        const texopt_image *src = &model->images[im];
        texopt_image_stats *is = &ds->images[i];
        if (!src->pixels) {
            free(todo);
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "image %d (%s) was not decoded", im,
                               is->name ? is->name : "unnamed");
        }
        image_output_size(src, dom, width, height, &is->output_width, &is->output_height);
        if (plan_bakes(model, plan, out, im))
            todo[count++] = i;
    }
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    double *uv_in = malloc(n * sizeof *uv_in), *uv_out = malloc(n * sizeof *uv_out);
    if (!uv_in || !uv_out) {
        free(uv_in);
        free(uv_out);
        free(todo);
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
    int workers = threads < count ? threads : count;
    if (workers > MAX_BAKE_WORKERS)
        workers = MAX_BAKE_WORKERS;
    if (workers >= 2) {
        layout.threads = 1;
        bake_pool bp = {.model = model, .dom = dom, .layout = &layout, .plan = plan, .out = out, .ds = ds, .todo = todo,
                        .count = count, .cancel_only = {NULL, NULL, jm->inner.cancel}, .jm = jm,
                        .from = from, .to = to};
        job_stage(jm, "bake", from, to);
        st = bake_images_side_by_side(&bp, workers, err, err_len);
    }
    for (int k = 0; workers < 2 && k < count && st == TEXOPT_OK; k++) {
        job_stage(jm, "bake", from + (to - from) * k / count, from + (to - from) * (k + 1) / count);
        st = bake_image(model, dom, todo[k], plan, &layout, out, ds, &jm->inner, err, err_len);
    }
    free(todo);
    free(uv_in);
    free(uv_out);
    return st;
}

/* Texture-size budgets are allocated at the relative cost they are expected to reach: the
 * texture's texels times the packing efficiency budget.h typically achieves (0.61-0.81 on
 * the sample models, BENCHMARKS.md@9f788a8 "End to end"). A miss by more than RESOLVE_RATIO is
 * solved once more at the cost reached. */
#define EXPECTED_PACKING_EFFICIENCY 0.68
#define RESOLVE_RATIO 1.1

static void budget_request(const texopt_job *job, const job_domain *jd, const texopt_params *p, job_monitor *jm,
                           texopt_budget_request *req)
{
    memset(req, 0, sizeof *req);
    req->kind = p->budget;
    req->relative_cost = p->relative_cost;
    req->texture_width = p->texture_width;
    req->texture_height = p->texture_height;
    req->input_cost = (double)jd->input_coverage.covered_texels;
    req->input_width = jd->mesh->width;
    req->input_height = jd->mesh->height;
    req->targets = source_targets(job, jd); /* charts free to rotate are turned to their smallest box */
    req->reshape_efficiency = p->packing_efficiency;
    req->threads = worker_threads(p);
    req->keep_shape = sharing(jd) ? jd->share->grouped : NULL;
    req->monitor = &jm->inner;
}

/* Allocation, stage 2, budget + pack: the packed layout in output texels. */
static texopt_status layout_for_budget(const texopt_job *job, int d, const texopt_params *p,
                                       double *texel_new, double *packed, texopt_budget_result *br,
                                       texopt_domain_stats *ds, job_monitor *jm, double from,
                                       double split, double to, char *err, size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    double cost = p->relative_cost;
    if (p->budget == TEXOPT_BUDGET_TEXTURE_SIZE)
        cost = (double)p->texture_width * p->texture_height * EXPECTED_PACKING_EFFICIENCY /
               (double)(jd->input_coverage.covered_texels ? jd->input_coverage.covered_texels : 1);
    texopt_budget_request req;
    budget_request(job, jd, p, jm, &req);
    texopt_status st = TEXOPT_OK;
    for (int round = 0; round < 2 && st == TEXOPT_OK; round++) {
        job_stage(jm, "stage2", from, split);
        st = solve_layout(job, d, cost, texel_new, ds, jm, err, err_len);
        if (st == TEXOPT_OK)
            st = check_cancel(jm, err, err_len);
        if (st != TEXOPT_OK)
            break;
        job_stage(jm, "pack", split, to);
        double t0 = now_seconds();
        /* a sharing group packs as one chart, its secondaries on the primary's texels */
        const texopt_mesh *charts = sharing(jd) ? &jd->share->view : jd->mesh;
        st = texopt_budget_fit(charts, texel_new, &req, packed, br, err, err_len);
        ds->seconds_pack = now_seconds() - t0;
        if (st != TEXOPT_OK || p->budget != TEXOPT_BUDGET_TEXTURE_SIZE || !job->allocating ||
            fabs(log(br->relative_cost / cost)) <= log(RESOLVE_RATIO) || !(br->relative_cost > 0))
            break;
        cost = br->relative_cost;
    }
    if (st == TEXOPT_OK) {
        ds->budget_scale = br->scale;
        job_stage_done(jm, "pack");
    }
    return st;
}

/* Charts of a few texels or less (a palette's colour spots, each face an island of its own)
 * pack mostly gutter: such a layout's texture can take many times the pixels of the input
 * layout's at the same budget (a 64x64 palette of 4,212 spots at c_r 0.3: 28x3056 against
 * 35x35, BENCHMARKS.md@9f788a8 "Palette models"), or fit a texture size at no scale. The domain then
 * keeps its input layout, its images resized to the budget as by method "input": a budget met
 * with over twice the pixels the input layout needs for it is not what was asked for. The
 * sample assets' perceptual layouts take 0.62-1.06 times the input layout's pixels at c_r 0.1,
 * where gutter weighs most. */
#define WASTED_PIXELS_LIMIT 2.0

/* Whether the domain keeps its input layout rather than the layout of *br (st: the budget's
 * status), with the reason in ds. */
static int input_layout_packs_better(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *p,
                                     const texopt_budget_result *br, texopt_status st, texopt_domain_stats *ds)
{
    int ow, oh;
    input_method_frame(&model->domains[mesh->domain], p, &ow, &oh);
    if (st == TEXOPT_E_LIMIT && br->no_fit) {
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "the new layout fits %dx%d at no scale (%zu chart%s); the input layout is kept, its images resized "
                 "to %dx%d", ow, oh, mesh->chart_count, mesh->chart_count == 1 ? "" : "s", ow, oh);
        return 1;
    }
    double ratio = (double)br->width * br->height / ((double)ow * oh);
    if (st != TEXOPT_OK || ratio <= WASTED_PIXELS_LIMIT)
        return 0;
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "the new layout packs its %zu chart%s into %dx%d, %.1fx the pixels the input layout needs at this "
             "budget (%dx%d), mostly gutter; the input layout is kept, its images resized to %dx%d",
             mesh->chart_count, mesh->chart_count == 1 ? "" : "s", br->width, br->height, ratio, ow, oh, ow, oh);
    return 1;
}

/* Whether the packed layout fails the layout check (layout_check.h, against the targets it
 * was solved from), recorded in ds, with the reason in ds->input_layout_kept; *st: the
 * check's status. */
static int layout_fails_check(const texopt_job *job, int d, const double *packed, const texopt_budget_result *br,
                              const texopt_params *p, texopt_domain_stats *ds, texopt_status *st, char *err,
                              size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    const texopt_triangle_target *targets = job->refined && job->refined[d] ? job->refined[d] : source_targets(job, jd);
    texopt_layout_check *c = &ds->layout_check;
    ds->has_layout_check = 1;
    double t0 = now_seconds();
    *st = texopt_layout_check_run(jd->mesh, packed, br->width, br->height, jd->share ? jd->share->primary_of : NULL,
                                  targets, c, err, err_len);
    ds->seconds_layout_check = now_seconds() - t0;
    if (*st != TEXOPT_OK || c->failed == TEXOPT_LAYOUT_PASSED)
        return 0;
    int ow, oh;
    input_method_frame(&job->model->domains[d], p, &ow, &oh);
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "the new layout failed the layout check (%s: %zu triangles, model triangle %u first); the input layout "
             "is kept, its images resized to %dx%d", texopt_layout_failure_name(c->failed),
             c->failed == TEXOPT_LAYOUT_OVERLAP ? c->overlapping
             : c->failed == TEXOPT_LAYOUT_FOLDOVER ? c->folded : c->oversized, c->triangles[0], ow, oh);
    return 1;
}

/* Methods "perceptual" and the baselines at one budget: allocation, stage 2, budget + pack,
 * re-bake; or the input layout resized (input_layout_packs_better, layout_fails_check). */
static texopt_status run_optimised_method(const texopt_job *job, int d, const texopt_params *p,
                                          int with_stats, job_output *out, texopt_domain_stats *ds,
                                          job_monitor *jm, double from, double to, char *err, size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    const texopt_mesh *mesh = jd->mesh;
    const stage_weights *w = &perceptual_weights;
    double span = (to - from) / (w->stage2 + w->pack + w->bake);
    double pack_from = from + span * w->stage2, bake_from = pack_from + span * w->pack;
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    double *texel_new = malloc(n * sizeof(double)), *packed = malloc(n * sizeof(double));
    texopt_status st = texel_new && packed ? TEXOPT_OK
                                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the new layout");
    texopt_budget_result br = {0};
    ds->input_layout_kept[0] = '\0';
    if (st == TEXOPT_OK)
        st = layout_for_budget(job, d, p, texel_new, packed, &br, ds, jm, from, pack_from, bake_from, err, err_len);
    ds->has_layout_check = 0;
    if (input_layout_packs_better(job->model, mesh, p, &br, st, ds) ||
        (st == TEXOPT_OK && layout_fails_check(job, d, packed, &br, p, ds, &st, err, err_len))) {
        free(texel_new);
        free(packed);
        ds->repacked = 0;
        return run_input_method(job->model, mesh, p, out, ds, jm, bake_from, to, err, err_len);
    }
    if (st == TEXOPT_OK && with_stats)
        st = measure_loss_share(job, d, texel_new, ds, jm, err, err_len);
    if (st == TEXOPT_OK) {
        record_distortion(mesh, texel_new, ds);
        ds->output_width = br.width;
        ds->output_height = br.height;
        ds->cost_input = (double)jd->input_coverage.covered_texels;
        ds->cost_output = br.cost;
        ds->relative_cost = br.relative_cost;
        ds->packing_efficiency_input = jd->input_coverage.packing_efficiency;
        ds->packing_efficiency = br.packing_efficiency;
        ds->repacked = 1;
        double t0 = now_seconds();
        st = rebake_domain(job->model, mesh, packed, br.width, br.height, worker_threads(p),
                           job->plan, out, ds, jm, bake_from, to, err, err_len);
        ds->seconds_bake = now_seconds() - t0;
    }
    if (st == TEXOPT_OK)
        write_domain_uvs(job->model, mesh, packed, br.width, br.height, out->uvs);
    if (st == TEXOPT_OK && out->solved) {
        out->solved[d] = texel_new;
        texel_new = NULL;
        out->packed[d] = packed;
        packed = NULL;
        out->packed_size[2 * d] = br.width;
        out->packed_size[2 * d + 1] = br.height;
    }
    free(texel_new);
    free(packed);
    return st;
}

/* The domains' share of a part of the job: by triangles (perceptual) or texels (input). */
static double domain_weight(const texopt_model *model, int d, int method)
{
    if (method == TEXOPT_METHOD_INPUT)
        return (double)model->domains[d].width * model->domains[d].height;
    double n = 0;
    for (int i = 0; i < model->domains[d].primitive_count; i++)
        n += (double)model->primitives[model->domains[d].primitives[i]].triangle_count;
    return n;
}

static double total_domain_weight(const texopt_model *model, int method)
{
    double total = 0;
    for (int d = 0; d < model->domain_count; d++)
        total += domain_weight(model, d, method);
    return total;
}

static texopt_status alloc_output(const texopt_model *model, int method, job_output *out, char *err,
                                  size_t err_len)
{
    size_t n = (size_t)(model->image_count > 0 ? model->image_count : 1);
    out->images = calloc(n, sizeof *out->images);
    out->edit_images = calloc(n, sizeof *out->edit_images);
    out->draft = calloc(n, sizeof *out->draft);
    if (!out->images || !out->edit_images || !out->draft)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the output images");
    if (method == TEXOPT_METHOD_INPUT)
        return TEXOPT_OK;
    size_t n_domains = (size_t)(model->domain_count > 0 ? model->domain_count : 1);
    out->solved = calloc(n_domains, sizeof *out->solved);
    out->packed = calloc(n_domains, sizeof *out->packed);
    out->packed_size = calloc(2 * n_domains, sizeof *out->packed_size);
    if (!out->solved || !out->packed || !out->packed_size)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the solved layouts");
    out->domain_count = model->domain_count;
    return alloc_uvs(model, &out->uvs, err, err_len);
}

/* A domain with no texels to lay out (a colour picked from a palette, a texture of one texel),
 * nothing to see or pixel art keeps its UVs (alloc_uvs copied them) and its images' bytes,
 * whatever the budget: the model's other domains are laid out as asked. */
static void keep_domain(const texopt_model *model, int d, texopt_domain_stats *ds)
{
    const texopt_domain *dom = &model->domains[d];
    ds->output_width = dom->width;
    ds->output_height = dom->height;
    ds->cost_input = ds->cost_output = ds->relative_cost = 0;
    ds->packing_efficiency_input = ds->packing_efficiency = 0;
    ds->repacked = 0;
    for (int i = 0; i < ds->image_count; i++) {
        ds->images[i].output_width = ds->images[i].input_width;
        ds->images[i].output_height = ds->images[i].input_height;
        ds->images[i].rewritten = 0;
    }
}

/* Every domain at the budget of p (relative cost or texture size) into *out (allocated
 * here), with its statistics in job->stats; progress over [from, to] of the job. */
static texopt_status run_budget(texopt_job *job, const texopt_params *p, int with_stats, job_output *out,
                                double from, double to, char *err, size_t err_len)
{
    const texopt_model *model = job->model;
    texopt_status st = alloc_output(model, p->method, out, err, err_len);
    double total = total_domain_weight(model, p->method), at = from;
    for (int d = 0; d < model->domain_count && st == TEXOPT_OK; d++) {
        double share = total > 0 ? (to - from) * domain_weight(model, d, p->method) / total : 0;
        texopt_domain_stats *ds = &job->stats.domains[d];
        ds->relative_cost_requested = p->budget == TEXOPT_BUDGET_RELATIVE_COST ? p->relative_cost : -1;
        st = check_cancel(&job->jm, err, err_len);
        if (st == TEXOPT_OK && job->domains[d].kept == DOMAIN_KEPT_AS_IS)
            keep_domain(model, d, ds);
        else if (st == TEXOPT_OK &&
                 (p->method == TEXOPT_METHOD_INPUT || job->domains[d].kept == DOMAIN_INPUT_RESIZED))
            st = run_input_method(model, job->domains[d].mesh, p, out, ds, &job->jm, at, at + share, err, err_len);
        else if (st == TEXOPT_OK)
            st = run_optimised_method(job, d, p, with_stats, out, ds, &job->jm, at, at + share, err, err_len);
        at += share;
    }
    return st;
}

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

static void fill_job_params(texopt_job_stats *js, const texopt_params *p)
{
    js->method = texopt_method_name(p->method);
    js->budget = p->budget == TEXOPT_BUDGET_TEXTURE_SIZE ? "texture_size"
                 : p->budget == TEXOPT_BUDGET_TARGET_LOSS ? "target_loss"
                                                          : "relative_cost";
    js->relative_cost = p->relative_cost;
    js->texture_width = p->budget == TEXOPT_BUDGET_TEXTURE_SIZE ? p->texture_width : 0;
    js->texture_height = p->budget == TEXOPT_BUDGET_TEXTURE_SIZE ? p->texture_height : 0;
    js->epsilon = p->epsilon;
    js->lambda_min = p->lambda_min;
    js->iterations = p->iterations;
    js->threads = p->threads;
    js->seed = (unsigned long long)p->seed;
    js->refinements = texopt_params_refinement_rounds(p);
    js->refine_lit = p->refine_lit != 0;
    js->mipmapped = p->mipmapped != 0;
    js->packing_efficiency = p->packing_efficiency;
}

#define MAX_EVALUATED_OUTPUTS 5 /* run_best_budget's candidates */

/* The views perceptual chooses its layout on (run_candidates, refine_kept,
 * keep_resize_if_better): the icosahedron's 12, not the dodecahedron's 20 that the reported q
 * is measured on (evaluate_output), so that q is judged on views the choice never saw. */
#define CHOICE_CAMERAS TEXOPT_CAMERAS_ICOSAHEDRON

/* The options of the pipeline's evaluations: q's resolution, the job's threads, its
 * monitor. */
static texopt_evaluate_options evaluation_options(const texopt_params *p, texopt_camera_set cameras, int lit,
                                                  job_monitor *jm)
{
    texopt_evaluate_options opt = {0};
    opt.resolution = p->eval_resolution;
    opt.threads = p->threads > 0 ? p->threads : 2;
    opt.monitor = &jm->inner;
    opt.cameras = cameras;
    opt.lit = lit;
    opt.mipmapped = p->mipmapped != 0;
    return opt;
}

/* Each of n outputs as the input model seen through its new UVs and images (a shallow view
 * that owns nothing but *images, which the caller frees). */
static texopt_status output_models(const texopt_model *model, const job_output *const *outs, int n,
                                   texopt_model *candidates, const texopt_model **shown, texopt_image **images,
                                   char *err, size_t err_len)
{
    if (n < 1 || n > MAX_EVALUATED_OUTPUTS)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "evaluation of %d outputs", n);
    size_t k = (size_t)(model->image_count > 0 ? model->image_count : 1);
    *images = calloc((size_t)n * k, sizeof **images);
    if (!*images)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the evaluation");
    for (int c = 0; c < n; c++) {
        texopt_image *own = *images + (size_t)c * k;
        for (int i = 0; i < model->image_count; i++)
            own[i] = outs[c]->edit_images[i] ? *outs[c]->edit_images[i] : model->images[i];
        candidates[c] = *model;
        candidates[c].images = own;
        if (outs[c]->uvs)
            candidates[c].uvs = outs[c]->uvs;
        candidates[c].document = NULL;
        candidates[c].destroy_document = NULL;
        shown[c] = &candidates[c];
    }
    return TEXOPT_OK;
}

/* q of every map (map_check.h) that shows domain (< 0: the whole model), for each of n outputs. */
static texopt_status evaluate_maps_on(const texopt_model *model, const job_output *const *outs, int n,
                                      const texopt_params *p, texopt_camera_set cameras, int domain,
                                      job_monitor *jm, texopt_map_q *q, char *err, size_t err_len)
{
    texopt_model candidates[MAX_EVALUATED_OUTPUTS];
    const texopt_model *shown[MAX_EVALUATED_OUTPUTS];
    texopt_image *images = NULL;
    texopt_status st = output_models(model, outs, n, candidates, shown, &images, err, err_len);
    int measured[TEXOPT_MAP_MEASURES];
    texopt_map_measures(model, domain, measured);
    texopt_evaluate_options opt = evaluation_options(p, cameras, 0, jm);
    if (st == TEXOPT_OK)
        st = texopt_map_evaluate(model, shown, n, &opt, measured, q, err, err_len);
    free(images);
    return st;
}

/* The whole-mesh loss q (evaluate.h) of each of n outputs against the input, in memory, in
 * one pass over the views (the input rendered once for all, or read from its kept views
 * when reference_views is not NULL): each candidate is the input model seen through the new
 * UVs and images (a shallow view that owns nothing). */
static texopt_status evaluate_outputs_on(const texopt_model *model, const job_output *const *outs, int n,
                                         const texopt_params *p, texopt_camera_set cameras, int lit,
                                         const texopt_evaluate_reference *reference_views, double *triangle_error,
                                         job_monitor *jm, texopt_evaluation *ev, char *err, size_t err_len)
{
    texopt_model candidates[MAX_EVALUATED_OUTPUTS];
    const texopt_model *shown[MAX_EVALUATED_OUTPUTS];
    texopt_image *images = NULL;
    texopt_status st = output_models(model, outs, n, candidates, shown, &images, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_evaluate_options opt = evaluation_options(p, cameras, lit, jm);
    opt.triangle_error = triangle_error;
    /* The refinement's measure (refine_kept); the lit refinement keeps the luma difference
     * it was measured with (the edge measure was measured on base colour only). */
    opt.triangle_error_edges = !lit;
    opt.reference_views = reference_views;
    st = texopt_evaluate_many(model, shown, n, &opt, ev, err, err_len);
    free(images);
    return st;
}

/* The reported q, as the paper and the benchmark define it: the dodecahedron's 20 views. */
static texopt_status evaluate_output(const texopt_model *model, const job_output *out, const texopt_params *p,
                                     job_monitor *jm, texopt_evaluation *ev, char *err, size_t err_len)
{
    return evaluate_outputs_on(model, &out, 1, p, TEXOPT_CAMERAS_DODECAHEDRON, 0, NULL, NULL, jm, ev, err, err_len);
}

static void free_domain_stats(texopt_domain_stats *ds, int n)
{
    if (ds)
        for (int d = 0; d < n; d++)
            free(ds[d].images);
    free(ds);
}

/* A copy of the job's per-domain statistics with image arrays of its own, so that two
 * candidates can each record theirs. */
static texopt_domain_stats *copy_domain_stats(const texopt_job_stats *js)
{
    int n = js->domain_count;
    texopt_domain_stats *c = calloc((size_t)(n > 0 ? n : 1), sizeof *c);
    for (int d = 0; c && d < n; d++) {
        c[d] = js->domains[d];
        c[d].images = NULL;
        size_t k = (size_t)(c[d].image_count > 0 ? c[d].image_count : 1);
        c[d].images = js->domains[d].images ? malloc(k * sizeof *c[d].images) : NULL;
        if (js->domains[d].images && !c[d].images) {
            free_domain_stats(c, n);
            return NULL;
        }
        if (c[d].images)
            memcpy(c[d].images, js->domains[d].images, k * sizeof *c[d].images);
    }
    return c;
}

/* One candidate of run_best_budget: its output, statistics and whole-mesh loss. */
typedef struct candidate {
    job_output out;
    texopt_domain_stats *domains;
    texopt_evaluation ev;
} candidate;

/* A layout of the budget as a candidate, baking the images the plan names. */
static texopt_status run_candidate(texopt_job *job, const texopt_params *p, double allocating, bake_plan plan,
                                   candidate *c, double from, double to, char *err, size_t err_len)
{
    texopt_domain_stats *job_domains = job->stats.domains;
    c->domains = copy_domain_stats(&job->stats);
    if (!c->domains)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for candidate statistics");
    job->stats.domains = c->domains;
    job->allocating = allocating;
    job->plan = plan;
    texopt_status st = run_budget(job, p, 0, &c->out, from, to, err, err_len);
    job->allocating = 0;
    job->plan = BAKE_ALL;
    job->stats.domains = job_domains;
    return st;
}

/* The per-triangle loss share (paper Fig. 16) of the kept candidate's solved layouts. */
static texopt_status measure_chosen_loss_share(texopt_job *job, const job_output *out, char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++)
        if (out->solved && out->solved[d])
            st = measure_loss_share(job, d, out->solved[d], &job->stats.domains[d], &job->jm, err, err_len);
    return st;
}

/* What a candidate's layouts and bakes took (its share of the statistics' stage seconds). */
static double candidate_seconds(const candidate *c, int domain_count)
{
    double s = 0;
    for (int d = 0; d < domain_count; d++)
        s += c->domains[d].seconds_stage2 + c->domains[d].seconds_pack + c->domains[d].seconds_bake;
    return s;
}

/* Bakes the images of a candidate that its run left out (bake_plan) into the layouts it
 * packed: under BAKE_ALL those and its drafts, as the saved model needs them. */
static texopt_status bake_remaining_images(texopt_job *job, const texopt_params *p, bake_plan plan, job_output *out,
                                           double from, double to, char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    int n = job->model->domain_count;
    for (int d = 0; d < n && st == TEXOPT_OK; d++) {
        if (!out->packed || !out->packed[d])
            continue;
        texopt_domain_stats *ds = &job->stats.domains[d];
        double t0 = now_seconds();
        st = rebake_domain(job->model, job->domains[d].mesh, out->packed[d], out->packed_size[2 * d],
                           out->packed_size[2 * d + 1], worker_threads(p), plan, out, ds, &job->jm,
                           from + (to - from) * d / n, from + (to - from) * (d + 1) / n, err, err_len);
        ds->seconds_bake += now_seconds() - t0;
    }
    return st;
}

/* The closed-loop refinement's step (allocate.h texopt_reallocate_by_error), the best of
 * those measured on Fox, spot and Duck (BENCHMARKS.md@9f788a8 "Quality"): area steps of (e_t /
 * e_mean)^0.5 within [0.5, 2] per round, singular values up to twice input density. */
static const texopt_reallocate_options refinement_step = {0.5, 0.5, 2.0, 2.0, NULL};

/* Per domain, room for one target per triangle in out[d] (zeros: a kept domain has none). */
static texopt_status alloc_domain_targets(const texopt_job *job, texopt_triangle_target **out, char *err,
                                          size_t err_len)
{
    for (int d = 0; d < job->model->domain_count; d++) {
        size_t n = job->domains[d].mesh->triangle_count;
        if (!(out[d] = calloc(n ? n : 1, sizeof *out[d])))
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the refined targets");
    }
    return TEXOPT_OK;
}

/* Per domain, the targets the kept candidate was solved from: stage 1's or a signal
 * metric's as they are (uniform, cap 0), or stage 1's allocated (allocate.h) with the
 * candidate's cap at the cost it reached. */
static texopt_status kept_targets(const texopt_job *job, double cap, const texopt_domain_stats *ds,
                                  texopt_triangle_target **out, char *err, size_t err_len)
{
    texopt_status st = alloc_domain_targets(job, out, err, err_len);
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++) {
        const job_domain *jd = &job->domains[d];
        if (jd->kept)
            continue;
        double area = ds[d].relative_cost * (double)jd->input_coverage.covered_texels;
        texopt_allocate_options o = domain_allocation(jd, cap);
        if (cap > 0 && area > 0)
            st = texopt_allocate_targets(jd->mesh, jd->targets, area, &o, out[d], NULL, err, err_len);
        else
            memcpy(out[d], source_targets(job, jd), jd->mesh->triangle_count * sizeof *out[d]);
    }
    return st;
}

/* Moves each domain's targets towards the triangles the screen shows wrong, rescaled to the
 * texel area the kept layout reached (also for the uniform candidate, whose targets stage 2
 * then solves at their final size: rescaling them to their own total area instead measured
 * worse on Fox at c_r 0.7 and 1 and no better on spot). model_error is per model triangle
 * (evaluate.h), scratch has room for as many. */
static texopt_status reallocate_domains(const texopt_job *job, texopt_triangle_target *const *from,
                                        const double *model_error, const texopt_domain_stats *ds,
                                        const texopt_reallocate_options *step, double *scratch,
                                        texopt_triangle_target **targets, char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++) {
        const job_domain *jd = &job->domains[d];
        const texopt_mesh *mesh = jd->mesh;
        if (jd->kept || mesh->triangle_count == 0)
            continue;
        /* A metric candidate's targets keep their own total area: its layout was solved at
         * that size and scaled by the budget, as its method does, and solving them at the
         * budget's size instead gives another layout (CesiumMan at c_r 0.3: no round kept). */
        double area = job->source == SOURCE_STAGE1 ? ds[d].relative_cost * (double)jd->input_coverage.covered_texels
                                                   : texopt_targets_area(mesh, from[d], jd->paid);
        if (!(area > 0))
            continue;
        for (size_t t = 0; t < mesh->triangle_count; t++)
            scratch[t] = model_error[mesh->model_triangle[t]];
        texopt_reallocate_options o = *step;
        o.paid = jd->paid;
        st = texopt_reallocate_by_error(mesh, from[d], scratch, area, &o, targets[d], NULL, err, err_len);
    }
    return st;
}

/* Per domain, a copy of `from` (the next round's targets start as the kept ones: a domain
 * the reallocation skips keeps them). */
static texopt_status copy_targets(const texopt_job *job, texopt_triangle_target *const *from,
                                  texopt_triangle_target **out, char *err, size_t err_len)
{
    texopt_status st = alloc_domain_targets(job, out, err, err_len);
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++)
        memcpy(out[d], from[d], job->domains[d].mesh->triangle_count * sizeof *out[d]);
    return st;
}

static void free_targets(texopt_triangle_target **targets, int n)
{
    for (int d = 0; targets && d < n; d++)
        free(targets[d]);
    free(targets);
}

/* One round of the refinement: the layout of `targets` as a candidate, with its loss and
 * per-triangle errors on the refinement's cameras against the input's kept views, lit or of
 * base colour. */
static texopt_status refinement_trial(texopt_job *job, const texopt_params *p, texopt_triangle_target **targets,
                                      int lit, const texopt_evaluate_reference *views, candidate *trial,
                                      double *triangle_error, double from, double to, char *err, size_t err_len)
{
    job->refined = targets;
    texopt_status st = run_candidate(job, p, 0, lit ? BAKE_DRAFT_REST : BAKE_EVALUATED, trial, from,
                                     from + 0.8 * (to - from), err, err_len);
    job->refined = NULL;
    const job_output *shown = &trial->out;
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "evaluate", from + 0.8 * (to - from), to);
        st = evaluate_outputs_on(job->model, &shown, 1, p, CHOICE_CAMERAS, lit, views, triangle_error,
                                 &job->jm, &trial->ev, err, err_len);
    }
    return st;
}

/* Drafts the images a candidate left out (BAKE_DRAFT_REST) into its layouts, recording them
 * in its own statistics. */
static texopt_status draft_candidate_images(texopt_job *job, const texopt_params *p, candidate *c, double from,
                                            double to, char *err, size_t err_len)
{
    texopt_domain_stats *job_domains = job->stats.domains;
    job->stats.domains = c->domains;
    texopt_status st = bake_remaining_images(job, p, BAKE_DRAFT_REST, &c->out, from, to, err, err_len);
    job->stats.domains = job_domains;
    return st;
}

/* What one candidate's refinement did (refine_kept), for the statistics. */
typedef struct refinement_record {
    int rounds, kept, lit;
    double q_before, q_after, seconds;
} refinement_record;

/* The kept candidate's refinement in the statistics, with the seconds of every refinement the
 * budget ran. */
static void record_refinement(texopt_job_stats *js, const refinement_record *r, double seconds)
{
    js->refinement_rounds = r->rounds;
    js->refinement_kept = r->kept;
    js->refinement_lit = r->lit;
    js->q_refinement_before = r->q_before;
    js->q_refinement_after = r->q_after;
    js->seconds_refinement = seconds;
}

/* Closed-loop refinement of the kept perceptual candidate, the paper's principle (perceptual
 * loss on screen) applied to the whole mesh: render the layout against the input, take each
 * triangle's on-screen error (evaluate.h triangle_error_edges: value and gradient both wrong,
 * as GMSD sees an edge; base-colour q 0.85-0.96x that of the plain luma difference on seven
 * sample models and level on Duck, BENCHMARKS.md@9f788a8 "The refinement steered by edges"), move
 * texels from the triangles shown right to those shown wrong (reallocate_domains), solve, pack
 * and bake again, and keep the new layout when its q is lower; a round that is not lower is
 * retried from the best layout with half the step (gamma), as a backtracking line search.
 * Errors and q are measured on the choice's views (CHOICE_CAMERAS), not on those that define
 * the reported q: the layout is not tuned on the views it is graded on. With
 * p->refine_lit, and when the material has maps a light reads besides base colour, the screen
 * is lit (with the luma difference per triangle, the measure it was tuned with; evaluate.h
 * `lit`: every map under one light), else base colour's: on a glossy multi-map material what
 * the light shows of the normal and roughness maps is what a viewer sees, and base colour's
 * error alone moves texels away from it; it costs base colour's q and over twice the rounds'
 * time (BENCHMARKS.md@9f788a8 "Specular lit loss", "Cheaper lit refinement"), hence not the default.
 * Lit rounds read the input's views shaded once (texopt_evaluate_reference_create) and
 * draft the maps besides base colour and normal (BAKE_DRAFT_REST), the kept layout's too,
 * so that every layout is judged with the same bake; the saved layout's drafts are baked
 * again with the fit (bake_remaining_images).
 * The rounds tried and kept, the measure, the 12-view q before and after and their time go
 * to *rec (for the statistics' allocation_choice.refinement); kept->ev stays the choice's. */
static texopt_status refine_kept(texopt_job *job, const texopt_params *p, candidate *kept, double cap,
                                 double from, double to, refinement_record *rec, char *err, size_t err_len)
{
    int rounds = texopt_params_refinement_rounds(p), nd = job->model->domain_count;
    memset(rec, 0, sizeof *rec);
    if (rounds <= 0)
        return TEXOPT_OK;
    double t0 = now_seconds();
    size_t tc = job->model->triangle_count ? job->model->triangle_count : 1, nda = (size_t)(nd > 0 ? nd : 1);
    texopt_triangle_target **best = calloc(nda, sizeof *best), **next = calloc(nda, sizeof *next);
    double *error = malloc(tc * sizeof *error), *next_error = malloc(tc * sizeof *error);
    double *scratch = malloc(tc * sizeof *scratch);
    texopt_status st = best && next && error && next_error && scratch
                           ? kept_targets(job, cap, kept->domains, best, err, err_len)
                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the refinement");
    if (st == TEXOPT_OK)
        st = copy_targets(job, best, next, err, err_len);
    int lit = rec->lit = p->refine_lit && texopt_lit_has_maps(job->model);
    const job_output *shown = &kept->out;
    texopt_evaluation best_ev;
    double span = (to - from) / (rounds + 1);
    texopt_evaluate_reference *views = NULL;
    if (st == TEXOPT_OK && lit)
        st = draft_candidate_images(job, p, kept, from, from + 0.5 * span, err, err_len);
    if (st == TEXOPT_OK)
        job_stage(&job->jm, "evaluate", from + (lit ? 0.5 * span : 0), from + span);
    if (st == TEXOPT_OK && lit) {
        texopt_evaluate_options opt = evaluation_options(p, CHOICE_CAMERAS, lit, &job->jm);
        st = texopt_evaluate_reference_create(job->model, &opt, &views, err, err_len);
    }
    if (st == TEXOPT_OK) {
        st = evaluate_outputs_on(job->model, &shown, 1, p, CHOICE_CAMERAS, lit, views, error, &job->jm,
                                 &best_ev, err, err_len);
        rec->q_before = best_ev.q;
    }
    texopt_reallocate_options step = refinement_step;
    for (int r = 0; r < rounds && st == TEXOPT_OK; r++) {
        candidate trial = {0};
        st = reallocate_domains(job, best, error, kept->domains, &step, scratch, next, err, err_len);
        if (st == TEXOPT_OK)
            st = refinement_trial(job, p, next, lit, views, &trial, next_error, from + span * (r + 1),
                                  from + span * (r + 2), err, err_len);
        if (st == TEXOPT_OK && trial.ev.q < best_ev.q) {
            free_domain_stats(kept->domains, nd);
            job_output_destroy(&kept->out, job->model->image_count);
            *kept = trial;
            memset(&trial, 0, sizeof trial);
            best_ev = kept->ev;
            texopt_triangle_target **t = best;
            best = next;
            next = t;
            double *e = error;
            error = next_error;
            next_error = e;
            rec->kept++;
        } else
            step.gamma *= 0.5;
        free_domain_stats(trial.domains, nd);
        job_output_destroy(&trial.out, job->model->image_count);
        rec->rounds = r + 1;
    }
    if (st == TEXOPT_OK)
        rec->q_after = best_ev.q; /* the kept layout's; unchanged when no round was kept */
    rec->seconds = now_seconds() - t0;
    texopt_evaluate_reference_destroy(views);
    free_targets(best, nd);
    free_targets(next, nd);
    free(error);
    free(next_error);
    free(scratch);
    return st;
}

/* The perceptual candidates of run_best_budget: stage 1's targets allocated to the budget
 * (allocate.h) with singular values capped at input density, the same capped at 1.5x it,
 * and the targets as they are (cap 0), scaled uniformly by the budget. None wins everywhere
 * (BENCHMARKS.md@9f788a8 "Quality", "A candidate denser than the input"): the uniform one on spot,
 * the dense one on Duck at c_r 0.1, 0.2 and 1 and on WaterBottle at 1, giving the
 * triangles the first one capped more texels than the input has (tewari's targets put up
 * to 1.8x on Duck's pupils' edge); cap 2 measured no better. Then the signal metrics'
 * targets as they are, the layouts of methods tewari and ssp: at the smallest budgets stage
 * 1's targets, found at one loss threshold, spread too few texels where the loss is
 * (CesiumMan at c_r 0.1: q 0.053 for the best of them before the refinement, 0.034 for
 * tewari's; WaterBottle 0.019 against ssp's 0.0138; BENCHMARKS.md@9f788a8 "The signal metrics'
 * layouts as candidates"); refine_best decides between the best of each kind. */
enum { CANDIDATE_UNIFORM, CANDIDATE_ALLOCATED, CANDIDATE_DENSE, CANDIDATE_HESSIAN, CANDIDATE_STRETCH, CANDIDATES };
static const double candidate_cap[CANDIDATES] = {0.0, 1.0, 1.5, 0.0, 0.0};
static const target_source candidate_source[CANDIDATES] = {SOURCE_STAGE1, SOURCE_STAGE1, SOURCE_STAGE1,
                                                           SOURCE_HESSIAN, SOURCE_STRETCH};
static const char *const candidate_name[CANDIDATES] = {"uniform", "allocated", "allocated_dense", "hessian",
                                                       "signal_stretch"};

/* Whether the allocation capped any target of the candidate (else one with a higher cap
 * would be the same layout). */
static int allocation_capped(const candidate *c, int domain_count)
{
    for (int d = 0; d < domain_count; d++)
        if (c->domains[d].has_allocation && c->domains[d].allocation_capped_share > 0)
            return 1;
    return 0;
}

/* Whether the job makes candidate i (the dense one only when the cap at input density bound
 * a target of the allocated one, the metric ones when params.metric_candidates asks). */
static int candidate_wanted(const texopt_job *job, const candidate *cand, int i)
{
    if (i == CANDIDATE_DENSE)
        return allocation_capped(&cand[CANDIDATE_ALLOCATED], job->stats.domain_count);
    if (candidate_source[i] != SOURCE_STAGE1)
        return job->params.metric_candidates > 0;
    return 1;
}

/* Frees a candidate's layout, bakes and statistics. */
static void candidate_free(texopt_job *job, candidate *c)
{
    free_domain_stats(c->domains, job->stats.domain_count);
    c->domains = NULL;
    job_output_destroy(&c->out, job->model->image_count);
}

/* Makes the candidates of one budget in their order (the dense one only when the cap at
 * input density bound), evaluates them in one pass on the choice's views and returns in
 * best[0] the index of stage 1's with the smallest q and in best[1] the metric one's (-1 when
 * none was made), a tie keeping the earlier, simpler one; *made says which were made. */
static texopt_status run_candidates(texopt_job *job, const texopt_params *p, candidate *cand, int *made,
                                    double from, double to, double chosen, int best[2], char *err, size_t err_len)
{
    const job_output *outs[CANDIDATES];
    int n = 0;
    texopt_status st = TEXOPT_OK;
    for (int i = 0; i < CANDIDATES && st == TEXOPT_OK; i++) {
        if (!candidate_wanted(job, cand, i))
            continue;
        job->source = candidate_source[i];
        st = run_candidate(job, p, candidate_cap[i], BAKE_EVALUATED, &cand[i], from + (to - from) * i / CANDIDATES,
                           from + (to - from) * (i + 1) / CANDIDATES, err, err_len);
        job->source = SOURCE_STAGE1;
        made[i] = st == TEXOPT_OK;
        outs[n++] = &cand[i].out;
    }
    texopt_evaluation evs[CANDIDATES];
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "evaluate", to, chosen);
        st = evaluate_outputs_on(job->model, outs, n, p, CHOICE_CAMERAS, 0, NULL, NULL, &job->jm, evs, err, err_len);
    }
    best[0] = best[1] = -1;
    for (int i = 0, e = 0; i < CANDIDATES && st == TEXOPT_OK; i++) {
        if (!made[i])
            continue;
        cand[i].ev = evs[e++];
        int *b = &best[candidate_source[i] != SOURCE_STAGE1];
        if (*b < 0 || cand[i].ev.q < cand[*b].ev.q)
            *b = i;
    }
    return st;
}

/* The candidates' q, the choice and what it cost, in the statistics (the refinement's are
 * refine_kept's). */
static void record_choice(texopt_job_stats *js, const texopt_evaluation *evs, const int *made,
                          const double *seconds, int best)
{
    js->has_allocation_choice = 1;
    js->q_allocated = evs[CANDIDATE_ALLOCATED].q;
    js->q_uniform = evs[CANDIDATE_UNIFORM].q;
    js->allocation_dense_made = made[CANDIDATE_DENSE];
    js->q_allocated_dense = made[CANDIDATE_DENSE] ? evs[CANDIDATE_DENSE].q : 0;
    js->metric_candidates_made = made[CANDIDATE_HESSIAN] && made[CANDIDATE_STRETCH];
    js->q_hessian = made[CANDIDATE_HESSIAN] ? evs[CANDIDATE_HESSIAN].q : 0;
    js->q_signal_stretch = made[CANDIDATE_STRETCH] ? evs[CANDIDATE_STRETCH].q : 0;
    js->allocation_chosen = candidate_name[best];
    js->seconds_choice_evaluate = evs[best].seconds;
    js->seconds_other_candidate = 0;
    for (int i = 0; i < CANDIDATES; i++)
        if (made[i] && i != best)
            js->seconds_other_candidate += seconds[i];
}

/* Refines candidate i of cand (refine_kept, starting from its targets' source). A metric
 * candidate gets twice the rounds: it starts nearer an optimum of its own, where the first
 * rounds' steps overshoot and only the halved ones gain (CesiumMan at c_r 0.1: the fifth
 * round, BENCHMARKS.md@9f788a8 "The signal metrics' layouts as candidates"). */
static texopt_status refine_candidate(texopt_job *job, const texopt_params *p, candidate *cand, int i, double from,
                                      double to, refinement_record *rec, char *err, size_t err_len)
{
    texopt_params rounds = *p;
    if (candidate_source[i] != SOURCE_STAGE1 && p->refinements > 0)
        rounds.refinements = p->refinements * 2 > 20 ? 20 : p->refinements * 2;
    job->source = candidate_source[i];
    texopt_status st = refine_kept(job, &rounds, &cand[i], candidate_cap[i], from, to, rec, err, err_len);
    job->source = SOURCE_STAGE1;
    return st;
}

/* Refines stage 1's best candidate (best[0]) and, when a metric candidate (best[1]) had a
 * lower q, that one too, and returns the index of the one whose refined q (on the
 * refinement's cameras, the same for both) is lower, its refinement's statistics in
 * job->stats (seconds: both). The refinement gains most on stage 1's layouts (CesiumMan at
 * c_r 0.3: 0.0084 -> 0.0059, below tewari's 0.0079, on which no round is kept), so the choice
 * before it would lose them (BENCHMARKS.md@9f788a8 "The signal metrics' layouts as candidates"). */
static texopt_status refine_best(texopt_job *job, const texopt_params *p, candidate *cand, const int best[2],
                                 double from, double to, int *kept, char *err, size_t err_len)
{
    int challenge = best[1] >= 0 && cand[best[1]].ev.q < cand[best[0]].ev.q;
    refinement_record rec[2] = {{0}, {0}};
    texopt_status st = TEXOPT_OK;
    if (texopt_params_refinement_rounds(p) <= 0)
        *kept = challenge ? best[1] : best[0];
    else {
        double split = challenge ? 0.5 * (from + to) : to;
        st = refine_candidate(job, p, cand, best[0], from, split, &rec[0], err, err_len);
        if (st == TEXOPT_OK && challenge)
            st = refine_candidate(job, p, cand, best[1], split, to, &rec[1], err, err_len);
        *kept = st == TEXOPT_OK && challenge && rec[1].q_after < rec[0].q_after ? best[1] : best[0];
    }
    record_refinement(&job->stats, &rec[*kept == best[1]], rec[0].seconds + rec[1].seconds);
    return st;
}

/* Domain d's vertices in uvs back to the model's TEXCOORD_0 (as alloc_uvs copied them). */
static void restore_domain_uvs(const texopt_model *model, int d, float *uvs)
{
    const texopt_domain *dom = &model->domains[d];
    for (int i = 0; model->uvs && i < dom->primitive_count; i++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[i]];
        memcpy(uvs + 2 * prim->first_vertex, model->uvs + 2 * prim->first_vertex,
               2 * prim->vertex_count * sizeof *uvs);
    }
}

/* Into *resized: out with domain d's input layout in place of its new one, its images resized
 * by method "input" (Lanczos-3) to the sizes out's layout writes them at, the same file
 * texture pixels; the other domains' UVs copied and their images borrowed from out. The
 * resize's statistics in rs[d] (a copy of the job's). */
static texopt_status resized_input_layout(texopt_job *job, const texopt_params *p, const job_output *out, int d,
                                          double at, job_output *resized, texopt_domain_stats *rs, char *err,
                                          size_t err_len)
{
    const texopt_model *model = job->model;
    const texopt_domain *dom = &model->domains[d];
    texopt_status st = alloc_output(model, p->method, resized, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    memcpy(resized->uvs, out->uvs, 2 * model->vertex_count * sizeof *resized->uvs);
    restore_domain_uvs(model, d, resized->uvs);
    for (int i = 0; i < model->image_count; i++)
        resized->edit_images[i] = out->edit_images[i];
    for (int i = 0; i < dom->image_count; i++)
        resized->edit_images[dom->images[i]] = NULL;
    texopt_params same_pixels = *p;
    same_pixels.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    same_pixels.texture_width = rs[d].output_width;
    same_pixels.texture_height = rs[d].output_height;
    return run_input_method(model, job->domains[d].mesh, &same_pixels, resized, &rs[d], &job->jm, at, at, err,
                            err_len);
}

/* Puts domain d of *resized (resized_input_layout) and its statistics rs[d] in place of out's
 * new layout of it. */
static void keep_resized_input_layout(texopt_job *job, job_output *out, job_output *resized, int d,
                                      const texopt_domain_stats *rs)
{
    const texopt_domain *dom = &job->model->domains[d];
    for (int i = 0; i < dom->image_count; i++) {
        int im = dom->images[i];
        texopt_image_destroy(&out->images[im]);
        out->images[im] = resized->images[im];
        memset(&resized->images[im], 0, sizeof resized->images[im]);
        out->edit_images[im] = resized->edit_images[im] ? &out->images[im] : NULL;
        out->draft[im] = 0;
    }
    restore_domain_uvs(job->model, d, out->uvs);
    free(out->solved[d]);
    free(out->packed[d]);
    out->solved[d] = NULL;
    out->packed[d] = NULL;
    texopt_domain_stats *ds = &job->stats.domains[d];
    texopt_image_stats *images = ds->images;
    *ds = rs[d];
    ds->images = images;
    memcpy(ds->images, rs[d].images, (size_t)ds->image_count * sizeof *ds->images);
    ds->repacked = 0;
}

/* Never worse than a resize: each domain perceptual laid out anew is judged against its input
 * layout resized to the same file texture pixels (resized_input_layout), both on the choice's
 * views (CHOICE_CAMERAS), in every map that shows the domain and lit (map_check.h), and keeps
 * the resize unless its new layout is below it in one and above it in none (stats
 * resize_check: every map's q, the map that decided; input_layout_kept). A domain at its
 * input's pixels thus keeps its input (the identity resize, q 0). Every image is baked first,
 * as it will be saved. Domains are judged one after another, each beside the others' kept
 * layouts. params.resize_check -1 leaves the layouts as they are. */
static texopt_status keep_resize_if_better(texopt_job *job, const texopt_params *p, job_output *out, double at,
                                           char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    int n = job->model->domain_count;
    for (int d = 0; d < n; d++)
        job->stats.domains[d].has_resize_check = 0;
    if (p->resize_check > 0)
        st = bake_remaining_images(job, p, BAKE_ALL, out, at, at, err, err_len);
    for (int d = 0; d < n && st == TEXOPT_OK && p->resize_check > 0; d++) {
        if (!out->packed || !out->packed[d])
            continue;
        double t0 = now_seconds();
        job_output resized = {0};
        texopt_map_q q[2];
        texopt_domain_stats *rs = copy_domain_stats(&job->stats);
        st = rs ? resized_input_layout(job, p, out, d, at, &resized, rs, err, err_len)
                : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the resize's statistics");
        const job_output *shown[2] = {out, &resized};
        if (st == TEXOPT_OK) {
            job_stage(&job->jm, "evaluate", at, at);
            st = evaluate_maps_on(job->model, shown, 2, p, CHOICE_CAMERAS, d, &job->jm, q, err, err_len);
        }
        int by = TEXOPT_SLOT_BASE_COLOR, kept = st == TEXOPT_OK && !texopt_map_layout_wins(&q[0], &q[1], &by);
        if (kept)
            keep_resized_input_layout(job, out, &resized, d, rs);
        texopt_domain_stats *ds = &job->stats.domains[d];
        if (kept)
            snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                     "its new layout's %s q on the choice's views, %.6g, is not below the %.6g of its input layout "
                     "resized with Lanczos-3 to the same %dx%d texture; the input layout is kept, its images "
                     "resized", texopt_map_measure_name(by), q[0].q[by], q[1].q[by], ds->output_width,
                     ds->output_height);
        if (st == TEXOPT_OK) {
            ds->has_resize_check = 1;
            ds->resize_check_kept = kept;
            ds->resize_check_decided_by = by;
            ds->q_resize_check_layout = q[0].q[by];
            ds->q_resize_check_resize = q[1].q[by];
            ds->resize_check_maps_layout = q[0];
            ds->resize_check_maps_resize = q[1];
            ds->seconds_resize_check = now_seconds() - t0;
        }
        job_output_destroy(&resized, job->model->image_count);
        free_domain_stats(rs, n);
    }
    return st;
}

/* One budget into *out. For perceptual, the candidate layouts above are made, stage 1's best
 * and (when lower) the metric candidates' best are refined (refine_best), and the one with the
 * smaller q on the choice's views (CHOICE_CAMERAS) is kept (its reported q is measured
 * after, on other views), unless a resize of the input layout is not worse there
 * (keep_resize_if_better). The candidates bake only the images q looks at (base colour) and
 * are held until the choice, so the winner is not rebuilt; its other images are left to
 * bake_remaining_images (not
 * needed at all by the target_loss search's steps), and the per-triangle loss share is
 * measured on the winner only. */
static texopt_status run_best_budget(texopt_job *job, const texopt_params *p, int with_stats, job_output *out,
                                     double from, double to, char *err, size_t err_len)
{
    job->allocating = 0;
    if (p->method != TEXOPT_METHOD_PERCEPTUAL)
        return run_budget(job, p, with_stats, out, from, to, err, err_len);
    /* Progress: the candidates, their evaluation, then the refinement's rounds. */
    int refining = texopt_params_refinement_rounds(p) > 0;
    double made_by = from + (refining ? 0.6 : 0.8) * (to - from), chosen = refining ? from + 0.7 * (to - from) : to;
    candidate cand[CANDIDATES];
    memset(cand, 0, sizeof cand);
    int made[CANDIDATES] = {0}, best[2], kept_index = -1;
    double seconds[CANDIDATES] = {0}; /* each candidate's stage 2, packing and bake */
    texopt_evaluation evs[CANDIDATES]; /* before the refinement */
    texopt_status st = run_candidates(job, p, cand, made, from, made_by, chosen, best, err, err_len);
    if (st == TEXOPT_OK) {
        for (int i = 0; i < CANDIDATES; i++) {
            evs[i] = cand[i].ev;
            seconds[i] = made[i] ? candidate_seconds(&cand[i], job->stats.domain_count) : 0;
            if (i != best[0] && i != best[1])
                candidate_free(job, &cand[i]);
        }
        st = refine_best(job, p, cand, best, chosen, to, &kept_index, err, err_len);
    }
    if (st == TEXOPT_OK) {
        texopt_job_stats *js = &job->stats;
        record_choice(js, evs, made, seconds, kept_index);
        candidate *kept = &cand[kept_index];
        free_domain_stats(js->domains, js->domain_count);
        js->domains = kept->domains;
        kept->domains = NULL;
        *out = kept->out;
        memset(&kept->out, 0, sizeof kept->out);
        st = keep_resize_if_better(job, p, out, to, err, err_len);
        if (st == TEXOPT_OK && with_stats)
            st = measure_chosen_loss_share(job, out, err, err_len);
    }
    for (int i = 0; i < CANDIDATES; i++)
        candidate_free(job, &cand[i]);
    return st;
}

static void record_evaluation(texopt_job_stats *js, const texopt_evaluation *ev)
{
    js->has_evaluation = 1;
    js->q = ev->q;
    js->eval_resolution = ev->resolution;
    js->seconds_evaluate = ev->seconds;
}

/* job->signal_weights for the loaded model. */
static texopt_status weigh_signals(texopt_job *job, char *err, size_t err_len)
{
    const texopt_model *m = job->model;
    job->signal_weights = malloc((m->image_count ? (size_t)m->image_count : 1) * TEXOPT_LIT_WEIGHT_STRIDE *
                                 sizeof *job->signal_weights);
    if (!job->signal_weights)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %d images' signal weights", m->image_count);
    return texopt_lit_signal_weights(m, job->signal_weights, err, err_len);
}

/* A layout method with no domain to lay out has nothing to do: refused with the first
 * domain's reason rather than writing the input again. */
static texopt_status check_something_laid_out(const texopt_job *job, char *err, size_t err_len)
{
    int n = job->model->domain_count;
    for (int d = 0; d < n; d++)
        if (job->domains[d].kept != DOMAIN_KEPT_AS_IS)
            return TEXOPT_OK;
    return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "%sdomain 0: %s",
                       n > 1 ? "no domain can be laid out; " : "", job->stats.domains[0].input_layout_kept);
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
    job->weights = p->method == TEXOPT_METHOD_INPUT ? &input_weights : &perceptual_weights;
    job->budget_from = job->weights->load + job->weights->stage1;
    job_monitor_init(&job->jm, monitor);
    fill_job_params(&job->stats, p);
    job_stage(&job->jm, "load", 0, job->weights->load);
    double t0 = now_seconds();
    st = texopt_model_load(&job->model, input_path, NULL, err, err_len);
    job->stats.seconds_load = now_seconds() - t0;
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
    double total = st == TEXOPT_OK ? total_domain_weight(job->model, p->method) : 0;
    double at = job->weights->load;
    for (int d = 0; st == TEXOPT_OK && d < job->model->domain_count; d++) {
        double share = total > 0 ? job->weights->stage1 * domain_weight(job->model, d, p->method) / total : 0;
        st = check_cancel(&job->jm, err, err_len);
        if (st == TEXOPT_OK)
            st = prepare_domain(job, d, at, at + share, err, err_len);
        at += share;
    }
    if (st == TEXOPT_OK)
        st = check_something_laid_out(job, err, err_len);
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
static texopt_status budget_params(const texopt_job *job, const texopt_job_budget *b, texopt_params *p,
                                   char *err, size_t err_len)
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

/* The target_loss budget: the smallest relative cost whose q is at most the target
 * (compare.h's bisection on log c_r), each step only the budget's part of the job. The step
 * the search will answer with (cost_max's, then each that meets the target) is kept with
 * the statistics it recorded, so the chosen cost is not made a second time. */
typedef struct loss_search {
    texopt_job *job;
    texopt_params p;     /* relative-cost budget; relative_cost set per step */
    double from, to;     /* progress range of the search */
    int max_evaluations;
    int done;
    job_output kept;
    texopt_evaluation kept_ev;
    texopt_job_stats kept_stats; /* job->stats after the kept step, its domains copied */
    double kept_cost;            /* < 0: none yet */
} loss_search;

#define SEARCH_COST_MIN 0.01
#define SEARCH_COST_MAX 1.0
#define SEARCH_TOLERANCE 0.05
#define SEARCH_MAX_EVALUATIONS 12

/* Keeps a step's output (moved out of *out) and a copy of the statistics it recorded. */
static texopt_status keep_step(loss_search *s, job_output *out, const texopt_evaluation *ev, char *err,
                               size_t err_len)
{
    texopt_domain_stats *domains = copy_domain_stats(&s->job->stats);
    if (!domains)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the search's statistics");
    int images = s->job->model->image_count;
    job_output_destroy(&s->kept, images);
    free_domain_stats(s->kept_stats.domains, s->kept_stats.domain_count);
    s->kept = *out;
    memset(out, 0, sizeof *out);
    s->kept_ev = *ev;
    s->kept_stats = s->job->stats;
    s->kept_stats.domains = domains;
    s->kept_cost = s->p.relative_cost;
    return TEXOPT_OK;
}

static texopt_status search_step(void *user, double relative_cost, double *q, char *err, size_t err_len)
{
    loss_search *s = user;
    double step = (s->to - s->from) / s->max_evaluations;
    double from = s->from + step * s->done;
    s->p.relative_cost = relative_cost;
    job_output out = {0};
    texopt_evaluation ev;
    texopt_status st = run_best_budget(s->job, &s->p, 0, &out, from, from + 0.8 * step, err, err_len);
    if (st == TEXOPT_OK) {
        job_stage(&s->job->jm, "evaluate", from + 0.8 * step, from + step);
        st = evaluate_output(s->job->model, &out, &s->p, &s->job->jm, &ev, err, err_len);
    }
    if (st == TEXOPT_OK)
        *q = ev.q;
    if (st == TEXOPT_OK && (s->kept_cost < 0 || ev.q <= s->p.target_loss))
        st = keep_step(s, &out, &ev, err, err_len);
    job_output_destroy(&out, s->job->model->image_count);
    s->done++;
    return st;
}

/* Searches the cost and hands over the step it answers with: its output in *out, its q in
 * *ev, its statistics back in job->stats. */
static texopt_status search_target_loss(texopt_job *job, const texopt_params *p, double from, double to,
                                        texopt_params *chosen, job_output *out, texopt_evaluation *ev, char *err,
                                        size_t err_len)
{
    loss_search s = {.job = job, .p = *p, .from = from, .to = to, .max_evaluations = SEARCH_MAX_EVALUATIONS,
                     .kept_cost = -1};
    s.p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    texopt_target_search res;
    texopt_status st = texopt_search_target_loss(search_step, &s, p->target_loss, SEARCH_COST_MIN, SEARCH_COST_MAX,
                                                 SEARCH_TOLERANCE, SEARCH_MAX_EVALUATIONS, &res, err, err_len);
    if (st == TEXOPT_OK && s.kept_cost != res.relative_cost)
        st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "target search: answered c_r %g but kept the step at %g",
                         res.relative_cost, s.kept_cost);
    texopt_job_stats *js = &job->stats;
    if (st == TEXOPT_OK) {
        free_domain_stats(js->domains, js->domain_count);
        *js = s.kept_stats;
        *out = s.kept;
        *ev = s.kept_ev;
    } else {
        job_output_destroy(&s.kept, job->model->image_count);
        free_domain_stats(s.kept_stats.domains, s.kept_stats.domain_count);
    }
    if (st != TEXOPT_OK)
        return st;
    js->has_search = 1;
    js->target_loss = p->target_loss;
    js->target_reached = res.reached;
    js->search_evaluations = res.evaluations;
    js->search_cost_below = res.cost_below;
    js->search_q_below = res.q_below;
    js->relative_cost = res.relative_cost;
    *chosen = s.p;
    chosen->relative_cost = res.relative_cost;
    chosen->evaluate = 1; /* the result's q is part of the answer */
    return TEXOPT_OK;
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
    fill_job_params(js, &p);
    js->has_search = 0;
    js->has_evaluation = 0;
    const stage_weights *w = job->weights;
    /* The target_loss search measures every step's q within its own range. */
    double end = 1.0 - w->save, tail = p.evaluate && p.budget != TEXOPT_BUDGET_TARGET_LOSS ? EVALUATE_WEIGHT : 0;
    double from = job->budget_from;
    job_output out = {0};
    texopt_evaluation ev;
    int evaluated = 0;
    js->has_allocation_choice = 0;
    /* A perceptual job's kept candidate bakes its remaining images from here. */
    double baked = p.method == TEXOPT_METHOD_PERCEPTUAL ? from + 0.85 * (end - tail - from) : end - tail;
    if (p.budget == TEXOPT_BUDGET_TARGET_LOSS) {
        st = search_target_loss(job, &p, from, baked, &p, &out, &ev, err, err_len);
        evaluated = st == TEXOPT_OK; /* every step measured its q */
        if (st == TEXOPT_OK && stats_json)
            st = measure_chosen_loss_share(job, &out, err, err_len);
    } else {
        st = run_best_budget(job, &p, stats_json != NULL, &out, from, baked, err, err_len);
    }
    if (st == TEXOPT_OK)
        st = bake_remaining_images(job, &p, BAKE_ALL, &out, baked, end - tail, err, err_len);
    if (st == TEXOPT_OK)
        st = check_cancel(&job->jm, err, err_len);
    if (st == TEXOPT_OK && p.evaluate && !evaluated) {
        job_stage(&job->jm, "evaluate", end - tail, end);
        st = evaluate_output(job->model, &out, &p, &job->jm, &ev, err, err_len);
        evaluated = st == TEXOPT_OK;
    }
    if (st == TEXOPT_OK && p.evaluate)
        record_evaluation(js, &ev);
    const job_output *written = &out;
    js->has_q_maps = 0;
    if (st == TEXOPT_OK && p.evaluate && stats_json) {
        st = evaluate_maps_on(job->model, &written, 1, &p, TEXOPT_CAMERAS_DODECAHEDRON, -1, &job->jm, &js->q_maps,
                              err, err_len);
        js->has_q_maps = st == TEXOPT_OK;
    }
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "save", end, 1.0);
        double t0 = now_seconds();
        texopt_model_edit edit = {out.uvs, out.edit_images, p.lossless_textures};
        st = texopt_model_save_glb(job->model, &edit, output_glb, err, err_len);
        js->seconds_save = now_seconds() - t0;
    }
    if (st == TEXOPT_OK && stats_json) /* the costs reported are the written file's */
        st = texopt_file_cost_record(output_glb, js, err, err_len);
    js->seconds_total = now_seconds() - job->jm.start;
    if (st == TEXOPT_OK && stats_json)
        st = texopt_stats_write(js, stats_json, err, err_len);
    if (st == TEXOPT_OK)
        job_stage_done(&job->jm, "save");
    job_output_destroy(&out, job->model->image_count);
    return st;
}

texopt_status texopt_optimize_file(const char *input_path, const char *output_glb,
                                   const char *stats_json, const texopt_params *params,
                                   const texopt_monitor *monitor, char *err, size_t err_len)
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
