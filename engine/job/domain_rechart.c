/* domain_rechart.c - a job's domains on new charts (domain_rechart.h). */
#include "domain_rechart.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model_split.h"
#include "rechart.h"
#include "seam_jump.h"
#include "target_restate.h"

#define RECHART_DENSITY_RATIO 2.0
/* The largest jump (mean over an edge, 1 = full range) of any of a domain's textures across
 * an input seam that a new chart may grow over: about 2.5 of 255 levels, below what the
 * eye separates on a flat colour. */
#define SEAM_JUMP_TOLERANCE 0.01

/* What the new charts' region growing asks of an input seam (rechart.h may_cross). */
typedef struct seam_test {
    const texopt_model *model;
    const texopt_mesh *mesh;
} seam_test;

/* Whether every texture of the domain reads the same across the seam of t and u: a new
 * chart over a seam where the texture jumps would resample the jump on its texel grid. */
static int seam_continuous(const void *context, uint32_t t, uint32_t u)
{
    const seam_test *s = context;
    const texopt_domain *dom = &s->model->domains[s->mesh->domain];
    for (int i = 0; i < dom->image_count; i++)
        if (texopt_seam_jump(s->mesh, &s->model->images[dom->images[i]], t, u) > SEAM_JUMP_TOLERANCE)
            return 0;
    return 1;
}

const texopt_mesh *job_layout_mesh(const job_domain *jd)
{
    return jd->layout ? jd->layout : jd->mesh;
}

texopt_status job_rechart_model(texopt_job *job, char *err, size_t err_len)
{
    texopt_model *model = job->model;
    uint32_t *group = calloc(3 * model->triangle_count + 1, sizeof *group);
    if (!group)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the new charts' corners");
    /* Charts of even input density: a chart starts at its input's mean density, and the
     * allocation caps targets there, so a detailed part (Duck's eyes: 35 times the mean)
     * inside a plain chart would lose its texels. */
    texopt_rechart_options opt = {.method = job->params.parameterizer, .density_ratio = RECHART_DENSITY_RATIO};
    texopt_status st = TEXOPT_OK;
    for (int d = 0; d < model->domain_count && st == TEXOPT_OK; d++) {
        texopt_mesh *mesh = NULL;
        texopt_rechart *r = NULL;
        st = texopt_mesh_create(&mesh, model, d, err, err_len);
        seam_test seams = {model, mesh};
        opt.may_cross = seam_continuous;
        opt.cross_context = &seams;
        if (st == TEXOPT_OK)
            st = texopt_rechart_create(&r, mesh, &opt, err, err_len);
        for (size_t t = 0; st == TEXOPT_OK && t < mesh->triangle_count; t++)
            for (int k = 0; k < 3; k++)
                group[3 * (size_t)mesh->model_triangle[t] + (size_t)k] = r->chart_of[t];
        job->domains[d].rechart = r;
        texopt_mesh_destroy(mesh);
    }
    size_t added = 0;
    if (st == TEXOPT_OK)
        st = texopt_model_split_vertices(model, group, &added, err, err_len);
    job->stats.vertices_split = added;
    free(group);
    return st;
}

/* Per new chart, world units to the input's texels: the input layout's density over the
 * chart's triangles (their texel area over their 3D area), so that a chart keeps the
 * resolution the input gave its part of the surface (the allocation caps targets at the
 * density it starts from); the whole input's density for a chart without texel area, half
 * the frame over the surface for an input without any. */
static void chart_densities(const texopt_mesh *mesh, const texopt_rechart *r, double *density)
{
    size_t n = r->chart_count;
    double *world = calloc(n ? n : 1, sizeof *world), texel = 0, surface = 0;
    for (size_t c = 0; c < n; c++)
        density[c] = 0;
    for (size_t t = 0; world && t < mesh->triangle_count; t++)
        if (!(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV))) {
            density[r->chart_of[t]] += fabs(mesh->area_texel[t]);
            world[r->chart_of[t]] += mesh->area_3d[t];
            texel += fabs(mesh->area_texel[t]);
            surface += mesh->area_3d[t];
        }
    double whole = surface > 0 ? sqrt((texel > 0 ? texel : 0.5 * mesh->width * mesh->height) / surface) : 1.0;
    for (size_t c = 0; c < n; c++)
        density[c] = world && world[c] > 0 && density[c] > 0 ? sqrt(density[c] / world[c]) : whole;
    free(world);
}

/* The charts' boxes (texels, each chart at its density) placed on shelves in a strip about
 * as wide as it ends up tall, 2 texels apart: offset[2 c] per chart. Returns the strip's
 * extent in extent[2]. */
static void place_charts(const texopt_rechart *r, const double *density, double *box, double *offset, double extent[2])
{
    size_t n = r->chart_count;
    for (size_t c = 0; c < 2 * n; c++)
        box[c] = 0;
    for (size_t t = 0; t < r->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) {
                double *b = &box[2 * r->chart_of[t] + (size_t)a];
                *b = fmax(*b, r->corner_uv[6 * t + 2 * (size_t)k + (size_t)a] * density[r->chart_of[t]]);
            }
    double area = 0, gap = 2;
    for (size_t c = 0; c < n; c++)
        area += (box[2 * c] + gap) * (box[2 * c + 1] + gap);
    double width = sqrt(area) * 1.1, x = 0, y = 0, shelf = 0;
    extent[0] = extent[1] = 0;
    for (size_t c = 0; c < n; c++) {
        if (x > 0 && x + box[2 * c] > width) {
            y += shelf + gap;
            x = shelf = 0;
        }
        offset[2 * c] = x;
        offset[2 * c + 1] = y;
        x += box[2 * c] + gap;
        shelf = fmax(shelf, box[2 * c + 1]);
        extent[0] = fmax(extent[0], x);
        extent[1] = fmax(extent[1], y + shelf);
    }
}

/* Whether the input layout is mostly mirrored in texels (v points down in texel space, so
 * most glTF charts are): the new charts then take the same handedness, and most triangles
 * keep the orientation stage 1's targets were found in. */
static int input_mostly_negative(const texopt_mesh *mesh)
{
    double sum = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        sum += mesh->area_texel[t];
    return sum < 0;
}

/* Per model vertex, the new UV (u = x / width) of the charts placed at their input
 * densities, scaled down together to fit the domain's frame. */
static texopt_status new_uvs(const texopt_model *model, const texopt_mesh *mesh, const texopt_rechart *r, float *uvs,
                             char *err, size_t err_len)
{
    size_t n = r->chart_count ? r->chart_count : 1;
    double *box = malloc(2 * n * sizeof *box), *offset = malloc(2 * n * sizeof *offset);
    double *density = malloc(n * sizeof *density), extent[2];
    if (!box || !offset || !density) {
        free(box);
        free(offset);
        free(density);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to place %zu charts", n);
    }
    chart_densities(mesh, r, density);
    place_charts(r, density, box, offset, extent);
    double fit = 1.0;
    if (extent[0] > mesh->width || extent[1] > mesh->height)
        fit = fmin(mesh->width / extent[0], mesh->height / extent[1]);
    int mirror = input_mostly_negative(mesh);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        uint32_t c = r->chart_of[t];
        for (int k = 0; k < 3; k++) {
            uint32_t v = model->triangles[3 * (size_t)mesh->model_triangle[t] + (size_t)k];
            double x = offset[2 * c] + density[c] * r->corner_uv[6 * t + 2 * (size_t)k];
            double y = density[c] * r->corner_uv[6 * t + 2 * (size_t)k + 1];
            y = offset[2 * c + 1] + (mirror ? box[2 * c + 1] - y : y);
            uvs[2 * v] = (float)(x * fit / mesh->width);
            uvs[2 * v + 1] = (float)(y * fit / mesh->height);
        }
    }
    free(box);
    free(offset);
    free(density);
    return TEXOPT_OK;
}

texopt_status job_rechart_layout_mesh(texopt_job *job, int d, char *err, size_t err_len)
{
    job_domain *jd = &job->domains[d];
    float *uvs = job_output_uvs_copy(job->model);
    if (!uvs)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the new charts' UVs");
    texopt_status st = new_uvs(job->model, jd->mesh, jd->rechart, uvs, err, err_len);
    if (st == TEXOPT_OK)
        st = job_output_mesh_with_uvs(job->model, d, uvs, &jd->layout, err, err_len);
    free(uvs);
    return st;
}

void job_rechart_targets(const job_domain *jd, texopt_triangle_target *targets)
{
    texopt_targets_restate(jd->mesh, jd->layout, targets);
}
