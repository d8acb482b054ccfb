/* resize_check.c - never worse than a resize (resize_check.h). */
#include "resize_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake_pool.h"
#include "input_method.h"
#include "job_evaluate.h"
#include "job_stats.h"

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
    texopt_status st = job_output_alloc(model, job->method->targets != NULL, resized, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    memcpy(resized->uvs, out->uvs, 2 * model->vertex_count * sizeof *resized->uvs);
    job_output_restore_uvs(model, d, resized->uvs);
    for (int i = 0; i < model->image_count; i++)
        resized->edit_images[i] = out->edit_images[i];
    for (int i = 0; i < dom->image_count; i++)
        resized->edit_images[dom->images[i]] = NULL;
    texopt_params same_pixels = *p;
    same_pixels.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    same_pixels.texture_width = rs[d].output_width;
    same_pixels.texture_height = rs[d].output_height;
    layout_run run = {.p = &same_pixels, .domains = rs, .out = resized};
    return job_run_input_method(job, &run, d, at, at, err, err_len);
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
    }
    job_output_restore_uvs(job->model, d, out->uvs);
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
        job_output resized = {0};
        texopt_map_q q[2];
        texopt_domain_stats *rs = job_stats_copy_domains(&job->stats);
        st = rs ? resized_input_layout(job, p, out, d, at, &resized, rs, err, err_len)
                : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the resize's statistics");
        const job_output *shown[2] = {out, &resized};
        if (st == TEXOPT_OK) {
            job_stage(&job->jm, "evaluate", at, at);
            st = job_evaluate_maps(job, shown, 2, p, CHOICE_CAMERAS, d, q, err, err_len);
        }
        int by = TEXOPT_SLOT_BASE_COLOR, kept = st == TEXOPT_OK && !texopt_map_layout_wins(&q[0], &q[1], &by);
        if (kept)
            keep_resized_input_layout(job, out, &resized, d, rs);
        texopt_domain_stats *ds = &job->stats.domains[d];
        if (kept)
            snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                     "its new layout's %s q on the choice's views, %.6g, is not below the %.6g of its input layout "
                     "resized with Lanczos-3 to the same %dx%d texture; the input layout is kept, its images "
                     "resized",
                     texopt_map_measure_name(by), q[0].q[by], q[1].q[by], ds->output_width, ds->output_height);
        if (st == TEXOPT_OK) {
            ds->has_resize_check = 1;
            ds->resize_check_kept = kept;
            ds->resize_check_decided_by = by;
            ds->q_resize_check_layout = q[0].q[by];
            ds->q_resize_check_resize = q[1].q[by];
            ds->resize_check_maps_layout = q[0];
            ds->resize_check_maps_resize = q[1];
            ds->seconds_resize_check = job_now_seconds() - t0;
        }
        job_output_destroy(&resized, job->model->image_count);
        job_stats_free_domains(rs, n);
    }
    return st;
}
