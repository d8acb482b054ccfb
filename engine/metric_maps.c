/* metric_maps.c - per-map signal-metric targets and the most demanding per triangle (see
 * metric_maps.h). The maps are measured side by side, one per worker at a time (a metric is
 * a few probes per texel of every triangle: seconds per map on the sample assets), and
 * combined afterwards in image order, so the result does not depend on the thread count. */
#include "metric_maps.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"

#define MAX_THREADS 64

/* One map's targets, filled by a worker. */
typedef struct map_result {
    const texopt_image *img; /* NULL: not decoded, skipped */
    texopt_triangle_target *targets;
    int flat;
    texopt_status status;
    char err[256];
} map_result;

typedef struct map_worker {
    const texopt_model *model;
    const texopt_mesh *mesh;
    texopt_signal_probe probe;
    double exponent, lambda_min;
    map_result *maps;
    int map_count, first, step;
} map_worker;

static double target_area(const texopt_triangle_target *g)
{
    return g->lambda1 * g->lambda2;
}

static void measure_map(const map_worker *w, double *metric, map_result *r)
{
    r->status = texopt_signal_metric_of(w->model, w->mesh, r->img, w->probe, metric);
    if (r->status == TEXOPT_OK)
        r->status = texopt_metric_flat(w->mesh, metric, w->exponent, &r->flat, r->err, sizeof r->err);
    if (r->status == TEXOPT_OK)
        r->status = texopt_targets_from_metric(w->mesh, metric, w->exponent, w->lambda_min, r->targets, r->err,
                                               sizeof r->err);
}

static void *measure_maps(void *arg)
{
    const map_worker *w = arg;
    double *metric = malloc(3 * (w->mesh->triangle_count ? w->mesh->triangle_count : 1) * sizeof *metric);
    for (int k = w->first; k < w->map_count; k += w->step) {
        map_result *r = &w->maps[k];
        if (!r->img)
            continue;
        if (metric)
            measure_map(w, metric, r);
        else
            r->status = texopt_fail(r->err, sizeof r->err, TEXOPT_E_NOMEM, "no memory for a map's metric");
    }
    free(metric);
    return NULL;
}

/* Each triangle takes the most demanding map's target; flat maps ask nothing unless all are. */
static void combine(const map_result *maps, int count, size_t n, texopt_triangle_target *targets)
{
    int measured = 0, any_detail = 0;
    for (int k = 0; k < count; k++) {
        const map_result *r = &maps[k];
        if (!r->img || (r->flat && measured))
            continue;
        for (size_t t = 0; t < n; t++)
            if (!measured || (!any_detail && !r->flat) || target_area(&r->targets[t]) > target_area(&targets[t]))
                targets[t] = r->targets[t];
        any_detail |= !r->flat;
        measured = 1;
    }
}

texopt_status texopt_metric_targets_every_map(const texopt_model *model, const texopt_mesh *mesh,
                                              texopt_signal_probe probe, double exponent, double lambda_min,
                                              int threads, texopt_triangle_target *targets, char *err,
                                              size_t err_len)
{
    if (!model || !mesh || !probe || !targets || mesh->domain < 0 || mesh->domain >= model->domain_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "metric targets: missing argument");
    const texopt_domain *dom = &model->domains[mesh->domain];
    size_t n = mesh->triangle_count ? mesh->triangle_count : 1;
    int count = dom->image_count, decoded = 0;
    map_result *maps = calloc(count > 0 ? (size_t)count : 1, sizeof *maps);
    texopt_status st = maps ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the maps' metrics");
    for (int k = 0; st == TEXOPT_OK && k < count; k++) {
        const texopt_image *img = &model->images[dom->images[k]];
        maps[k].img = img->pixels ? img : NULL;
        decoded += maps[k].img != NULL;
        if (maps[k].img && !(maps[k].targets = malloc(n * sizeof *maps[k].targets)))
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the maps' targets");
    }
    if (st == TEXOPT_OK && decoded == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "domain %d has no decoded image to measure", mesh->domain);
    if (st == TEXOPT_OK) {
        int workers = threads < 1 ? 1 : (threads > MAX_THREADS ? MAX_THREADS : threads);
        workers = workers < decoded ? workers : decoded;
        map_worker w[MAX_THREADS];
        for (int k = 0; k < workers; k++)
            w[k] = (map_worker){.model = model, .mesh = mesh, .probe = probe, .exponent = exponent,
                                .lambda_min = lambda_min, .maps = maps, .map_count = count, .first = k,
                                .step = workers};
        texopt_parallel_run(measure_maps, w, sizeof *w, workers);
        for (int k = 0; k < count && st == TEXOPT_OK; k++)
            if (maps[k].img && maps[k].status != TEXOPT_OK)
                st = texopt_fail(err, err_len, maps[k].status, "%s", maps[k].err);
    }
    if (st == TEXOPT_OK)
        combine(maps, count, mesh->triangle_count, targets);
    for (int k = 0; maps && k < count; k++)
        free(maps[k].targets);
    free(maps);
    return st;
}
