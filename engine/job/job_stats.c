/* job_stats.c - the job's statistics filled from what its stages report (job_stats.h). */
#include "job_stats.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "distortion.h"

void job_stats_fill_params(texopt_job_stats *js, const texopt_params *p)
{
    js->method = texopt_method_name(p->method);
    js->budget = p->budget == TEXOPT_BUDGET_TEXTURE_SIZE  ? "texture_size"
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
    js->refine_lit = p->refine_lit;
    js->mipmapped = p->mipmapped != 0;
    js->packing_efficiency = p->packing_efficiency;
    js->bijective = p->bijective != 0;
    js->packing_refine = p->packing_refine != 0;
    js->hessian_floor = texopt_params_hessian_floor(p);
    js->metric_candidates = p->metric_candidates > 0;
    js->resize_check = p->resize_check > 0;
    js->charts = p->charts;
    js->parameterizer = p->parameterizer;
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

texopt_status job_stats_record_images(const texopt_model *model, const texopt_domain *dom, texopt_domain_stats *ds,
                                      char *err, size_t err_len)
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

void job_stats_record_stage1(const texopt_mesh *mesh, const texopt_triangle_target *targets,
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

void job_stats_record_stage2(const texopt_meshwise_report *rep, texopt_domain_stats *ds)
{
    ds->has_stage2 = 1;
    ds->stage2_iterations = rep->iterations;
    ds->energy_initial = rep->energy_initial;
    ds->energy_final = rep->energy_final;
    ds->flipped = (size_t)rep->flipped;
}

void job_stats_record_scaffold(const texopt_scaffold_report *rep, texopt_domain_stats *ds)
{
    ds->has_scaffold = 1;
    ds->scaffold_rounds = rep->rounds;
    ds->scaffold_charts = rep->charts_scaffolded;
    ds->scaffold_skipped_charts = rep->charts_skipped;
    ds->scaffold_triangles = rep->triangles;
}

void job_stats_record_distortion(const texopt_mesh *mesh, const double *texel, texopt_domain_stats *ds)
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

void job_stats_record_evaluation(texopt_job_stats *js, const texopt_evaluation *ev)
{
    js->has_evaluation = 1;
    js->q = ev->q;
    js->eval_resolution = ev->resolution;
    js->seconds_evaluate = ev->seconds;
}

void job_stats_free_domains(texopt_domain_stats *ds, int n)
{
    if (ds)
        for (int d = 0; d < n; d++)
            free(ds[d].images);
    free(ds);
}

texopt_domain_stats *job_stats_copy_domains(const texopt_job_stats *js)
{
    int n = js->domain_count;
    texopt_domain_stats *c = calloc((size_t)(n > 0 ? n : 1), sizeof *c);
    for (int d = 0; c && d < n; d++) {
        c[d] = js->domains[d];
        c[d].images = NULL;
        size_t k = (size_t)(c[d].image_count > 0 ? c[d].image_count : 1);
        c[d].images = js->domains[d].images ? malloc(k * sizeof *c[d].images) : NULL;
        if (js->domains[d].images && !c[d].images) {
            job_stats_free_domains(c, n);
            return NULL;
        }
        if (c[d].images)
            memcpy(c[d].images, js->domains[d].images, k * sizeof *c[d].images);
    }
    return c;
}
