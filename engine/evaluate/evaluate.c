/* evaluate.c - whole-mesh loss q: 20 views (or 12), GMSD on covered luma, mean (Sun et al. 2022, 5.1).
 *
 * Each view is rasterised once from the reference geometry and shaded for the reference and
 * for every candidate (meshrender.h), so all images cover exactly the same pixels; the GMSD
 * mask is that coverage, and the reference side of GMSD is prepared once per view. Views are
 * independent and run on `threads` workers, each with its own raster, images and GMSD
 * workspace; results are written to per-view slots, so the sum is the same for any thread
 * count. The texture (base colour by default; texture_keys.h) changes which binding
 * meshrender shades and, for normal maps, turns the candidate's XY per triangle back to the
 * reference's tangent frame (evaluate.h); lit evaluation shades every map through
 * lit_shade.h with the same turns. Does not: render with OSMesa (see meshrender.c for why),
 * look at two textures at once. */
#include "evaluate.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "coverage.h"
#include "distortion.h"
#include "gltf_tangents.h"
#include "gmsd.h"
#include "lit_shade.h"
#include "mesh.h"
#include "parallel.h"
#include "sample.h"
#include "texel_map.h"
#include "texture_filter.h"

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Distortion of every domain, weighted by its counted triangles. */
static texopt_status domains_distortion(const texopt_model *model, double *out, char *err, size_t err_len)
{
    double sum = 0;
    size_t counted = 0;
    for (int d = 0; d < model->domain_count; d++) {
        texopt_mesh *mesh = NULL;
        texopt_status st = texopt_mesh_create(&mesh, model, d, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        texopt_distortion dist;
        st = texopt_distortion_measure(mesh, NULL, &dist, err, err_len);
        texopt_mesh_destroy(mesh);
        if (st == TEXOPT_E_INVALID_ARGUMENT)
            continue; /* a domain with nothing to measure adds nothing */
        if (st != TEXOPT_OK)
            return st;
        sum += dist.symmetric_dirichlet * (double)dist.counted;
        counted += dist.counted;
    }
    *out = counted ? sum / (double)counted : 0;
    return TEXOPT_OK;
}

int texopt_evaluate_texture_from_name(const char *name)
{
    static const struct {
        const char *name;
        texopt_slot slot;
    } short_names[] = {
        {"base", TEXOPT_SLOT_BASE_COLOR}, {"mr", TEXOPT_SLOT_METALLIC_ROUGHNESS}, {"ao", TEXOPT_SLOT_OCCLUSION}};
    for (size_t i = 0; name && i < sizeof short_names / sizeof short_names[0]; i++)
        if (!strcasecmp(name, short_names[i].name))
            return short_names[i].slot;
    return texopt_texture_key_from_name(name);
}

int texopt_evaluate_select_measure(texopt_evaluate_options *opt, const char *name)
{
    int lit = name && !strcasecmp(name, "lit");
    int texture = lit ? TEXOPT_SLOT_BASE_COLOR : texopt_evaluate_texture_from_name(name);
    if (texture < 0)
        return -1;
    opt->lit = lit;
    opt->texture = texture;
    return 0;
}

const char *texopt_evaluate_measure_name(const texopt_evaluate_options *opt)
{
    return opt->lit ? "lit" : texopt_texture_key_name(opt->texture);
}

texopt_status texopt_evaluate_check_texture(const texopt_model *reference, int texture, char *err, size_t err_len)
{
    if (texture < 0 || texture >= TEXOPT_TEXTURE_KEY_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unknown texture %d", texture);
    if (texture != TEXOPT_SLOT_BASE_COLOR && !texopt_meshrender_has_texture(reference, texture))
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "the reference has no %s texture (read through TEXCOORD_0) to evaluate",
                           texopt_texture_key_name(texture));
    return TEXOPT_OK;
}

texopt_status texopt_evaluate_check_lit(const texopt_model *reference, char *err, size_t err_len)
{
    if (!texopt_meshrender_has_texture(reference, TEXOPT_SLOT_BASE_COLOR) && !texopt_lit_has_maps(reference))
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "the reference has no baseColor, metallicRoughness, normal, occlusion or emissive "
                           "texture (read through TEXCOORD_0) to light");
    return TEXOPT_OK;
}

texopt_status texopt_evaluate_cost(const texopt_model *model, texopt_cost *out, char *err, size_t err_len)
{
    if (!model || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "missing model");
    texopt_cost c;
    memset(&c, 0, sizeof c);
    texopt_status st = texopt_coverage_model_texels(model, &c.covered_texels, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    for (int d = 0; d < model->domain_count; d++)
        c.frame_texels += (uint64_t)model->domains[d].width * (uint64_t)model->domains[d].height;
    for (int i = 0; i < model->image_count; i++) {
        int used = 0;
        for (int d = 0; d < model->domain_count && !used; d++)
            for (int k = 0; k < model->domains[d].image_count; k++)
                used |= model->domains[d].images[k] == i;
        if (used)
            c.texture_pixels += (uint64_t)model->images[i].width * (uint64_t)model->images[i].height;
    }
    c.packing_efficiency = c.frame_texels ? (double)c.covered_texels / (double)c.frame_texels : 0;
    st = domains_distortion(model, &c.symmetric_dirichlet, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    *out = c;
    return TEXOPT_OK;
}

texopt_status texopt_evaluate_default_resolution(const texopt_model *model, int *side, char *err, size_t err_len)
{
    uint64_t texels = 0;
    texopt_status st = texopt_coverage_model_texels(model, &texels, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double s = floor(1.25 * sqrt((double)texels) + 0.5);
    *side = (int)fmin(4096, fmax(64, s));
    return TEXOPT_OK;
}

typedef struct eval_job {
    const texopt_model *reference;
    const texopt_model *const *candidates;
    int candidate_count;
    const texopt_view *views;
    int view_count;
    int side;
    int threads;
    int texture;            /* texture_keys.h */
    texopt_lit_frames *lit; /* the reference's tangent frames when lit, NULL otherwise */
    atomic_int next_view;
    atomic_int failed;
    texopt_evaluation *out; /* per candidate */
    /* view_count x triangle_count, NULL when not asked: kept per view and added in view
     * order, so the errors do not depend on which thread drew which view */
    double *triangle_error_sum;
    size_t *triangle_error_count;
    int triangle_error_edges; /* texopt_evaluate_options' */
    texopt_status status;
    char err[256];
    pthread_mutex_t lock; /* guards status/err and the monitor callback */
    int views_done;
    const texopt_monitor *monitor;
    texopt_texture_filter **ref_filters;   /* per image; NULL: bilinear */
    texopt_texture_filter ***cand_filters; /* per candidate, per image; NULL: bilinear */
    double **cand_turns;                   /* per candidate: normal-map turns (meshrender.h), NULL: none */
    const float *cached_luma;              /* per view side x side: the reference's, read instead of shaded */
    float *stored_luma;                    /* per view side x side: where the reference's shading is kept */
} eval_job;

struct texopt_evaluate_reference {
    const texopt_model *model;
    texopt_evaluate_options opt; /* as shaded; triangle_error, reference_views and, once
                                    shaded, the caller's monitor cleared */
    int side, view_count;
    float *luma; /* view_count x side x side */
};

/* Mip pyramids of every image the evaluated texture's bindings use (every slot lighting reads
 * when lit), with their wrap modes. */
static texopt_status build_filters(const texopt_model *m, int texture, int lit, texopt_texture_filter ***out, char *err,
                                   size_t err_len)
{
    texopt_texture_filter **f = calloc(m->image_count > 0 ? (size_t)m->image_count : 1, sizeof *f);
    if (!f)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for texture filters");
    *out = f;
    for (int k = 0; k < TEXOPT_TEXTURE_KEY_COUNT; k++) {
        if (lit ? k >= TEXOPT_SLOT_COUNT : k != texture)
            continue;
        for (int p = 0; p < m->primitive_count; p++) {
            const texopt_texture_ref *r = texopt_meshrender_binding(m, p, k);
            if (!r || f[r->image])
                continue;
            texopt_status st =
                texopt_texture_filter_create(&f[r->image], &m->images[r->image], r->wrap_s, r->wrap_t, err, err_len);
            if (st != TEXOPT_OK)
                return st;
        }
    }
    return TEXOPT_OK;
}

static void destroy_filters(texopt_texture_filter **f, int count)
{
    if (!f)
        return;
    for (int i = 0; i < count; i++)
        texopt_texture_filter_destroy(f[i]);
    free(f);
}

static void job_fail(eval_job *job, texopt_status st, const char *msg)
{
    pthread_mutex_lock(&job->lock);
    if (job->status == TEXOPT_OK) {
        job->status = st;
        snprintf(job->err, sizeof job->err, "%s", msg);
    }
    pthread_mutex_unlock(&job->lock);
    atomic_store(&job->failed, 1);
}

/* Per worker: the screen-sized buffers of one view. */
typedef struct view_buffers {
    texopt_gmsd_workspace *ws;
    texopt_gmsd_reference *prepared;
    float *luma_ref, *luma_cand;
    float *scratch;    /* TEXOPT_LIT_SCRATCH_FLOATS per pixel when lit, NULL otherwise */
    float *similarity; /* per pixel, with triangle_error_edges; NULL otherwise */
    unsigned char *mask;
} view_buffers;

/* What one pixel adds to its triangle's error (texopt_evaluate_options.triangle_error_edges);
 * negative: nothing (the pixel is not counted). */
static double pixel_error(const view_buffers *b, const float *luma_ref, size_t i)
{
    double difference = fabs((double)luma_ref[i] - b->luma_cand[i]);
    if (!b->similarity)
        return difference;
    return b->similarity[i] < 0 ? -1.0 : sqrt(difference * (1.0 - b->similarity[i]));
}

/* Adds one candidate's per-pixel luma error of view v to the view's triangle sums. */
static void account_triangle_error(eval_job *job, int v, const texopt_raster *raster, const float *luma_ref,
                                   const view_buffers *b)
{
    size_t n = (size_t)job->side * (size_t)job->side, tc = job->reference->triangle_count;
    double *sum = job->triangle_error_sum + (size_t)v * tc;
    size_t *cnt = job->triangle_error_count + (size_t)v * tc;
    if (b->similarity)
        texopt_gmsd_similarity_map(b->ws, b->prepared, b->similarity);
    for (size_t i = 0; i < n; i++) {
        double e = raster->triangle[i] >= 0 ? pixel_error(b, luma_ref, i) : -1.0;
        if (e >= 0) {
            sum[raster->triangle[i]] += e;
            cnt[raster->triangle[i]]++;
        }
    }
}

/* One model's luma of a raster: the evaluated texture, or lit. */
static texopt_status shade_luma(const eval_job *job, const texopt_model *model, const texopt_raster *raster,
                                texopt_texture_filter *const *filters, const double *turn, view_buffers *b, float *luma,
                                char *msg, size_t msg_len)
{
    if (job->lit)
        return texopt_lit_shade(model, raster, job->lit, filters, turn, b->scratch, luma, msg, msg_len);
    return texopt_meshrender_shade_luma(model, raster, job->texture, filters, turn, luma, msg, msg_len);
}

/* Renders one view of the reference once (raster, shading or the kept shading, GMSD
 * reference side) and compares every candidate with it; returns a status with the message
 * in msg. */
static texopt_status evaluate_view(eval_job *job, int v, view_buffers *b, char *msg, size_t msg_len)
{
    texopt_raster raster;
    size_t n = (size_t)job->side * (size_t)job->side;
    const float *luma_ref = job->cached_luma ? job->cached_luma + (size_t)v * n : b->luma_ref;
    texopt_status st = texopt_meshrender_rasterize(job->reference, &job->views[v], job->side, &raster, msg, msg_len);
    if (st == TEXOPT_OK && !job->cached_luma)
        st = shade_luma(job, job->reference, &raster, job->ref_filters, NULL, b, b->luma_ref, msg, msg_len);
    if (st == TEXOPT_OK && job->stored_luma)
        memcpy(job->stored_luma + (size_t)v * n, luma_ref, n * sizeof *luma_ref);
    if (st == TEXOPT_OK) {
        for (size_t i = 0; i < n; i++)
            b->mask[i] = raster.triangle[i] >= 0;
        if (!texopt_gmsd_reference_set(b->prepared, luma_ref, b->mask, job->side, job->side))
            st = texopt_fail(msg, msg_len, TEXOPT_E_INVALID_ARGUMENT, "view %d: bad GMSD reference", v);
    }
    for (int c = 0; c < job->candidate_count && st == TEXOPT_OK; c++) {
        st = shade_luma(job, job->candidates[c], &raster, job->cand_filters ? job->cand_filters[c] : NULL,
                        job->cand_turns ? job->cand_turns[c] : NULL, b, b->luma_cand, msg, msg_len);
        if (st != TEXOPT_OK)
            break;
        double g = texopt_gmsd_against(b->ws, b->prepared, b->luma_cand);
        if (!isfinite(g))
            st = texopt_fail(msg, msg_len, TEXOPT_E_NUMERIC, "GMSD of view %d is not finite", v);
        job->out[c].view_gmsd[v] = g;
        job->out[c].view_pixels[v] = raster.covered;
        if (st == TEXOPT_OK && job->triangle_error_sum)
            account_triangle_error(job, v, &raster, luma_ref, b);
    }
    texopt_raster_destroy(&raster);
    return st;
}

static void report_view_done(eval_job *job)
{
    pthread_mutex_lock(&job->lock);
    job->views_done++;
    texopt_progress p = {.stage = "evaluate",
                         .stage_fraction = (double)job->views_done / job->view_count,
                         .fraction = -1,
                         .eta_seconds = -1};
    texopt_monitor_report(job->monitor, &p);
    pthread_mutex_unlock(&job->lock);
}

static void *eval_worker_run(void *arg)
{
    eval_job *job = arg;
    size_t n = (size_t)job->side * (size_t)job->side;
    view_buffers b;
    b.ws = texopt_gmsd_workspace_create(job->side, job->side);
    b.prepared = texopt_gmsd_reference_create(job->side, job->side);
    b.luma_ref = malloc(n * sizeof(float));
    b.luma_cand = malloc(n * sizeof(float));
    b.mask = malloc(n);
    b.scratch = job->lit ? malloc(TEXOPT_LIT_SCRATCH_FLOATS * n * sizeof(float)) : NULL;
    int edges = job->triangle_error_sum && job->triangle_error_edges;
    b.similarity = edges ? malloc(n * sizeof(float)) : NULL;
    if (!b.ws || !b.prepared || !b.luma_ref || !b.luma_cand || !b.mask || (job->lit && !b.scratch) ||
        (edges && !b.similarity)) {
        job_fail(job, TEXOPT_E_NOMEM, "no memory for the evaluation views");
    } else {
        char msg[256];
        for (;;) {
            if (atomic_load(&job->failed))
                break;
            if (texopt_monitor_canceled(job->monitor)) {
                job_fail(job, TEXOPT_E_CANCELED, "evaluation canceled");
                break;
            }
            int v = atomic_fetch_add(&job->next_view, 1);
            if (v >= job->view_count)
                break;
            msg[0] = 0;
            texopt_status st = evaluate_view(job, v, &b, msg, sizeof msg);
            if (st != TEXOPT_OK) {
                job_fail(job, st, msg);
                break;
            }
            report_view_done(job);
        }
    }
    texopt_gmsd_workspace_destroy(b.ws);
    texopt_gmsd_reference_destroy(b.prepared);
    free(b.luma_ref);
    free(b.luma_cand);
    free(b.mask);
    free(b.scratch);
    free(b.similarity);
    return NULL;
}

static void destroy_candidate_filters(texopt_texture_filter ***f, const texopt_model *const *candidates, int count)
{
    if (!f)
        return;
    for (int c = 0; c < count; c++)
        destroy_filters(f[c], candidates[c]->image_count);
    free(f);
}

/* The mip pyramids of every candidate and, unless its views are kept, of the reference
 * (mipmapped evaluation). */
static texopt_status build_all_filters(eval_job *job, int reference_too, char *err, size_t err_len)
{
    int lit = job->lit != NULL;
    texopt_status st =
        reference_too ? build_filters(job->reference, job->texture, lit, &job->ref_filters, err, err_len) : TEXOPT_OK;
    if (st == TEXOPT_OK) {
        job->cand_filters =
            calloc((size_t)(job->candidate_count > 0 ? job->candidate_count : 1), sizeof *job->cand_filters);
        if (!job->cand_filters)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for texture filters");
    }
    for (int c = 0; c < job->candidate_count && st == TEXOPT_OK; c++)
        st = build_filters(job->candidates[c], job->texture, lit, &job->cand_filters[c], err, err_len);
    return st;
}

/* Whether a renderer shades candidate primitive p with stored tangents. A candidate with no
 * file behind it (the pipeline's, in memory) is the reference seen through new UVs: it has
 * the reference's attributes. */
static int stores_tangents(const texopt_model *reference, const texopt_model *candidate, int p)
{
    return texopt_primitive_has_tangents(candidate->document ? candidate : reference, p);
}

/* The turn (cos, sin) that brings candidate triangle t's normal XY back to the reference's
 * tangent frame: the inverse of the rotation the re-bake gave it (texel_map.h), from the map
 * candidate texel -> reference texel of the two images; none (1, 0) when either side has no
 * normal map or the candidate's triangle is degenerate. */
static void triangle_turn(const texopt_model *reference, const texopt_model *candidate, size_t t,
                          const texopt_texture_ref *ref_map, const texopt_texture_ref *cand_map, double *turn)
{
    turn[0] = 1;
    turn[1] = 0;
    if (!ref_map || !cand_map)
        return;
    const texopt_image *ref_img = &reference->images[ref_map->image], *cand_img = &candidate->images[cand_map->image];
    double from[3][2], to[3][2], m[4];
    for (int k = 0; k < 3; k++) {
        uint32_t a = reference->triangles[3 * t + k], b = candidate->triangles[3 * t + k];
        from[k][0] = reference->uvs[2 * (size_t)a] * ref_img->width;
        from[k][1] = reference->uvs[2 * (size_t)a + 1] * ref_img->height;
        to[k][0] = candidate->uvs[2 * (size_t)b] * cand_img->width;
        to[k][1] = candidate->uvs[2 * (size_t)b + 1] * cand_img->height;
    }
    if (!texopt_texel_map((const double(*)[2])from, (const double(*)[2])to, m, NULL))
        return;
    double c, s;
    texopt_texel_map_rotation(m, &c, &s);
    turn[0] = c;
    turn[1] = -s;
}

/* The normal-map turns of one candidate (see evaluate.h): per triangle, none where the
 * candidate's primitive stores tangents (the re-bake did not turn those either). */
static texopt_status candidate_turns(const texopt_model *reference, const texopt_model *candidate, int normal_map,
                                     double **out, char *err, size_t err_len)
{
    size_t tc = reference->triangle_count;
    const texopt_texture_ref **ref_map = NULL, **cand_map = NULL;
    double *turn = malloc((tc ? tc : 1) * 2 * sizeof *turn);
    texopt_status st = turn ? texopt_meshrender_triangle_bindings(reference, normal_map, &ref_map, err, err_len)
                            : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the normal-map turns");
    if (st == TEXOPT_OK)
        st = texopt_meshrender_triangle_bindings(candidate, normal_map, &cand_map, err, err_len);
    for (int p = 0; p < candidate->primitive_count && st == TEXOPT_OK; p++) {
        const texopt_primitive *prim = &candidate->primitives[p];
        if (!stores_tangents(reference, candidate, p))
            continue;
        for (size_t t = prim->first_triangle; t < prim->first_triangle + prim->triangle_count && t < tc; t++)
            cand_map[t] = NULL;
    }
    for (size_t t = 0; t < tc && st == TEXOPT_OK; t++)
        triangle_turn(reference, candidate, t, ref_map[t], cand_map[t], turn + 2 * t);
    free(ref_map);
    free(cand_map);
    if (st != TEXOPT_OK) {
        free(turn);
        return st;
    }
    *out = turn;
    return TEXOPT_OK;
}

static texopt_status build_all_turns(eval_job *job, int normal_map, char *err, size_t err_len)
{
    job->cand_turns = calloc((size_t)(job->candidate_count > 0 ? job->candidate_count : 1), sizeof *job->cand_turns);
    if (!job->cand_turns)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the normal-map turns");
    texopt_status st = TEXOPT_OK;
    for (int c = 0; c < job->candidate_count && st == TEXOPT_OK; c++)
        st = candidate_turns(job->reference, job->candidates[c], normal_map, &job->cand_turns[c], err, err_len);
    return st;
}

static void destroy_turns(double **turns, int count)
{
    for (int c = 0; turns && c < count; c++)
        free(turns[c]);
    free(turns);
}

/* Checks the candidates against the reference; the views and screen side to use. */
static texopt_status prepare_views(const texopt_model *reference, const texopt_model *const *candidates, int count,
                                   const texopt_evaluate_options *opt, texopt_view *views, int *view_count, int *side,
                                   char *err, size_t err_len)
{
    if (opt->resolution < 0 || opt->resolution > 16384 || (opt->resolution > 0 && opt->resolution < 8))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "resolution %d is outside [8, 16384]",
                           opt->resolution);
    texopt_status st = opt->lit ? texopt_evaluate_check_lit(reference, err, err_len)
                                : texopt_evaluate_check_texture(reference, opt->texture, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    if (opt->triangle_error && count != 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "per-triangle errors are measured for one candidate at a time");
    for (int c = 0; c < count; c++) {
        if (!candidates[c])
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "candidate %d is missing", c);
        texopt_status st = texopt_meshrender_same_geometry(reference, candidates[c], err, err_len);
        if (st != TEXOPT_OK)
            return st;
        if (!reference->uvs || !candidates[c]->uvs)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "both models need TEXCOORD_0");
    }
    st = texopt_meshrender_camera_set(reference, opt->cameras, views, view_count, err, err_len);
    *side = opt->resolution;
    if (st == TEXOPT_OK && *side == 0)
        st = texopt_evaluate_default_resolution(reference, side, err, err_len);
    return st;
}

/* Mean over the views of each candidate's GMSD, into out[c]. */
static void finish_results(const eval_job *job, double t0, texopt_evaluation *out)
{
    double seconds = now_seconds() - t0;
    for (int c = 0; c < job->candidate_count; c++) {
        double sum = 0;
        for (int v = 0; v < job->view_count; v++)
            sum += job->out[c].view_gmsd[v];
        job->out[c].q = sum / job->view_count;
        job->out[c].view_count = job->view_count;
        job->out[c].resolution = job->side;
        job->out[c].seconds = seconds;
        out[c] = job->out[c];
    }
}

static void sum_triangle_errors(const eval_job *job, double *triangle_error)
{
    size_t tc = job->reference->triangle_count;
    for (size_t t = 0; t < tc; t++) {
        double s = 0;
        size_t c = 0;
        for (int v = 0; v < job->view_count; v++) {
            s += job->triangle_error_sum[(size_t)v * tc + t];
            c += job->triangle_error_count[(size_t)v * tc + t];
        }
        triangle_error[t] = c ? s / (double)c : 0.0;
    }
}

/* Whether kept views were shaded as opt asks, of this reference at this side. */
static int same_reference_views(const texopt_evaluate_reference *kept, const texopt_model *reference,
                                const texopt_evaluate_options *opt, int side, int view_count)
{
    const texopt_evaluate_options *o = &kept->opt;
    return kept->model == reference && kept->side == side && kept->view_count == view_count &&
           o->cameras == opt->cameras && !o->mipmapped == !opt->mipmapped && !o->lit == !opt->lit &&
           (opt->lit || o->texture == opt->texture);
}

/* The evaluation of candidates against the reference (none when only its views are kept
 * into `store`, which then receives view_count x side x side floats), into out. */
static texopt_status run_evaluation(const texopt_model *reference, const texopt_model *const *candidates,
                                    int candidate_count, const texopt_evaluate_options *opt,
                                    texopt_evaluate_reference *store, texopt_evaluation *out, char *err, size_t err_len)
{
    double t0 = now_seconds();
    texopt_view views[TEXOPT_VIEW_COUNT];
    int side = 0, view_count = 0;
    texopt_status st =
        prepare_views(reference, candidates, candidate_count, opt, views, &view_count, &side, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const texopt_evaluate_reference *kept = opt->reference_views;
    if (kept && !same_reference_views(kept, reference, opt, side, view_count))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "the kept reference views were shaded for another reference, screen or measure");
    if (store) {
        size_t n = (size_t)side * (size_t)side * (size_t)view_count;
        store->luma = n <= SIZE_MAX / sizeof *store->luma ? malloc(n * sizeof *store->luma) : NULL;
        if (!store->luma)
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to keep %d views of %d x %d pixels", view_count,
                               side, side);
        store->side = side;
        store->view_count = view_count;
    }
    eval_job job;
    memset(&job, 0, sizeof job);
    job.reference = reference;
    job.candidates = candidates;
    job.candidate_count = candidate_count;
    job.views = views;
    job.view_count = view_count;
    job.side = side;
    job.texture = opt->texture;
    job.triangle_error_edges = opt->triangle_error_edges;
    job.threads = opt->threads <= 0 ? 1 : (opt->threads > view_count ? view_count : opt->threads);
    job.monitor = opt->monitor;
    job.cached_luma = kept ? kept->luma : NULL;
    job.stored_luma = store ? store->luma : NULL;
    job.out = calloc((size_t)(candidate_count > 0 ? candidate_count : 1), sizeof *job.out);
    atomic_init(&job.next_view, 0);
    atomic_init(&job.failed, 0);
    pthread_mutex_init(&job.lock, NULL);
    if (!job.out)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the evaluations");
    if (st == TEXOPT_OK && opt->lit)
        st = texopt_lit_frames_create(reference, &job.lit, err, err_len);
    if (st == TEXOPT_OK && opt->mipmapped)
        st = build_all_filters(&job, !kept, err, err_len);
    if (st == TEXOPT_OK && (opt->lit || texopt_texture_key_kind(opt->texture) == TEXOPT_TEXTURE_NORMAL))
        st = build_all_turns(&job, opt->lit ? TEXOPT_SLOT_NORMAL : opt->texture, err, err_len);
    size_t tc = reference->triangle_count;
    if (st == TEXOPT_OK && opt->triangle_error) {
        job.triangle_error_sum = calloc((size_t)view_count * tc, sizeof(double));
        job.triangle_error_count = calloc((size_t)view_count * tc, sizeof(size_t));
        if (!job.triangle_error_sum || !job.triangle_error_count)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for per-triangle errors");
    }
    if (st == TEXOPT_OK) {
        texopt_parallel_run(eval_worker_run, &job, 0, job.threads);
        st = job.status;
        if (st != TEXOPT_OK)
            texopt_fail(err, err_len, st, "%s", job.err);
    }
    if (st == TEXOPT_OK && opt->triangle_error)
        sum_triangle_errors(&job, opt->triangle_error);
    if (st == TEXOPT_OK)
        finish_results(&job, t0, out);
    free(job.triangle_error_sum);
    free(job.triangle_error_count);
    destroy_filters(job.ref_filters, reference->image_count);
    destroy_candidate_filters(job.cand_filters, candidates, candidate_count);
    destroy_turns(job.cand_turns, candidate_count);
    texopt_lit_frames_destroy(job.lit);
    free(job.out);
    pthread_mutex_destroy(&job.lock);
    return st;
}

texopt_status texopt_evaluate_many(const texopt_model *reference, const texopt_model *const *candidates,
                                   int candidate_count, const texopt_evaluate_options *opt, texopt_evaluation *out,
                                   char *err, size_t err_len)
{
    texopt_evaluate_options defaults = {0};
    if (!opt)
        opt = &defaults;
    if (!reference || !candidates || candidate_count < 1 || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "missing model or output");
    return run_evaluation(reference, candidates, candidate_count, opt, NULL, out, err, err_len);
}

texopt_status texopt_evaluate_reference_create(const texopt_model *reference, const texopt_evaluate_options *opt,
                                               texopt_evaluate_reference **out, char *err, size_t err_len)
{
    if (!reference || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "missing model or output");
    *out = NULL;
    texopt_evaluate_reference *views = calloc(1, sizeof *views);
    if (!views)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the reference views");
    views->model = reference;
    if (opt)
        views->opt = *opt;
    views->opt.triangle_error = NULL;
    views->opt.reference_views = NULL;
    texopt_status st = run_evaluation(reference, NULL, 0, &views->opt, views, NULL, err, err_len);
    if (st != TEXOPT_OK) {
        texopt_evaluate_reference_destroy(views);
        return st;
    }
    views->opt.monitor = NULL; /* the views outlive the call it reported to */
    *out = views;
    return TEXOPT_OK;
}

void texopt_evaluate_reference_destroy(texopt_evaluate_reference *views)
{
    if (!views)
        return;
    free(views->luma);
    free(views);
}

/* The lit luma of one view as a grey RGB image into out (side x side x 3). */
static texopt_status render_lit(const texopt_model *reference, const texopt_model *model, const texopt_raster *raster,
                                const double *turn, texopt_image *out, char *err, size_t err_len)
{
    size_t n = (size_t)raster->side * (size_t)raster->side;
    float *luma = malloc(n * sizeof *luma), *scratch = malloc(n * TEXOPT_LIT_SCRATCH_FLOATS * sizeof *scratch);
    texopt_lit_frames *frames = NULL;
    texopt_status st = luma && scratch ? texopt_lit_frames_create(reference, &frames, err, err_len)
                                       : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a lit render");
    if (st == TEXOPT_OK)
        st = texopt_lit_shade(model, raster, frames, NULL, turn, scratch, luma, err, err_len);
    for (size_t i = 0; st == TEXOPT_OK && i < n; i++)
        out->pixels[3 * i] = out->pixels[3 * i + 1] = out->pixels[3 * i + 2] = luma[i];
    texopt_lit_frames_destroy(frames);
    free(luma);
    free(scratch);
    return st;
}

texopt_status texopt_evaluate_render(const texopt_model *reference, const texopt_model *model,
                                     const texopt_evaluate_options *opt, const texopt_raster *raster, texopt_image *out,
                                     char *err, size_t err_len)
{
    if (!reference || !model || !opt || !raster || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "render: missing model, options or raster");
    memset(out, 0, sizeof *out);
    int normal = opt->lit ? TEXOPT_SLOT_NORMAL : opt->texture;
    double *turn = NULL;
    texopt_status st = texopt_meshrender_same_geometry(reference, model, err, err_len);
    if (st == TEXOPT_OK && !reference->uvs)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "render: the reference has no TEXCOORD_0");
    if (st == TEXOPT_OK && model != reference && texopt_texture_key_kind(normal) == TEXOPT_TEXTURE_NORMAL)
        st = candidate_turns(reference, model, normal, &turn, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_image_create(out, raster->side, raster->side, 3, err, err_len);
    if (st == TEXOPT_OK)
        st = opt->lit ? render_lit(reference, model, raster, turn, out, err, err_len)
                      : texopt_meshrender_shade_rgb(model, raster, opt->texture, NULL, turn, out->pixels, err, err_len);
    if (st != TEXOPT_OK)
        texopt_image_destroy(out);
    free(turn);
    return st;
}

texopt_status texopt_evaluate(const texopt_model *reference, const texopt_model *candidate,
                              const texopt_evaluate_options *opt, texopt_evaluation *out, char *err, size_t err_len)
{
    if (!candidate)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "missing model or output");
    return texopt_evaluate_many(reference, &candidate, 1, opt, out, err, err_len);
}
