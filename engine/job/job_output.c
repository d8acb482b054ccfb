/* job_output.c - what one layout of the budget produces for the save step (job_output.h). */
#include "job_output.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void job_output_destroy(job_output *o, int image_count)
{
    if (o->images)
        for (int i = 0; i < image_count; i++)
            texopt_image_destroy(&o->images[i]);
    free(o->images);
    free(o->edit_images);
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

texopt_status job_output_alloc(const texopt_model *model, int lays_out, job_output *out, char *err, size_t err_len)
{
    size_t n = (size_t)(model->image_count > 0 ? model->image_count : 1);
    out->images = calloc(n, sizeof *out->images);
    out->edit_images = calloc(n, sizeof *out->edit_images);
    if (!out->images || !out->edit_images)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the output images");
    if (!lays_out)
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

void job_output_write_uvs(const texopt_model *model, const texopt_mesh *mesh, const double *texel, int width,
                          int height, float *uvs)
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

float *job_output_uvs_copy(const texopt_model *model)
{
    float *uvs = calloc(2 * (model->vertex_count + 1), sizeof *uvs);
    if (uvs && model->uvs)
        memcpy(uvs, model->uvs, 2 * model->vertex_count * sizeof *uvs);
    return uvs;
}

texopt_status job_output_mesh_with_uvs(const texopt_model *model, int d, const float *uvs, texopt_mesh **mesh,
                                       char *err, size_t err_len)
{
    texopt_model with_uvs = *model; /* read only: the model's own arrays but the UVs */
    with_uvs.uvs = (float *)uvs;
    return texopt_mesh_create(mesh, &with_uvs, d, err, err_len);
}

void job_output_restore_uvs(const texopt_model *model, int d, float *uvs)
{
    const texopt_domain *dom = &model->domains[d];
    for (int i = 0; model->uvs && i < dom->primitive_count; i++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[i]];
        memcpy(uvs + 2 * prim->first_vertex, model->uvs + 2 * prim->first_vertex, 2 * prim->vertex_count * sizeof *uvs);
    }
}

int job_scaled_side(int side, double factor)
{
    long v = lround(side * factor);
    return v < 1 ? 1 : (v > 16384 ? 16384 : (int)v);
}

void job_image_output_size(const texopt_image *img, const texopt_domain *dom, int out_w, int out_h, int *w, int *h)
{
    *w = job_scaled_side(img->width, (double)out_w / dom->width);
    *h = job_scaled_side(img->height, (double)out_h / dom->height);
}
