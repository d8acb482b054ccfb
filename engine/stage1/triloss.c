/* triloss.c - perceptual loss of one candidate Jacobian on one triangle's one-ring
 * (Sun et al. 2022, section 4.1.1; GMSD of Xue et al. 2013), on the render-once buffer.
 *
 * Not here: choosing candidates (triopt.c), rasterising (uvraster.c), the bake solver
 * (window_bake.c) and GMSD itself (gmsd.c). */
#include "triloss.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gmsd.h"
#include "lit_weight.h"
#include "sample.h"
#include "window_bake.h"

#define TRILOSS_RIDGE 1e-6
/* Close-ups (triloss.h) are taken where the one-ring's window shows the triangle at more than
 * this many times the raster's zoom limit; the candidate windows are ranked by E under the
 * probe J = CLOSE_UP_PROBE I, at most CLOSE_UP_CANDIDATES of them per triangle. */
#define CLOSE_UP_FROM 1.5
#define CLOSE_UP_PROBE 0.25
#define CLOSE_UP_CANDIDATES 64
/* Signals of one texture size share one bake: one factorisation of A^T A + ridge I. */
#define TRILOSS_BATCH_MAX TEXOPT_BAKE_MAX_CHANNELS

typedef struct loss_signal {
    int image;    /* model image index */
    int channel;  /* -1: luma, else the channel compared */
    float weight; /* the signal's scale (texopt_triloss_weigh_signals), 1 unless weighed */
} loss_signal;

/* Signals of textures of one size, baked together. */
typedef struct loss_batch {
    int first_signal, signal_count;
    int active_count; /* of the prepared triangle: signals that need their own bake */
    int lead;         /* the active signal with the largest E at the last full evaluation */
    int tex_w, tex_h; /* the texture grid */
    double sx, sy;    /* domain texel frame -> this texture's texels */
} loss_batch;

struct texopt_triloss {
    const texopt_model *model;
    const texopt_mesh *mesh;
    int size;
    texopt_wrap wrap_s, wrap_t;
    texopt_uvraster *raster;
    int signal_count;
    loss_signal *signals;
    int batch_count;
    loss_batch *batches;

    /* the prepared triangle */
    size_t n;                         /* covered pixels */
    int32_t *pixel;                   /* per covered pixel: its index in the viewport */
    double *phat;                     /* 2 per covered pixel, domain texels */
    double centroid[2];               /* pivot of J: the texel centre nearest the triangle's centroid */
    double radius;                    /* max |p_hat - c| over covered pixels (infinity norm) */
    float *reference;                 /* per batch: n x active_count values, at n * first_signal */
    int *active;                      /* per batch: its active signals' indices, at first_signal */
    unsigned char *deciding;          /* per signal: it gave E in an evaluation since the prepare */
    float *ref_img;                   /* per signal: size x size image, 0 where uncovered */
    unsigned char *mask;              /* size x size */
    texopt_gmsd_reference **gmsd_ref; /* per signal: its GMSD side prepared once */

    /* per-candidate scratch */
    float *split; /* n x (TRILOSS_BATCH_MAX - 1): references of the signals after the lead */
    double *pos;
    float *recon;
    float *dist_img;
    texopt_bake_workspace *bake;
    texopt_gmsd_workspace *gmsd;

    /* close-up evaluators of the same mesh (none in a close-up itself) and how many hold a
     * window of the prepared triangle */
    struct texopt_triloss *close_up[TEXOPT_TRILOSS_CLOSE_UPS];
    int close_up_count;
};

void texopt_jacobian_from_params(double alpha, double lambda1, double lambda2, double beta, double jacobian[4])
{
    double ca = cos(alpha), sa = sin(alpha), cb = cos(beta), sb = sin(beta);
    /* S = V diag(l1, l2) V^T is symmetric. */
    double s00 = lambda1 * cb * cb + lambda2 * sb * sb;
    double s11 = lambda1 * sb * sb + lambda2 * cb * cb;
    double s01 = (lambda1 - lambda2) * cb * sb;
    jacobian[0] = ca * s00 - sa * s01;
    jacobian[1] = ca * s01 - sa * s11;
    jacobian[2] = sa * s00 + ca * s01;
    jacobian[3] = sa * s01 + ca * s11;
}

/* What stage 1 compares of one image: the luma of what its colour bindings read, or the
 * channels its other bindings read one by one (TEXOPT_CHANNEL_*; a shown alpha among them).
 * The primitives' variant materials (KHR_materials_variants) count as theirs: the layout
 * serves every material the surface may be drawn with. */
typedef struct image_use {
    int luma;
    unsigned channels;
} image_use;

static void add_material_use(const texopt_model *model, int m, int image, image_use *use)
{
    if (m < 0 || m >= model->material_count)
        return;
    const texopt_material *mat = &model->materials[m];
    for (int b = 0; b < texopt_material_binding_count(mat); b++) {
        const texopt_texture_ref *ref = texopt_material_binding(mat, b);
        /* A binding through another UV set reads the image along a layout this one leaves. */
        if (ref->image != image || ref->texcoord != 0)
            continue;
        unsigned channels = texopt_material_binding_channels(mat, b);
        if (texopt_material_binding_kind(mat, b) == TEXOPT_TEXTURE_COLOR) {
            use->luma |= (channels & TEXOPT_CHANNELS_RGB) != 0;
            use->channels |= channels & TEXOPT_CHANNEL_A;
        } else {
            use->channels |= channels;
        }
    }
}

static image_use image_use_in_domain(const texopt_model *model, const texopt_domain *dom, int image)
{
    image_use use = {0, 0};
    for (int p = 0; p < dom->primitive_count; p++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[p]];
        for (int i = 0; i <= prim->variant_count; i++)
            add_material_use(model, texopt_primitive_material(model, prim, i), image, &use);
    }
    return use;
}

/* The signals of one image, into channels (-1: luma, else the image channel compared); returns
 * how many (at most 5). Per channel when a data binding reads R, G or B, and then all three if
 * a colour binding reads the image too (luma adds nothing they do not show). None when the
 * file lacks every channel its bindings read (specular strength in a file without alpha reads
 * 1 everywhere), unless `fallback`: then its R, G and B, as for a data map of unknown meaning,
 * so that a domain always has a signal (a fallback domain has no other signal to keep). */
static int image_signal_channels(const texopt_image *img, image_use use, int fallback, int channels[5])
{
    int n = 0;
    unsigned taken = 0;
    if (fallback)
        use = (image_use){0, TEXOPT_CHANNELS_RGB};
    if (use.luma && (use.channels & TEXOPT_CHANNELS_RGB))
        use.channels |= TEXOPT_CHANNELS_RGB;
    else if (use.luma)
        channels[n++] = -1;
    for (int c = 0; c < 4; c++) {
        int ic = (use.channels >> c) & 1u ? texopt_image_channel_of(img->channels, c) : -1;
        if (ic >= 0 && !((taken >> ic) & 1u)) {
            taken |= 1u << ic;
            channels[n++] = ic;
        }
    }
    return n;
}

/* How many signals the domain's images `order[0..used)` give. */
static int domain_signal_count(const texopt_model *model, const texopt_domain *dom, const int *order, int used)
{
    int count = 0, channel[5];
    for (int i = 0; i < used; i++)
        count += image_signal_channels(&model->images[order[i]], image_use_in_domain(model, dom, order[i]), 0, channel);
    return count;
}

/* Orders images by (width, height, index), so equal sizes end up next to each other. */
static int image_before(const texopt_model *model, int ia, int ib)
{
    const texopt_image *x = &model->images[ia], *y = &model->images[ib];
    if (x->width != y->width)
        return x->width < y->width;
    if (x->height != y->height)
        return x->height < y->height;
    return ia < ib;
}

/* Lists the signals, grouped by texture size so equal-size textures share bake calls. */
static texopt_status build_signals(texopt_triloss *tl, char *err, size_t err_len)
{
    const texopt_model *model = tl->model;
    const texopt_domain *dom = &model->domains[tl->mesh->domain];
    int count = 0;
    for (int i = 0; i < dom->image_count; i++)
        if (model->images[dom->images[i]].pixels)
            count += 5;
    if (count == 0)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "triloss: domain %d has no decoded texture",
                           tl->mesh->domain);
    tl->signals = calloc((size_t)count, sizeof *tl->signals);
    tl->batches = calloc((size_t)count, sizeof *tl->batches);
    if (!tl->signals || !tl->batches)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triloss: no memory for signals");

    int *order = malloc(sizeof(int) * (size_t)dom->image_count);
    if (!order)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triloss: no memory for signals");
    int used = 0;
    for (int i = 0; i < dom->image_count; i++)
        if (model->images[dom->images[i]].pixels)
            order[used++] = dom->images[i];
    for (int i = 1; i < used; i++)
        for (int j = i; j > 0 && image_before(model, order[j], order[j - 1]); j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }

    int fallback = domain_signal_count(model, dom, order, used) == 0;
    for (int i = 0; i < used; i++) {
        const texopt_image *img = &model->images[order[i]];
        int channel[5];
        int channels = image_signal_channels(img, image_use_in_domain(model, dom, order[i]), fallback, channel);
        for (int c = 0; c < channels; c++) {
            loss_batch *last = tl->batch_count ? &tl->batches[tl->batch_count - 1] : NULL;
            if (!last || last->tex_w != img->width || last->tex_h != img->height ||
                last->signal_count == TRILOSS_BATCH_MAX) {
                last = &tl->batches[tl->batch_count++];
                last->first_signal = tl->signal_count;
                last->tex_w = img->width;
                last->tex_h = img->height;
                last->sx = (double)img->width / tl->mesh->width;
                last->sy = (double)img->height / tl->mesh->height;
            }
            last->signal_count++;
            tl->signals[tl->signal_count].image = order[i];
            tl->signals[tl->signal_count].channel = channel[c];
            tl->signals[tl->signal_count].weight = 1.0f;
            tl->signal_count++;
        }
    }
    free(order);
    return TEXOPT_OK;
}

/* An evaluator without close-ups. */
static texopt_status create_evaluator(texopt_triloss **out, const texopt_model *model, const texopt_mesh *mesh,
                                      int viewport, char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triloss: NULL output");
    *out = NULL;
    if (!model || !mesh)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triloss: NULL model or mesh");
    if (mesh->domain < 0 || mesh->domain >= model->domain_count || mesh->width <= 0 || mesh->height <= 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "triloss: mesh domain %d is not a domain of the model", mesh->domain);
    texopt_triloss *tl = calloc(1, sizeof *tl);
    if (!tl)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triloss: out of memory");
    tl->model = model;
    tl->mesh = mesh;
    tl->size = viewport;
    tl->wrap_s = model->domains[mesh->domain].wrap_s;
    tl->wrap_t = model->domains[mesh->domain].wrap_t;
    texopt_status st = texopt_uvraster_create(&tl->raster, viewport, err, err_len);
    if (st == TEXOPT_OK)
        st = build_signals(tl, err, err_len);
    if (st == TEXOPT_OK) {
        size_t px = (size_t)viewport * (size_t)viewport;
        tl->pixel = malloc(px * sizeof *tl->pixel);
        tl->phat = malloc(2 * px * sizeof *tl->phat);
        tl->reference = malloc(px * (size_t)tl->signal_count * sizeof *tl->reference);
        tl->active = malloc((size_t)tl->signal_count * sizeof *tl->active);
        tl->deciding = calloc((size_t)tl->signal_count, 1);
        tl->split = malloc(px * TRILOSS_BATCH_MAX * sizeof *tl->split);
        tl->ref_img = calloc(px * (size_t)tl->signal_count, sizeof *tl->ref_img);
        tl->mask = calloc(px, 1);
        tl->pos = malloc(2 * px * sizeof *tl->pos);
        tl->recon = malloc(px * TRILOSS_BATCH_MAX * sizeof *tl->recon);
        tl->dist_img = calloc(px, sizeof *tl->dist_img);
        tl->bake = texopt_bake_workspace_create((int)px, TRILOSS_BATCH_MAX);
        tl->gmsd = texopt_gmsd_workspace_create(viewport, viewport);
        tl->gmsd_ref = calloc((size_t)tl->signal_count, sizeof *tl->gmsd_ref);
        int refs_ok = tl->gmsd_ref != NULL;
        for (int s = 0; refs_ok && s < tl->signal_count; s++)
            refs_ok = (tl->gmsd_ref[s] = texopt_gmsd_reference_create(viewport, viewport)) != NULL;
        if (!tl->pixel || !tl->phat || !tl->reference || !tl->active || !tl->deciding || !tl->split || !tl->ref_img ||
            !tl->mask || !tl->pos || !tl->recon || !tl->dist_img || !tl->bake || !tl->gmsd || !refs_ok)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triloss: out of memory for a %dx%d view", viewport,
                             viewport);
    }
    if (st != TEXOPT_OK) {
        texopt_triloss_destroy(tl);
        return st;
    }
    *out = tl;
    return TEXOPT_OK;
}

texopt_status texopt_triloss_create(texopt_triloss **out, const texopt_model *model, const texopt_mesh *mesh,
                                    int viewport, char *err, size_t err_len)
{
    texopt_status st = create_evaluator(out, model, mesh, viewport, err, err_len);
    for (int k = 0; k < TEXOPT_TRILOSS_CLOSE_UPS && st == TEXOPT_OK; k++)
        st = create_evaluator(&(*out)->close_up[k], model, mesh, viewport, err, err_len);
    if (st != TEXOPT_OK && *out) {
        texopt_triloss_destroy(*out);
        *out = NULL;
    }
    return st;
}

void texopt_triloss_weigh_signals(texopt_triloss *tl, const double *weights)
{
    for (int s = 0; tl && weights && s < tl->signal_count; s++) {
        const loss_signal *sig = &tl->signals[s];
        tl->signals[s].weight =
            (float)weights[TEXOPT_LIT_WEIGHT_STRIDE * (size_t)sig->image + (size_t)(sig->channel + 1)];
    }
    for (int k = 0; tl && k < TEXOPT_TRILOSS_CLOSE_UPS; k++)
        texopt_triloss_weigh_signals(tl->close_up[k], weights);
}

void texopt_triloss_use_paper_window(texopt_triloss *tl)
{
    if (!tl)
        return;
    tl->raster->paper_window = 1;
    tl->raster->max_zoom = 0.0;
    tl->raster->max_covered = 0;
}

void texopt_triloss_destroy(texopt_triloss *tl)
{
    if (!tl)
        return;
    for (int k = 0; k < TEXOPT_TRILOSS_CLOSE_UPS; k++)
        texopt_triloss_destroy(tl->close_up[k]);
    texopt_uvraster_destroy(tl->raster);
    free(tl->signals);
    free(tl->batches);
    free(tl->pixel);
    free(tl->phat);
    free(tl->reference);
    free(tl->active);
    free(tl->deciding);
    free(tl->split);
    free(tl->ref_img);
    free(tl->mask);
    free(tl->pos);
    free(tl->recon);
    free(tl->dist_img);
    texopt_bake_workspace_destroy(tl->bake);
    texopt_gmsd_workspace_destroy(tl->gmsd);
    for (int s = 0; tl->gmsd_ref && s < tl->signal_count; s++)
        texopt_gmsd_reference_destroy(tl->gmsd_ref[s]);
    free(tl->gmsd_ref);
    free(tl);
}

/* Copies the covered pixels of the raster into a compact list and sets the mask. */
static void collect_covered(texopt_triloss *tl)
{
    const texopt_uvraster *r = tl->raster;
    size_t px = (size_t)tl->size * (size_t)tl->size, n = 0;
    double radius = 0.0;
    for (size_t q = 0; q < px; q++) {
        tl->mask[q] = r->face[q] >= 0;
        tl->dist_img[q] = 0.0f;
        if (!tl->mask[q])
            continue;
        tl->pixel[n] = (int32_t)q;
        tl->phat[2 * n] = r->texel[2 * q];
        tl->phat[2 * n + 1] = r->texel[2 * q + 1];
        radius =
            fmax(radius, fmax(fabs(tl->phat[2 * n] - tl->centroid[0]), fabs(tl->phat[2 * n + 1] - tl->centroid[1])));
        n++;
    }
    tl->n = n;
    tl->radius = radius;
}

static int signal_is_constant(const float *block, size_t n, int stride, int s)
{
    for (size_t k = 1; k < n; k++)
        if (block[k * (size_t)stride + (size_t)s] != block[(size_t)s])
            return 0;
    return 1;
}

static int signals_equal(const float *block, size_t n, int stride, int s, int t)
{
    for (size_t k = 0; k < n; k++)
        if (block[k * (size_t)stride + (size_t)s] != block[k * (size_t)stride + (size_t)t])
            return 0;
    return 1;
}

/* Keeps the columns `columns[0..count)` (ascending) of an n x stride row-major block, in
 * place as n x count: row k moves to k * count <= k * stride, so the forward order never
 * overwrites a value it has still to read. */
static void keep_columns(float *block, size_t n, int stride, const int *columns, int count)
{
    for (size_t k = 0; k < n; k++)
        for (int j = 0; j < count; j++)
            block[k * (size_t)count + (size_t)j] = block[k * (size_t)stride + (size_t)columns[j]];
}

/* Which signals of batch b the candidates must bake, and their references compacted in
 * place (n x active_count). Left out, on this triangle: a signal constant over the covered
 * pixels (the bake reproduces a constant under every J, so its GMSD is 0 up to rounding:
 * ORM channels a material does not use, black emissive) and a signal equal to an earlier one
 * (grey occlusion stored as RGB: same bake, same GMSD). Only the maximum over signals is
 * kept, so this changes E by rounding at most and saves their solves and GMSDs. */
static void select_active_signals(texopt_triloss *tl, int b)
{
    loss_batch *batch = &tl->batches[b];
    float *block = tl->reference + tl->n * (size_t)batch->first_signal;
    int *active = tl->active + batch->first_signal;
    int count = 0, stride = batch->signal_count;
    for (int s = 0; s < stride; s++) {
        int keep = !signal_is_constant(block, tl->n, stride, s);
        for (int j = 0; keep && j < count; j++)
            keep = !signals_equal(block, tl->n, stride, s, active[j]);
        if (keep)
            active[count++] = s;
    }
    keep_columns(block, tl->n, stride, active, count);
    batch->active_count = count;
    batch->lead = 0;
}

/* The signals first..end-1 of a batch that read the same image as signal `first`. */
static int same_image_run_end(const texopt_triloss *tl, const loss_batch *batch, int first)
{
    int end = first + 1;
    while (end < batch->signal_count &&
           tl->signals[batch->first_signal + end].image == tl->signals[batch->first_signal + first].image)
        end++;
    return end;
}

/* I_hat: the input textures looked up at p_hat, as signals; one lookup per image and pixel
 * serves every signal (channel) of that image. */
static void sample_references(texopt_triloss *tl)
{
    size_t px = (size_t)tl->size * (size_t)tl->size;
    memset(tl->ref_img, 0, px * (size_t)tl->signal_count * sizeof *tl->ref_img);
    for (int b = 0; b < tl->batch_count; b++) {
        const loss_batch *batch = &tl->batches[b];
        float *block = tl->reference + tl->n * (size_t)batch->first_signal;
        for (int first = 0, end; first < batch->signal_count; first = end) {
            end = same_image_run_end(tl, batch, first);
            const texopt_image *img = &tl->model->images[tl->signals[batch->first_signal + first].image];
            for (size_t k = 0; k < tl->n; k++) {
                float v[4];
                texopt_sample_bilinear(img, tl->wrap_s, tl->wrap_t, tl->phat[2 * k] * batch->sx,
                                       tl->phat[2 * k + 1] * batch->sy, v);
                for (int s = first; s < end; s++) {
                    const loss_signal *sig = &tl->signals[batch->first_signal + s];
                    float value = sig->weight * (sig->channel < 0 ? texopt_luma(v, img->channels) : v[sig->channel]);
                    block[k * (size_t)batch->signal_count + (size_t)s] = value;
                    tl->ref_img[px * (size_t)(batch->first_signal + s) + (size_t)tl->pixel[k]] = value;
                }
            }
        }
        select_active_signals(tl, b);
        /* Only the active signals are compared (signal_loss). Cannot fail: the images are
         * the viewport the references were created for. */
        for (int j = 0; j < batch->active_count; j++) {
            int s = batch->first_signal + tl->active[batch->first_signal + j];
            texopt_gmsd_reference_set(tl->gmsd_ref[s], tl->ref_img + px * (size_t)s, tl->mask, tl->size, tl->size);
        }
    }
}

/* The references of the triangle as the raster shows it. */
static void sample_prepared(texopt_triloss *tl, uint32_t triangle)
{
    tl->close_up_count = 0;
    memset(tl->deciding, 0, (size_t)tl->signal_count);
    const uint32_t *tri = tl->mesh->triangle + 3 * (size_t)triangle;
    /* J pivots about the texel centre nearest the centroid: a quarter turn about a texel
     * centre maps the texel lattice onto itself, so the loss keeps the 90-degree symmetry of
     * the pixel grid (paper Fig. 7) instead of charging a sub-texel phase shift to every
     * rotation. Close-ups pivot about the same centre: one J deforms the whole triangle. */
    for (int d = 0; d < 2; d++) {
        double c = (tl->mesh->texel[2 * (size_t)tri[0] + d] + tl->mesh->texel[2 * (size_t)tri[1] + d] +
                    tl->mesh->texel[2 * (size_t)tri[2] + d]) /
                   3.0;
        tl->centroid[d] = floor(c) + 0.5;
    }
    collect_covered(tl);
    sample_references(tl);
}

/* Prepares close-up evaluator `view` on the window of side `side` centred at (x, y). */
static texopt_status prepare_close_up(texopt_triloss *view, uint32_t triangle, double x, double y, double side,
                                      char *err, size_t err_len)
{
    double window[3] = {x - 0.5 * side, y - 0.5 * side, side};
    texopt_status st = texopt_uvraster_render_window(view->raster, view->mesh, triangle, window, err, err_len);
    if (st == TEXOPT_OK)
        sample_prepared(view, triangle);
    return st;
}

/* Index of the largest score, -1 when none is above 0; the first of equal ones. */
static int best_score(const double *score, int n)
{
    int best = -1;
    for (int i = 0; i < n; i++)
        if (score[i] > 0.0 && (best < 0 || score[i] > score[best]))
            best = i;
    return best;
}

/* Close-ups of a triangle its own window shows at over CLOSE_UP_FROM times the zoom limit:
 * every candidate window at the limit (camera.h texopt_camera_close_up_centres) is scored by
 * its E under the probe, in the first close-up evaluator, and the best ones are kept. */
static texopt_status prepare_close_ups(texopt_triloss *tl, uint32_t triangle, char *err, size_t err_len)
{
    const texopt_mesh *mesh = tl->mesh;
    const texopt_uvraster *r = tl->raster;
    double density = sqrt(fabs(mesh->area_texel[triangle]) / mesh->area_3d[triangle]);
    if (!tl->close_up[0] || !(r->max_zoom > 0.0) || !(density > 0.0) || !isfinite(density) ||
        !(texopt_camera_zoom(&r->camera, density) > CLOSE_UP_FROM * r->max_zoom))
        return TEXOPT_OK;
    double side = r->max_zoom * r->size / density, centres[2 * CLOSE_UP_CANDIDATES], score[CLOSE_UP_CANDIDATES];
    const uint32_t *tri = mesh->triangle + 3 * (size_t)triangle;
    int n = (int)texopt_camera_close_up_centres(
        &r->camera, texopt_mesh_vertex_point(mesh, tri[0]), texopt_mesh_vertex_point(mesh, tri[1]),
        texopt_mesh_vertex_point(mesh, tri[2]), side, CLOSE_UP_CANDIDATES, centres);
    const double probe[4] = {CLOSE_UP_PROBE, 0.0, 0.0, CLOSE_UP_PROBE};
    texopt_status st = TEXOPT_OK;
    for (int i = 0; i < n && st == TEXOPT_OK; i++) {
        st = prepare_close_up(tl->close_up[0], triangle, centres[2 * i], centres[2 * i + 1], side, err, err_len);
        if (st == TEXOPT_OK)
            st = texopt_triloss_eval(tl->close_up[0], probe, INFINITY, &score[i], err, err_len);
    }
    for (int k = 0; k < TEXOPT_TRILOSS_CLOSE_UPS && st == TEXOPT_OK; k++) {
        int i = best_score(score, n);
        if (i < 0)
            break;
        score[i] = 0.0;
        st = prepare_close_up(tl->close_up[k], triangle, centres[2 * i], centres[2 * i + 1], side, err, err_len);
        if (st == TEXOPT_OK)
            tl->close_up_count = k + 1;
    }
    return st;
}

/* The side of the texture a candidate is re-baked into: the input's, or wider when the
 * one-ring reaches further from its centroid (check_grids keeps it within the bake's size). */
static double grid_side(int tex, double radius_texels)
{
    double need = 2.0 * ceil(radius_texels) + 8.0;
    return need > tex ? need : tex;
}

/* A one-ring spanning so many texels (UVs that repeat the texture hundreds of times over a
 * few triangles) that the texture it is re-baked into would pass the bake's 2^31 texels is
 * refused here, with what it spans, rather than by the bake with a bare size. */
static texopt_status check_grids(const texopt_triloss *tl, char *err, size_t err_len)
{
    for (int b = 0; b < tl->batch_count && tl->n > 0; b++) {
        const loss_batch *batch = &tl->batches[b];
        double w = grid_side(batch->tex_w, tl->radius * batch->sx);
        double h = grid_side(batch->tex_h, tl->radius * batch->sy);
        if (!(w * h <= 0x7fffffff))
            return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                               "its neighbourhood spans %.0f x %.0f texels, %.0f repeats of its "
                               "%dx%d texture, too many to re-bake (UVs or a texture transform scaled by "
                               "hundreds?)",
                               w, h, w / batch->tex_w, batch->tex_w, batch->tex_h);
    }
    return TEXOPT_OK;
}

texopt_status texopt_triloss_prepare(texopt_triloss *tl, uint32_t triangle, char *err, size_t err_len)
{
    if (!tl)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triloss: NULL evaluator");
    texopt_status st = texopt_uvraster_render(tl->raster, tl->mesh, triangle, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    sample_prepared(tl, triangle);
    st = check_grids(tl, err, err_len);
    return st == TEXOPT_OK ? prepare_close_ups(tl, triangle, err, err_len) : st;
}

/* p(q) = c + J (p_hat - c) in the batch's texels, shifted by whole texels to the grid centre. */
static void candidate_positions(texopt_triloss *tl, const loss_batch *batch, const double J[4], int grid_w, int grid_h)
{
    double cx = tl->centroid[0], cy = tl->centroid[1];
    double ox = floor(0.5 * grid_w) - floor(cx * batch->sx);
    double oy = floor(0.5 * grid_h) - floor(cy * batch->sy);
    for (size_t k = 0; k < tl->n; k++) {
        double dx = tl->phat[2 * k] - cx, dy = tl->phat[2 * k + 1] - cy;
        tl->pos[2 * k] = (cx + J[0] * dx + J[1] * dy) * batch->sx + ox;
        tl->pos[2 * k + 1] = (cy + J[2] * dx + J[3] * dy) * batch->sy + oy;
    }
}

/* GMSD of active signal j of the batch against the reconstruction column c of `columns`. */
static texopt_status signal_loss(texopt_triloss *tl, const loss_batch *batch, int j, int c, int columns, double *e,
                                 char *err, size_t err_len)
{
    int signal = batch->first_signal + tl->active[batch->first_signal + j];
    for (size_t k = 0; k < tl->n; k++)
        tl->dist_img[tl->pixel[k]] = tl->recon[k * (size_t)columns + (size_t)c];
    *e = texopt_gmsd_against(tl->gmsd, tl->gmsd_ref[signal], tl->dist_img);
    if (!isfinite(*e))
        return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "triloss: GMSD is not finite for signal %d", signal);
    return TEXOPT_OK;
}

/* The running maximum of an evaluation and the signal that set it. */
typedef struct loss_max {
    double value;
    int signal; /* -1 while every E so far is 0 */
} loss_max;

static void raise_max(loss_max *m, const texopt_triloss *tl, const loss_batch *batch, int j, double e)
{
    if (e > m->value) {
        m->value = e;
        m->signal = batch->first_signal + tl->active[batch->first_signal + j];
    }
}

/* The batch's largest E over its active signals, all baked in one fit. */
static texopt_status batch_loss_together(texopt_triloss *tl, loss_batch *batch, const float *block, int grid_w,
                                         int grid_h, loss_max *worst, char *err, size_t err_len)
{
    int count = batch->active_count;
    texopt_status st = texopt_bake_fit(tl->bake, (int)tl->n, tl->pos, block, count, grid_w, grid_h, TEXOPT_WRAP_REPEAT,
                                       TEXOPT_WRAP_REPEAT, TRILOSS_RIDGE, tl->recon, err, err_len);
    double top = -1.0;
    for (int j = 0; j < count && st == TEXOPT_OK; j++) {
        double e;
        st = signal_loss(tl, batch, j, j, count, &e, err, err_len);
        if (st != TEXOPT_OK)
            break;
        if (e > top) {
            top = e;
            batch->lead = j;
        }
        raise_max(worst, tl, batch, j, e);
    }
    return st;
}

/* The same with an early exit: the lead signal (the largest E last time) is baked and
 * compared first, and when it alone reaches stop_above the other signals are not solved;
 * otherwise they are, reusing the lead's factorisation. */
static texopt_status batch_loss_lead_first(texopt_triloss *tl, loss_batch *batch, const float *block, int grid_w,
                                           int grid_h, double stop_above, loss_max *worst, char *err, size_t err_len)
{
    int count = batch->active_count, lead = batch->lead;
    for (size_t k = 0; k < tl->n; k++)
        tl->split[k] = block[k * (size_t)count + (size_t)lead];
    texopt_status st = texopt_bake_fit(tl->bake, (int)tl->n, tl->pos, tl->split, 1, grid_w, grid_h, TEXOPT_WRAP_REPEAT,
                                       TEXOPT_WRAP_REPEAT, TRILOSS_RIDGE, tl->recon, err, err_len);
    double top;
    if (st == TEXOPT_OK)
        st = signal_loss(tl, batch, lead, 0, 1, &top, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    raise_max(worst, tl, batch, lead, top);
    if (worst->value >= stop_above)
        return TEXOPT_OK;
    int rest = count - 1;
    for (size_t k = 0; k < tl->n; k++)
        for (int j = 0, c = 0; j < count; j++)
            if (j != lead)
                tl->split[k * (size_t)rest + (size_t)c++] = block[k * (size_t)count + (size_t)j];
    st = texopt_bake_refit(tl->bake, tl->split, rest, tl->recon, err, err_len);
    for (int j = 0, c = 0; j < count && st == TEXOPT_OK; j++) {
        if (j == lead)
            continue;
        double e;
        st = signal_loss(tl, batch, j, c++, rest, &e, err, err_len);
        if (st == TEXOPT_OK && e > top) {
            top = e;
            batch->lead = j;
        }
        raise_max(worst, tl, batch, j, e);
    }
    return st;
}

texopt_status texopt_triloss_eval(texopt_triloss *tl, const double jacobian[4], double stop_above, double *out_loss,
                                  char *err, size_t err_len)
{
    if (!tl || !jacobian || !out_loss)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triloss: NULL argument");
    *out_loss = 0.0;
    loss_max worst = {0.0, -1};
    for (int b = 0; b < tl->batch_count && tl->n > 0; b++) {
        loss_batch *batch = &tl->batches[b];
        if (batch->active_count == 0)
            continue;
        int grid_w = (int)grid_side(batch->tex_w, tl->radius * batch->sx);
        int grid_h = (int)grid_side(batch->tex_h, tl->radius * batch->sy);
        candidate_positions(tl, batch, jacobian, grid_w, grid_h);
        const float *block = tl->reference + tl->n * (size_t)batch->first_signal;
        texopt_status st =
            batch->active_count > 1 && isfinite(stop_above)
                ? batch_loss_lead_first(tl, batch, block, grid_w, grid_h, stop_above, &worst, err, err_len)
                : batch_loss_together(tl, batch, block, grid_w, grid_h, &worst, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        if (worst.value >= stop_above)
            break;
    }
    if (worst.signal >= 0)
        tl->deciding[worst.signal] = 1;
    *out_loss = worst.value;
    for (int k = 0; k < tl->close_up_count && *out_loss < stop_above; k++) {
        double e;
        texopt_status st = texopt_triloss_eval(tl->close_up[k], jacobian, stop_above, &e, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        *out_loss = fmax(*out_loss, e);
    }
    return TEXOPT_OK;
}

void texopt_triloss_keep_deciding(texopt_triloss *tl)
{
    for (int k = 0; tl && k < tl->close_up_count; k++)
        texopt_triloss_keep_deciding(tl->close_up[k]);
    int any = 0;
    for (int s = 0; tl && s < tl->signal_count; s++)
        any |= tl->deciding[s];
    if (!any)
        return;
    for (int b = 0; b < tl->batch_count; b++) {
        loss_batch *batch = &tl->batches[b];
        int *active = tl->active + batch->first_signal, keep[TRILOSS_BATCH_MAX], kept = 0;
        for (int j = 0; j < batch->active_count; j++)
            if (tl->deciding[batch->first_signal + active[j]])
                keep[kept++] = j;
        keep_columns(tl->reference + tl->n * (size_t)batch->first_signal, tl->n, batch->active_count, keep, kept);
        for (int j = 0; j < kept; j++)
            active[j] = active[keep[j]];
        batch->active_count = kept;
        batch->lead = 0;
    }
}

const texopt_uvraster *texopt_triloss_raster(const texopt_triloss *tl)
{
    return tl ? tl->raster : NULL;
}

int texopt_triloss_close_up_count(const texopt_triloss *tl)
{
    return tl ? tl->close_up_count : 0;
}

int texopt_triloss_signal_count(const texopt_triloss *tl)
{
    return tl ? tl->signal_count : 0;
}
