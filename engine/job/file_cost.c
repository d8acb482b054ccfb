/* file_cost.c - the costs of a written model file; see file_cost.h. */
#include "file_cost.h"

#include <sys/stat.h>
#include <time.h>

#include "atlas_quality.h"
#include "coverage.h"
#include "distortion.h"
#include "gltf_io.h"
#include "mesh.h"

void texopt_file_cost_of_model(const texopt_model *model, texopt_file_cost *out)
{
    out->texture_pixels = out->texture_bytes = 0;
    for (int i = 0; i < model->image_count; i++) {
        out->texture_pixels += (uint64_t)model->images[i].width * (uint64_t)model->images[i].height;
        out->texture_bytes += texopt_model_image_bytes(model, i);
    }
}

/* Domain d of the file measured as info.c does: its mesh, coverage.h and atlas_quality.h on
 * its own layout, and for a domain whose distortion the job reported, that layout's
 * distortion (the file may hold the input's layout resized, and its UVs are floats). */
static texopt_status record_domain(const texopt_model *model, int d, texopt_domain_stats *ds, char *err, size_t err_len)
{
    texopt_mesh *mesh = NULL;
    texopt_coverage cov;
    texopt_status st = texopt_mesh_create(&mesh, model, d, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_coverage_measure(mesh, NULL, &cov, err, err_len);
    texopt_distortion out;
    if (st == TEXOPT_OK && ds->has_distortion && texopt_distortion_measure(mesh, NULL, &out, NULL, 0) == TEXOPT_OK) {
        ds->distortion_out = out;
        ds->distortion_output = out.symmetric_dirichlet;
    }
    if (st == TEXOPT_OK)
        ds->has_atlas_quality = texopt_atlas_quality_measure(mesh, NULL, &ds->atlas_quality, NULL, 0) == TEXOPT_OK;
    texopt_mesh_destroy(mesh);
    if (st != TEXOPT_OK)
        return st;
    ds->cost_output = (double)cov.covered_texels;
    ds->relative_cost = ds->cost_output / ds->cost_input;
    ds->packing_efficiency = cov.packing_efficiency;
    return TEXOPT_OK;
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

texopt_status texopt_file_cost_record(const char *path, texopt_job_stats *stats, char *err, size_t err_len)
{
    double t0 = seconds_now();
    texopt_model *model = NULL;
    texopt_load_options opt = {.skip_images = 1};
    texopt_status st = texopt_model_load(&model, path, &opt, err, err_len);
    if (st == TEXOPT_OK && model->domain_count != stats->domain_count)
        st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "the written file has %d texture domains, the job %d",
                         model->domain_count, stats->domain_count);
    for (int d = 0; st == TEXOPT_OK && d < stats->domain_count; d++)
        if (stats->domains[d].cost_input > 0)
            st = record_domain(model, d, &stats->domains[d], err, err_len);
    if (st == TEXOPT_OK) {
        texopt_file_cost fc;
        texopt_file_cost_of_model(model, &fc);
        struct stat sb;
        stats->has_file_cost = 1;
        stats->file_texture_pixels = fc.texture_pixels;
        stats->file_texture_bytes = fc.texture_bytes;
        stats->file_bytes = stat(path, &sb) == 0 ? (uint64_t)sb.st_size : 0;
        stats->seconds_file_cost = seconds_now() - t0;
    }
    texopt_model_destroy(model);
    return st;
}
