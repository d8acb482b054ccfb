/* metric_maps.c - the signal metrics of every map of a domain, weighted and summed (see
 * metric_maps.h). The maps are measured side by side, one per worker at a time (a metric is
 * a few probes per texel of every triangle: seconds per map on the sample assets), and
 * summed afterwards in image order, so the result does not depend on the thread count. */
#include "metric_maps.h"

#include <math.h>
#include <stdlib.h>

#include "lit_weight.h"
#include "parallel.h"

#define MAX_THREADS 64

/* One map's metric, filled by a worker. */
typedef struct map_metric {
    const texopt_image *img; /* NULL: not decoded, skipped */
    double *metric;          /* 3 per triangle */
    double weight;           /* what a lit render shows of a unit change of it */
} map_metric;

typedef struct map_worker {
    const texopt_model *model;
    const texopt_mesh *mesh;
    texopt_signal_probe probe;
    map_metric *maps;
    int map_count, first, step;
} map_worker;

static void *measure_maps(void *arg)
{
    const map_worker *w = arg;
    for (int k = w->first; k < w->map_count; k += w->step)
        if (w->maps[k].img)
            texopt_signal_metric_of(w->model, w->mesh, w->maps[k].img, w->probe, w->maps[k].metric);
    return NULL;
}

/* Whether a binding of the domain's materials reads image `image` as a colour. */
static int read_as_colour(const texopt_model *model, const texopt_domain *dom, int image)
{
    for (int p = 0; p < dom->primitive_count; p++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[p]];
        for (int i = 0; i <= prim->variant_count; i++) {
            int m = texopt_primitive_material(model, prim, i);
            const texopt_material *mat = m >= 0 && m < model->material_count ? &model->materials[m] : NULL;
            for (int b = 0; mat && b < texopt_material_binding_count(mat); b++)
                if (texopt_material_binding(mat, b)->image == image &&
                    texopt_material_binding_kind(mat, b) == TEXOPT_TEXTURE_COLOR)
                    return 1;
        }
    }
    return 0;
}

/* The image's weight (lit_weight.h): its luma's when read as a colour, else the root mean
 * square of the channels the probes read (R, G, B or the one channel). */
static double image_weight(const texopt_model *model, const texopt_domain *dom, int image, const double *weights)
{
    if (!weights)
        return 1;
    const double *w = weights + (size_t)image * TEXOPT_LIT_WEIGHT_STRIDE;
    if (read_as_colour(model, dom, image))
        return w[0];
    int channels = model->images[image].channels >= 3 ? 3 : 1;
    double sum = 0;
    for (int c = 0; c < channels; c++)
        sum += w[1 + c] * w[1 + c];
    return sqrt(sum / channels);
}

texopt_status texopt_metric_targets_every_map(const texopt_model *model, const texopt_mesh *mesh,
                                              texopt_signal_probe probe, double exponent, double lambda_min,
                                              const double *signal_weights, int threads,
                                              texopt_triangle_target *targets, char *err, size_t err_len)
{
    if (!model || !mesh || !probe || !targets || mesh->domain < 0 || mesh->domain >= model->domain_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "metric targets: missing argument");
    const texopt_domain *dom = &model->domains[mesh->domain];
    size_t n = mesh->triangle_count ? mesh->triangle_count : 1;
    int count = dom->image_count, decoded = 0;
    map_metric *maps = calloc(count > 0 ? (size_t)count : 1, sizeof *maps);
    double *sum = calloc(3 * n, sizeof *sum);
    texopt_status st =
        maps && sum ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the maps' metrics");
    for (int k = 0; st == TEXOPT_OK && k < count; k++) {
        const texopt_image *img = &model->images[dom->images[k]];
        maps[k].img = img->pixels ? img : NULL;
        maps[k].weight = image_weight(model, dom, dom->images[k], signal_weights);
        decoded += maps[k].img != NULL;
        if (maps[k].img && !(maps[k].metric = malloc(3 * n * sizeof *maps[k].metric)))
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the maps' metrics");
    }
    if (st == TEXOPT_OK && decoded == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "domain %d has no decoded image to measure", mesh->domain);
    if (st == TEXOPT_OK) {
        int workers = threads < 1 ? 1 : (threads > MAX_THREADS ? MAX_THREADS : threads);
        workers = workers < decoded ? workers : decoded;
        map_worker w[MAX_THREADS];
        for (int k = 0; k < workers; k++)
            w[k] = (map_worker){.model = model,
                                .mesh = mesh,
                                .probe = probe,
                                .maps = maps,
                                .map_count = count,
                                .first = k,
                                .step = workers};
        texopt_parallel_run(measure_maps, w, sizeof *w, workers);
        /* The metrics are squared signal derivatives: a signal scaled by w scales its metric
         * by w^2, and the maps add as the channels of one map do. */
        for (int k = 0; k < count; k++)
            for (size_t i = 0; maps[k].img && i < 3 * mesh->triangle_count; i++)
                sum[i] += maps[k].weight * maps[k].weight * maps[k].metric[i];
        st = texopt_targets_from_metric(mesh, sum, exponent, lambda_min, targets, err, err_len);
    }
    for (int k = 0; maps && k < count; k++)
        free(maps[k].metric);
    free(maps);
    free(sum);
    return st;
}
