/* job_evaluate.c - the whole-mesh loss q of a job's layouts, in memory (job_evaluate.h). */
#include "job_evaluate.h"

#include <stdlib.h>

texopt_evaluate_options job_evaluation_options(const texopt_params *p, texopt_camera_set cameras, int lit,
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

/* Each of n outputs as the input model seen through its new UVs and images (a view,
 * job_output.h job_output_view: vertices split where a domain was cut); the caller frees
 * *images and the views (free_output_models). */
static void free_output_models(const texopt_model *model, texopt_model *candidates, int n, texopt_image *images)
{
    for (int c = 0; c < n; c++)
        job_output_view_free(model, &candidates[c]);
    free(images);
}

static texopt_status output_models(const texopt_model *model, const job_output *const *outs, int n,
                                   texopt_model *candidates, const texopt_model **shown, texopt_image **images,
                                   char *err, size_t err_len)
{
    if (n < 1 || n > JOB_MAX_EVALUATED_OUTPUTS)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "evaluation of %d outputs", n);
    size_t k = (size_t)(model->image_count > 0 ? model->image_count : 1);
    *images = calloc((size_t)n * k, sizeof **images);
    if (!*images)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the evaluation");
    texopt_status st = TEXOPT_OK;
    for (int c = 0; c < n; c++)
        candidates[c] = *model;
    for (int c = 0; c < n && st == TEXOPT_OK; c++) {
        texopt_image *own = *images + (size_t)c * k;
        for (int i = 0; i < model->image_count; i++)
            own[i] = outs[c]->edit_images[i] ? *outs[c]->edit_images[i] : model->images[i];
        st = job_output_view(model, outs[c], &candidates[c], err, err_len);
        candidates[c].images = own;
        shown[c] = &candidates[c];
    }
    if (st != TEXOPT_OK) {
        free_output_models(model, candidates, n, *images);
        *images = NULL;
    }
    return st;
}

texopt_status job_evaluate_outputs(texopt_job *job, const job_output *const *outs, int n, const texopt_params *p,
                                   const job_screen *screen, texopt_evaluation *ev, char *err, size_t err_len)
{
    texopt_model candidates[JOB_MAX_EVALUATED_OUTPUTS];
    const texopt_model *shown[JOB_MAX_EVALUATED_OUTPUTS];
    texopt_image *images = NULL;
    texopt_status st = output_models(job->model, outs, n, candidates, shown, &images, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_evaluate_options opt = job_evaluation_options(p, screen->cameras, screen->lit, &job->jm);
    opt.triangle_error = screen->triangle_error;
    /* The refinement's measure (job_refine.h); the lit refinement keeps the luma difference
     * it was measured with (the edge measure was measured on base colour only). */
    opt.triangle_error_edges = !screen->lit;
    opt.reference_views = screen->reference_views;
    st = texopt_evaluate_many(job->model, shown, n, &opt, ev, err, err_len);
    free_output_models(job->model, candidates, n, images);
    return st;
}

texopt_status job_evaluate_maps(texopt_job *job, const job_output *const *outs, int n, const texopt_params *p,
                                texopt_camera_set cameras, int domain, texopt_map_q *q, char *err, size_t err_len)
{
    texopt_model candidates[JOB_MAX_EVALUATED_OUTPUTS];
    const texopt_model *shown[JOB_MAX_EVALUATED_OUTPUTS];
    texopt_image *images = NULL;
    texopt_status st = output_models(job->model, outs, n, candidates, shown, &images, err, err_len);
    int measured[TEXOPT_MAP_MEASURES];
    texopt_map_measures(job->model, domain, measured);
    texopt_evaluate_options opt = job_evaluation_options(p, cameras, 0, &job->jm);
    if (st == TEXOPT_OK) {
        st = texopt_map_evaluate(job->model, shown, n, &opt, measured, q, err, err_len);
        free_output_models(job->model, candidates, n, images);
    }
    return st;
}

texopt_status job_evaluate_output(texopt_job *job, const job_output *out, const texopt_params *p, texopt_evaluation *ev,
                                  char *err, size_t err_len)
{
    job_screen screen = {TEXOPT_CAMERAS_DODECAHEDRON, 0, NULL, NULL};
    return job_evaluate_outputs(job, &out, 1, p, &screen, ev, err, err_len);
}
