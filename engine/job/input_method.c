/* input_method.c - method "input": a domain's input layout kept, its images resized
 * (input_method.h). */
#include "input_method.h"

#include <math.h>
#include <stdlib.h>

#include "bake_pool.h"
#include "lanczos.h"

/* Cost of the unchanged layout in its input frame and in the resized frame (the same UVs
 * seen on the new texel grid), with the domain's wrap modes. */
static texopt_status input_layout_costs(const texopt_mesh *mesh, int ow, int oh, texopt_domain_stats *ds, char *err,
                                        size_t err_len)
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

void job_input_frame(const texopt_domain *dom, const texopt_params *params, int *ow, int *oh)
{
    if (params->budget == TEXOPT_BUDGET_TEXTURE_SIZE) {
        *ow = params->texture_width;
        *oh = params->texture_height;
    } else {
        double s = sqrt(params->relative_cost);
        *ow = job_scaled_side(dom->width, s);
        *oh = job_scaled_side(dom->height, s);
    }
}

texopt_status job_run_input_method(texopt_job *job, const layout_run *run, int d, double from, double to, char *err,
                                   size_t err_len)
{
    const texopt_model *model = job->model;
    const texopt_mesh *mesh = job->domains[d].mesh;
    const texopt_params *params = run->p;
    job_output *out = run->out;
    texopt_domain_stats *ds = &run->domains[d];
    job_monitor *jm = &job->jm;
    const texopt_domain *dom = &model->domains[mesh->domain];
    int ow, oh;
    job_input_frame(dom, params, &ow, &oh);
    ds->output_width = ow;
    ds->output_height = oh;
    double t0 = job_now_seconds();
    for (int i = 0; i < dom->image_count; i++) {
        int im = dom->images[i];
        const texopt_image *src = &model->images[im];
        texopt_image_stats *is = &ds->images[i];
        job_stage(jm, "bake", from + (to - from) * i / dom->image_count,
                  from + (to - from) * (i + 1) / dom->image_count);
        texopt_status st = job_check_cancel(jm, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        int w, h;
        job_image_output_size(src, dom, ow, oh, &w, &h);
        is->output_width = w;
        is->output_height = h;
        if (w == src->width && h == src->height)
            continue; /* the identity: keep the file's own bytes */
        if (!src->pixels)
            return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "image %d (%s) was not decoded", im,
                               is->name ? is->name : "unnamed");
        st = texopt_image_create(&out->images[im], w, h, src->channels, err, err_len);
        if (st == TEXOPT_OK)
            st = texopt_lanczos_resize(src, &out->images[im], job_worker_threads(params), err, err_len);
        if (st != TEXOPT_OK)
            return st;
        out->edit_images[im] = &out->images[im];
        is->rewritten = 1;
    }
    ds->seconds_bake = job_now_seconds() - t0;
    return input_layout_costs(mesh, ow, oh, ds, err, err_len);
}

/* The whole tiles (per axis) that move the input layout into the frame [0, 1] x [0, 1]:
 * *tile the floor of its smallest UV. 0 when the layout does not lie in one tile, or lies
 * in another than the first where the axis does not REPEAT (a mirrored or clamped read
 * there is not the frame's). */
static int layout_tile(const texopt_mesh *mesh, const texopt_domain *dom, double tile[2])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, size[2] = {mesh->width, mesh->height};
    for (size_t v = 0; v < mesh->vertex_count; v++)
        for (int a = 0; a < 2; a++) {
            double uv = mesh->texel[2 * v + a] / size[a];
            lo[a] = fmin(lo[a], uv);
            hi[a] = fmax(hi[a], uv);
        }
    texopt_wrap wrap[2] = {dom->wrap_s, dom->wrap_t};
    for (int a = 0; a < 2; a++) {
        tile[a] = floor(lo[a]);
        if (!(hi[a] <= tile[a] + 1) || (tile[a] != 0 && wrap[a] != TEXOPT_WRAP_REPEAT))
            return 0;
    }
    return mesh->vertex_count > 0;
}

texopt_status job_refit_input_layout(texopt_job *job, const layout_run *run, int d, double from, double to, char *err,
                                     size_t err_len)
{
    const texopt_mesh *mesh = job->domains[d].mesh;
    const texopt_domain *dom = &job->model->domains[mesh->domain];
    texopt_domain_stats *ds = &run->domains[d];
    double tile[2];
    if (!layout_tile(mesh, dom, tile))
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                           "domain %d: its input layout does not lie in one tile of its texture", d);
    int size[2];
    job_input_frame(dom, run->p, &size[0], &size[1]);
    ds->output_width = size[0];
    ds->output_height = size[1];
    double *packed = malloc(sizeof(double) * 2 * (mesh->vertex_count ? mesh->vertex_count : 1));
    if (!packed)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the refitted layout");
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        packed[2 * v] = (mesh->texel[2 * v] / mesh->width - tile[0]) * size[0];
        packed[2 * v + 1] = (mesh->texel[2 * v + 1] / mesh->height - tile[1]) * size[1];
    }
    double t0 = job_now_seconds();
    texopt_status st = job_rebake_domain(job, run, d, NULL, packed, size, from, to, err, err_len);
    ds->seconds_bake = job_now_seconds() - t0;
    free(packed);
    return st == TEXOPT_OK ? input_layout_costs(mesh, size[0], size[1], ds, err, err_len) : st;
}
