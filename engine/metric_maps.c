/* metric_maps.c - per-map signal-metric targets and the most demanding per triangle (see
 * metric_maps.h). */
#include "metric_maps.h"

#include <stdlib.h>

static double target_area(const texopt_triangle_target *g)
{
    return g->lambda1 * g->lambda2;
}

/* Targets of one image into mine; *flat when its metric is flat over the mesh. */
static texopt_status map_targets(const texopt_model *model, const texopt_mesh *mesh, const texopt_image *img,
                                 texopt_signal_probe probe, double exponent, double lambda_min, double *metric,
                                 texopt_triangle_target *mine, int *flat, char *err, size_t err_len)
{
    texopt_status st = texopt_signal_metric_of(model, mesh, img, probe, metric);
    if (st == TEXOPT_OK)
        st = texopt_metric_flat(mesh, metric, exponent, flat, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_targets_from_metric(mesh, metric, exponent, lambda_min, mine, err, err_len);
    return st;
}

texopt_status texopt_metric_targets_every_map(const texopt_model *model, const texopt_mesh *mesh,
                                              texopt_signal_probe probe, double exponent, double lambda_min,
                                              texopt_triangle_target *targets, char *err, size_t err_len)
{
    if (!model || !mesh || !probe || !targets || mesh->domain < 0 || mesh->domain >= model->domain_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "metric targets: missing argument");
    size_t n = mesh->triangle_count ? mesh->triangle_count : 1;
    const texopt_domain *dom = &model->domains[mesh->domain];
    double *metric = malloc(3 * n * sizeof *metric);
    texopt_triangle_target *mine = malloc(n * sizeof *mine);
    texopt_status st = metric && mine ? TEXOPT_OK
                                      : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the maps' metrics");
    int measured = 0, any_detail = 0;
    for (int k = 0; st == TEXOPT_OK && k < dom->image_count; k++) {
        const texopt_image *img = &model->images[dom->images[k]];
        int flat = 1;
        if (!img->pixels)
            continue;
        st = map_targets(model, mesh, img, probe, exponent, lambda_min, metric, mine, &flat, err, err_len);
        if (st != TEXOPT_OK || (flat && measured))
            continue;
        /* The first map measured fills targets (all lambda 1 when flat); a flat map after it
         * adds nothing; a map with detail replaces flat targets or raises the others'. */
        for (size_t t = 0; t < mesh->triangle_count; t++)
            if (!measured || (!any_detail && !flat) || target_area(&mine[t]) > target_area(&targets[t]))
                targets[t] = mine[t];
        any_detail |= !flat;
        measured = 1;
    }
    if (st == TEXOPT_OK && !measured)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "domain %d has no decoded image to measure",
                         mesh->domain);
    free(metric);
    free(mine);
    return st;
}
