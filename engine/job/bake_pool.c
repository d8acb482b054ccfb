/* bake_pool.c - the re-bake of a run's domains into their packed layouts (bake_pool.h). */
#include "bake_pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>

#include "gltf_tangents.h"
#include "parallel.h"
#include "rebake.h"

#define MAX_BAKE_WORKERS 8 /* images of one domain baked at once, at most */

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

/* Whether the plan bakes image im (one not baked yet). */
static int plan_bakes(const texopt_model *model, bake_plan plan, const job_output *out, int im)
{
    return !out->edit_images[im] && (plan == BAKE_ALL || image_is_evaluated(model, im));
}

/* One domain's bake: what every image of it is baked with. */
typedef struct domain_bake {
    const texopt_model *model;
    const texopt_domain *dom;
    const texopt_rebake_layout *layout;
    job_output *out;
    texopt_domain_stats *ds;
} domain_bake;

/* Bakes image i of the domain (its output size already in the statistics) into out, with the
 * fit (job_state.h bake_plan says why there are no drafts). */
static texopt_status bake_image(const domain_bake *b, int i, const texopt_monitor *monitor, char *err, size_t err_len)
{
    const texopt_model *model = b->model;
    job_output *out = b->out;
    int im = b->dom->images[i];
    const texopt_image *src = &model->images[im];
    texopt_image_stats *is = &b->ds->images[i];
    texopt_wrap ws, wt;
    image_wrap(model, im, &ws, &wt);
    out->edit_images[im] = NULL;
    texopt_image_destroy(&out->images[im]);
    texopt_status st =
        texopt_image_create(&out->images[im], is->output_width, is->output_height, src->channels, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_rebake_image_fit(src, ws, wt, normal_map_needs_rotation(model, b->dom, im), b->layout,
                                     TEXOPT_REBAKE_FIT_DEFAULT, &out->images[im], NULL, monitor, err, err_len);
    if (st == TEXOPT_OK) {
        out->edit_images[im] = &out->images[im];
        is->rewritten = 1;
    }
    return st;
}

/* Several images of a domain baked at once, one thread each: a bake scales about 1.5x on
 * two threads (BENCHMARKS.md@9f788a8 "End to end"), whole images side by side nearly 2x, and the
 * re-bake's result does not depend on its thread count. Progress per finished image. */
typedef struct bake_pool {
    domain_bake bake; /* layout threads = 1 */
    const int *todo;  /* image indices within the domain */
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
        texopt_status st = bake_image(&bp->bake, bp->todo[k], &bp->cancel_only, err, sizeof err);
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

/* The input and output UVs of a domain's bake: per input vertex, or per triangle corner when
 * the layout is on new charts (`charts`, whose vertices are not the input's; the triangles
 * are the same, so each corner reads the input texture through its input UV). */
typedef struct bake_layouts {
    uint32_t *corners; /* per corner its index, when per corner; else NULL */
    const uint32_t *triangles;
    double *uv_in, *uv_out;
} bake_layouts;

static void bake_layouts_free(bake_layouts *bl)
{
    free(bl->corners);
    free(bl->uv_in);
    free(bl->uv_out);
}

static int bake_layouts_make(bake_layouts *bl, const texopt_mesh *mesh, const texopt_mesh *charts, const double *packed,
                             int width, int height)
{
    size_t n = charts ? 3 * mesh->triangle_count : mesh->vertex_count;
    bl->corners = charts ? malloc((n ? n : 1) * sizeof *bl->corners) : NULL;
    bl->uv_in = malloc(2 * (n ? n : 1) * sizeof *bl->uv_in);
    bl->uv_out = malloc(2 * (n ? n : 1) * sizeof *bl->uv_out);
    if (!bl->uv_in || !bl->uv_out || (charts && !bl->corners)) {
        bake_layouts_free(bl);
        return -1;
    }
    bl->triangles = charts ? bl->corners : mesh->triangle;
    for (size_t i = 0; i < n; i++) {
        size_t in = charts ? mesh->triangle[i] : i, out = charts ? charts->triangle[i] : i;
        if (charts)
            bl->corners[i] = (uint32_t)i;
        bl->uv_in[2 * i] = mesh->texel[2 * in] / mesh->width;
        bl->uv_in[2 * i + 1] = mesh->texel[2 * in + 1] / mesh->height;
        bl->uv_out[2 * i] = packed[2 * out] / width;
        bl->uv_out[2 * i + 1] = packed[2 * out + 1] / height;
    }
    return 0;
}

texopt_status job_rebake_domain(texopt_job *job, const layout_run *run, int d, const texopt_mesh *charts,
                                const double *packed, const int size[2], double from, double to, char *err,
                                size_t err_len)
{
    const texopt_model *model = job->model;
    const texopt_mesh *mesh = job->domains[d].mesh;
    texopt_domain_stats *ds = &run->domains[d];
    job_monitor *jm = &job->jm;
    int width = size[0], height = size[1], threads = job_worker_threads(run->p);
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
        job_image_output_size(src, dom, width, height, &is->output_width, &is->output_height);
        if (plan_bakes(model, run->plan, run->out, im))
            todo[count++] = i;
    }
    bake_layouts bl;
    if (bake_layouts_make(&bl, mesh, charts, packed, width, height) != 0) {
        free(todo);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the bake layouts");
    }
    texopt_rebake_layout layout = {mesh->triangle_count, bl.triangles, bl.uv_in, bl.uv_out, threads};
    domain_bake bake = {model, dom, &layout, run->out, ds};
    texopt_status st = TEXOPT_OK;
    int workers = threads < count ? threads : count;
    if (workers > MAX_BAKE_WORKERS)
        workers = MAX_BAKE_WORKERS;
    if (workers >= 2) {
        layout.threads = 1;
        bake_pool bp = {.bake = bake,
                        .todo = todo,
                        .count = count,
                        .cancel_only = {NULL, NULL, jm->inner.cancel},
                        .jm = jm,
                        .from = from,
                        .to = to};
        job_stage(jm, "bake", from, to);
        st = bake_images_side_by_side(&bp, workers, err, err_len);
    }
    for (int k = 0; workers < 2 && k < count && st == TEXOPT_OK; k++) {
        job_stage(jm, "bake", from + (to - from) * k / count, from + (to - from) * (k + 1) / count);
        st = bake_image(&bake, todo[k], &jm->inner, err, err_len);
    }
    free(todo);
    bake_layouts_free(&bl);
    return st;
}

texopt_status job_bake_remaining_images(texopt_job *job, const layout_run *run, double from, double to, char *err,
                                        size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    const job_output *out = run->out;
    int n = job->model->domain_count;
    for (int d = 0; d < n && st == TEXOPT_OK; d++) {
        if (!out->packed || !out->packed[d])
            continue;
        texopt_domain_stats *ds = &run->domains[d];
        double t0 = job_now_seconds();
        const texopt_mesh *charts = out->cut && out->cut[d] ? out->cut[d] : job->domains[d].layout;
        st = job_rebake_domain(job, run, d, charts, out->packed[d], &out->packed_size[2 * d],
                               from + (to - from) * d / n, from + (to - from) * (d + 1) / n, err, err_len);
        ds->seconds_bake += job_now_seconds() - t0;
    }
    return st;
}
