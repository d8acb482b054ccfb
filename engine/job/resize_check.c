/* resize_check.c - never worse than a resize (resize_check.h). */
#include "resize_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake_pool.h"
#include "input_method.h"
#include "job_evaluate.h"
#include "job_stats.h"
#include "meshrender.h"

/* How a domain's input layout gets its images at the new layout's pixels (input_method.h). */
typedef texopt_status (*input_images_fn)(texopt_job *job, const layout_run *run, int d, double from, double to,
                                         char *err, size_t err_len);

/* Into *resized: out with domain d's input layout in place of its new one, its images made by
 * `make` (input_method.h: resized with Lanczos-3, or re-baked by the fit) at the sizes out's
 * layout writes them at, the same file texture pixels; the other domains' UVs copied and
 * their images borrowed from out. Its statistics in rs[d] (a copy of the job's). */
static texopt_status input_layout_at_same_pixels(texopt_job *job, const texopt_params *p, const job_output *out, int d,
                                                 double at, input_images_fn make, job_output *resized,
                                                 texopt_domain_stats *rs, char *err, size_t err_len)
{
    const texopt_model *model = job->model;
    const texopt_domain *dom = &model->domains[d];
    texopt_status st = job_output_alloc(model, job->method->targets != NULL, resized, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    memcpy(resized->uvs, out->uvs, 2 * model->vertex_count * sizeof *resized->uvs);
    job_output_restore_uvs(model, d, resized->uvs);
    st = job_output_copy_corners(model, out, resized, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    job_output_uncut_domain(model, d, resized);
    for (int i = 0; i < model->image_count; i++)
        resized->edit_images[i] = out->edit_images[i];
    for (int i = 0; i < dom->image_count; i++)
        resized->edit_images[dom->images[i]] = NULL;
    texopt_params same_pixels = *p;
    same_pixels.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    same_pixels.texture_width = rs[d].output_width;
    same_pixels.texture_height = rs[d].output_height;
    layout_run run = {.p = &same_pixels, .plan = BAKE_ALL, .domains = rs, .out = resized};
    return make(job, &run, d, at, at, err, err_len);
}

/* Whether a primitive of domain d reads image im through texture key `key`. */
static int key_reads_image(const texopt_model *model, int d, int key, int im)
{
    for (int p = 0; p < model->primitive_count; p++) {
        const texopt_texture_ref *r =
            model->primitives[p].domain == d ? texopt_meshrender_binding(model, p, key) : NULL;
        if (r && r->image == im)
            return 1;
    }
    return 0;
}

/* Per image of domain d, into use_fit: whether its fitted bake is kept, being above the resize
 * in no map that reads it (an image no measured map reads keeps its resize). Returns how
 * many are. */
static int choose_fitted_images(const texopt_model *model, int d, const texopt_map_q *resize, const texopt_map_q *fit,
                                int *use_fit)
{
    const texopt_domain *dom = &model->domains[d];
    int count = 0;
    for (int i = 0; i < dom->image_count; i++) {
        int read = 0, above = 0;
        for (int m = 0; m < TEXOPT_TEXTURE_KEY_COUNT; m++)
            if (resize->measured[m] && key_reads_image(model, d, m, dom->images[i])) {
                read = 1;
                above |= fit->q[m] > resize->q[m];
            }
        use_fit[i] = read && !above;
        count += use_fit[i];
    }
    return count;
}

/* Swaps the images of domain d not in use_fit, with their statistics, between *fitted and
 * *resized: *fitted becomes the mix the fallback writes, *resized the rest; swapping again
 * undoes it. */
static void swap_resized_images(const texopt_model *model, int d, const int *use_fit, job_output *fitted,
                                texopt_domain_stats *fs, job_output *resized, texopt_domain_stats *rs)
{
    const texopt_domain *dom = &model->domains[d];
    for (int i = 0; i < dom->image_count; i++) {
        if (use_fit[i])
            continue;
        int im = dom->images[i], f_edited = fitted->edit_images[im] != NULL;
        int r_edited = resized->edit_images[im] != NULL;
        texopt_image tmp = fitted->images[im];
        fitted->images[im] = resized->images[im];
        resized->images[im] = tmp;
        fitted->edit_images[im] = r_edited ? &fitted->images[im] : NULL;
        resized->edit_images[im] = f_edited ? &resized->images[im] : NULL;
        texopt_image_stats is = fs[d].images[i];
        fs[d].images[i] = rs[d].images[i];
        rs[d].images[i] = is;
    }
}

/* Puts domain d of *kept (input_layout_at_same_pixels) and its statistics ks[d] in place of
 * out's new layout of it. */
static void keep_input_layout(texopt_job *job, job_output *out, job_output *kept, int d, const texopt_domain_stats *ks)
{
    const texopt_domain *dom = &job->model->domains[d];
    for (int i = 0; i < dom->image_count; i++) {
        int im = dom->images[i];
        texopt_image_destroy(&out->images[im]);
        out->images[im] = kept->images[im];
        memset(&kept->images[im], 0, sizeof kept->images[im]);
        out->edit_images[im] = kept->edit_images[im] ? &out->images[im] : NULL;
    }
    job_output_restore_uvs(job->model, d, out->uvs);
    job_output_uncut_domain(job->model, d, out);
    free(out->solved[d]);
    free(out->packed[d]);
    out->solved[d] = NULL;
    out->packed[d] = NULL;
    texopt_domain_stats *ds = &job->stats.domains[d];
    texopt_image_stats *images = ds->images;
    *ds = ks[d];
    ds->images = images;
    memcpy(ds->images, ks[d].images, (size_t)ds->image_count * sizeof *ds->images);
    ds->repacked = 0;
}

/* The three ways to write one domain at the new layout's pixels, and what they measure. */
typedef struct domain_choice {
    job_output resized, fitted; /* the input layout resized; re-baked by the fit (then the mix) */
    texopt_domain_stats *rs, *fs;
    int can_fit;       /* fitted was made (the layout lies in one tile, the pixels differ) */
    int *use_fit;      /* per image of the domain: the mix keeps its fitted bake */
    int fitted_images; /* how many */
    texopt_map_q q[3]; /* layout, resize, fit (every image fitted) */
    texopt_map_q mix;  /* the mix's */
} domain_choice;

static void domain_choice_free(domain_choice *c, const texopt_job *job)
{
    job_output_destroy(&c->resized, job->model->image_count);
    job_output_destroy(&c->fitted, job->model->image_count);
    job_stats_free_domains(c->rs, job->model->domain_count);
    job_stats_free_domains(c->fs, job->model->domain_count);
    free(c->use_fit);
}

/* Makes the resize and, where it can be, the fitted bake of domain d, measures them beside
 * out on the choice's views, and the mix (its images in c->use_fit, its q in c->mix); the
 * resize and the fitted bake are left as they were made. */
static texopt_status measure_choices(texopt_job *job, const texopt_params *p, const job_output *out, int d, double at,
                                     domain_choice *c, char *err, size_t err_len)
{
    const texopt_domain *dom = &job->model->domains[d];
    c->rs = job_stats_copy_domains(&job->stats);
    c->fs = job_stats_copy_domains(&job->stats);
    if (!c->rs || !c->fs)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the resize's statistics");
    texopt_status st =
        input_layout_at_same_pixels(job, p, out, d, at, job_run_input_method, &c->resized, c->rs, err, err_len);
    c->can_fit = st == TEXOPT_OK && (c->rs[d].output_width != dom->width || c->rs[d].output_height != dom->height);
    if (c->can_fit) {
        st = input_layout_at_same_pixels(job, p, out, d, at, job_refit_input_layout, &c->fitted, c->fs, err, err_len);
        c->can_fit = st == TEXOPT_OK;
        if (st == TEXOPT_E_UNSUPPORTED) /* a tiled layout: the resize alone */
            st = TEXOPT_OK;
    }
    const job_output *shown[3] = {out, &c->resized, &c->fitted};
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "evaluate", at, at);
        st = job_evaluate_maps(job, shown, c->can_fit ? 3 : 2, p, CHOICE_CAMERAS, d, c->q, err, err_len);
    }
    c->mix = c->q[1];
    if (st != TEXOPT_OK || !c->can_fit)
        return st;
    c->use_fit = malloc(sizeof(int) * (size_t)(dom->image_count ? dom->image_count : 1));
    if (!c->use_fit)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the fitted images");
    c->fitted_images = choose_fitted_images(job->model, d, &c->q[1], &c->q[2], c->use_fit);
    if (c->fitted_images == dom->image_count)
        c->mix = c->q[2];
    else if (c->fitted_images > 0) {
        swap_resized_images(job->model, d, c->use_fit, &c->fitted, c->fs, &c->resized, c->rs);
        const job_output *mix = &c->fitted;
        st = job_evaluate_maps(job, &mix, 1, p, CHOICE_CAMERAS, d, &c->mix, err, err_len);
        swap_resized_images(job->model, d, c->use_fit, &c->fitted, c->fs, &c->resized, c->rs);
    }
    return st;
}

/* The measure two candidates that both beat the resize in every map are told apart by: what
 * a viewer shows, lit when it is measured, else base colour. */
static int shown_measure(const texopt_map_q *q)
{
    return q->measured[TEXOPT_MAP_LIT] ? TEXOPT_MAP_LIT : TEXOPT_SLOT_BASE_COLOR;
}

/* Which of the three domain d keeps (texopt_resize_check_kept), the measure that decided and
 * whether the layout, below the resize, lost to the fitted bake on it. */
static int decide(const domain_choice *c, int *by, int *lost_to_fit)
{
    *by = TEXOPT_SLOT_BASE_COLOR;
    int by_fit = TEXOPT_SLOT_BASE_COLOR;
    int layout_wins = texopt_map_layout_wins(&c->q[0], &c->q[1], by);
    int fit_wins = c->fitted_images > 0 && texopt_map_layout_wins(&c->mix, &c->q[1], &by_fit);
    int shown = shown_measure(&c->q[0]);
    *lost_to_fit = layout_wins && fit_wins && c->q[0].q[shown] > c->mix.q[shown]; /* a tie keeps the layout */
    if (*lost_to_fit)
        *by = shown;
    if (layout_wins && !*lost_to_fit)
        return TEXOPT_RESIZE_CHECK_LAYOUT;
    return fit_wins ? TEXOPT_RESIZE_CHECK_INPUT_FIT : TEXOPT_RESIZE_CHECK_RESIZE;
}

static void record(texopt_domain_stats *ds, const domain_choice *c, int kept, int by, int lost_to_fit, double seconds)
{
    const texopt_map_q *against = lost_to_fit ? &c->mix : &c->q[1];
    char images[96] = "its images resized with Lanczos-3";
    if (kept == TEXOPT_RESIZE_CHECK_INPUT_FIT && c->fitted_images == ds->image_count)
        snprintf(images, sizeof images, "its images re-baked by the fit");
    else if (kept == TEXOPT_RESIZE_CHECK_INPUT_FIT)
        snprintf(images, sizeof images, "%d of its %d images re-baked by the fit, the others resized with Lanczos-3",
                 c->fitted_images, ds->image_count);
    if (kept != TEXOPT_RESIZE_CHECK_LAYOUT)
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "its new layout's %s q on the choice's views, %.6g, is not below the %.6g of its input layout %s "
                 "to the same %dx%d texture; the input layout is kept, %s",
                 texopt_map_measure_name(by), c->q[0].q[by], against->q[by],
                 lost_to_fit ? "re-baked by the fit" : "resized with Lanczos-3", ds->output_width, ds->output_height,
                 images);
    ds->has_resize_check = 1;
    ds->resize_check_kept = kept;
    ds->resize_check_decided_by = by;
    ds->q_resize_check_layout = c->q[0].q[by];
    ds->q_resize_check_resize = c->q[1].q[by];
    ds->resize_check_maps_layout = c->q[0];
    ds->resize_check_maps_resize = c->q[1];
    ds->resize_check_has_input_fit = c->can_fit;
    ds->resize_check_maps_input_fit = c->mix;
    ds->resize_check_input_fit_images = c->fitted_images;
    ds->seconds_resize_check = seconds;
}

texopt_status job_keep_resize_if_better(texopt_job *job, const texopt_params *p, job_output *out, double at, char *err,
                                        size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    int n = job->model->domain_count;
    for (int d = 0; d < n; d++)
        job->stats.domains[d].has_resize_check = 0;
    layout_run all = {.p = p, .plan = BAKE_ALL, .domains = job->stats.domains, .out = out};
    if (p->resize_check > 0)
        st = job_bake_remaining_images(job, &all, at, at, err, err_len);
    for (int d = 0; d < n && st == TEXOPT_OK && p->resize_check > 0; d++) {
        if (!out->packed || !out->packed[d])
            continue;
        double t0 = job_now_seconds();
        domain_choice c = {0};
        st = measure_choices(job, p, out, d, at, &c, err, err_len);
        if (st == TEXOPT_OK) {
            int by, lost_to_fit, kept = decide(&c, &by, &lost_to_fit);
            if (kept == TEXOPT_RESIZE_CHECK_RESIZE)
                keep_input_layout(job, out, &c.resized, d, c.rs);
            else if (kept == TEXOPT_RESIZE_CHECK_INPUT_FIT) {
                swap_resized_images(job->model, d, c.use_fit, &c.fitted, c.fs, &c.resized, c.rs); /* the mix */
                keep_input_layout(job, out, &c.fitted, d, c.fs);
            }
            record(&job->stats.domains[d], &c, kept, by, lost_to_fit, job_now_seconds() - t0);
        }
        domain_choice_free(&c, job);
    }
    return st;
}
