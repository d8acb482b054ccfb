/* job_output.c - what one layout of the budget produces for the save step (job_output.h). */
#include "job_output.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model_split.h"

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
        if (o->cut)
            texopt_mesh_destroy(o->cut[d]);
    }
    free(o->cut);
    free(o->corner_group);
    free(o->corner_uvs);
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
    out->cut = calloc(n_domains, sizeof *out->cut);
    if (!out->solved || !out->packed || !out->packed_size || !out->cut)
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

static texopt_status alloc_corners(const texopt_model *model, job_output *out, char *err, size_t err_len)
{
    if (out->corner_group)
        return TEXOPT_OK;
    size_t n = 3 * model->triangle_count + 1;
    out->corner_group = calloc(n, sizeof *out->corner_group);
    out->corner_uvs = calloc(2 * n, sizeof *out->corner_uvs);
    if (out->corner_group && out->corner_uvs)
        return TEXOPT_OK;
    free(out->corner_group);
    free(out->corner_uvs);
    out->corner_group = NULL;
    out->corner_uvs = NULL;
    return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the cut corners");
}

texopt_status job_output_write_cut_uvs(const texopt_model *model, const texopt_mesh *cut, const double *texel,
                                       int width, int height, job_output *out, char *err, size_t err_len)
{
    job_output_write_uvs(model, cut, texel, width, height, out->uvs);
    texopt_status st = alloc_corners(model, out, err, err_len);
    for (size_t t = 0; st == TEXOPT_OK && t < cut->triangle_count; t++)
        for (size_t k = 0; k < 3; k++) {
            size_t c = 3 * (size_t)cut->model_triangle[t] + k, v = cut->triangle[3 * t + k];
            out->corner_group[c] = 1 + cut->chart_of[t];
            out->corner_uvs[2 * c] = (float)(texel[2 * v] / width);
            out->corner_uvs[2 * c + 1] = (float)(texel[2 * v + 1] / height);
        }
    return st;
}

void job_output_uncut_domain(const texopt_model *model, int d, job_output *out)
{
    if (out->cut) {
        texopt_mesh_destroy(out->cut[d]);
        out->cut[d] = NULL;
    }
    const texopt_domain *dom = &model->domains[d];
    for (int i = 0; out->corner_group && i < dom->primitive_count; i++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[i]];
        memset(out->corner_group + 3 * prim->first_triangle, 0, 3 * prim->triangle_count * sizeof *out->corner_group);
    }
}

texopt_status job_output_copy_corners(const texopt_model *model, const job_output *src, job_output *dst, char *err,
                                      size_t err_len)
{
    if (!src->corner_group)
        return TEXOPT_OK;
    texopt_status st = alloc_corners(model, dst, err, err_len);
    if (st == TEXOPT_OK) {
        memcpy(dst->corner_group, src->corner_group, 3 * model->triangle_count * sizeof *dst->corner_group);
        memcpy(dst->corner_uvs, src->corner_uvs, 6 * model->triangle_count * sizeof *dst->corner_uvs);
    }
    return st;
}

static void *copy_floats(const float *p, size_t n, int *ok)
{
    if (!p)
        return NULL;
    float *q = malloc((n ? n : 1) * sizeof *q);
    if (q)
        memcpy(q, p, n * sizeof *q);
    *ok &= q != NULL;
    return q;
}

/* Whether any corner of the output is cut. */
static int has_cut_corner(const texopt_model *model, const job_output *out)
{
    for (size_t c = 0; out->corner_group && c < 3 * model->triangle_count; c++)
        if (out->corner_group[c])
            return 1;
    return 0;
}

texopt_status job_output_view(const texopt_model *model, const job_output *out, texopt_model *view, char *err,
                              size_t err_len)
{
    *view = *model;
    if (out->uvs)
        view->uvs = out->uvs;
    view->document = NULL;
    view->destroy_document = NULL;
    if (!has_cut_corner(model, out))
        return TEXOPT_OK;
    /* the split replaces (frees) these arrays: the view's own copies */
    int ok = 1;
    size_t nv = model->vertex_count, nc = 3 * model->triangle_count;
    view->positions = copy_floats(model->positions, 3 * nv, &ok);
    view->normals = copy_floats(model->normals, 3 * nv, &ok);
    view->uvs = copy_floats(out->uvs ? out->uvs : model->uvs, 2 * nv, &ok);
    view->triangles = malloc((nc ? nc : 1) * sizeof *view->triangles);
    view->file_vertex = model->file_vertex ? malloc((nv ? nv : 1) * sizeof *view->file_vertex) : NULL;
    view->primitives = malloc((size_t)(model->primitive_count ? model->primitive_count : 1) * sizeof *view->primitives);
    ok = ok && view->triangles && (!model->file_vertex || view->file_vertex) && view->primitives;
    texopt_status st = ok ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the cut model");
    if (st == TEXOPT_OK) {
        memcpy(view->triangles, model->triangles, nc * sizeof *view->triangles);
        if (model->file_vertex)
            memcpy(view->file_vertex, model->file_vertex, nv * sizeof *view->file_vertex);
        memcpy(view->primitives, model->primitives, (size_t)model->primitive_count * sizeof *view->primitives);
        st = texopt_model_split_vertices(view, out->corner_group, NULL, err, err_len);
    }
    for (size_t c = 0; st == TEXOPT_OK && c < nc; c++)
        if (out->corner_group[c])
            memcpy(view->uvs + 2 * (size_t)view->triangles[c], out->corner_uvs + 2 * c, 2 * sizeof *view->uvs);
    if (st != TEXOPT_OK)
        job_output_view_free(model, view);
    return st;
}

void job_output_view_free(const texopt_model *model, texopt_model *view)
{
    if (view->positions != model->positions) {
        free(view->positions);
        free(view->normals);
        free(view->uvs);
        free(view->triangles);
        free(view->file_vertex);
        free(view->primitives);
    }
    *view = *model;
}
