/* budget.c - scale + pack + measure loops of the two budgets (see budget.h). */
#include "budget.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "coverage.h"

#define MAX_SIDE 16384
#define COST_TOLERANCE 0.005
#define COST_ROUNDS 6
#define BISECTION_STEPS 14
#define SMALL_ATLAS_CHARTS 64 /* up to this many charts, more widths are tried */

static int round_up4(double x)
{
    double v = 4.0 * ceil(x / 4.0);
    return v < 4 ? 4 : (v > MAX_SIDE ? MAX_SIDE + 1 : (int)v);
}

static double layout_area(const texopt_mesh *mesh, const double *texel)
{
    double area = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (mesh->flags[t] & TEXOPT_TRI_DEGENERATE_UV)
            continue;
        const uint32_t *v = mesh->triangle + 3 * t;
        const double *a = texel + 2 * v[0], *b = texel + 2 * v[1], *c = texel + 2 * v[2];
        area += 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
    }
    return area;
}

static void scale_layout(const double *in, double s, double *out, size_t vertices)
{
    for (size_t i = 0; i < 2 * vertices; i++)
        out[i] = in[i] * s;
}

static texopt_status measure_cost(const texopt_mesh *mesh, const double *texel, int w, int h,
                                  double *cost, char *err, size_t err_len)
{
    texopt_coverage_options o = {0};
    o.texel = texel;
    o.width = w;
    o.height = h;
    o.use_wraps = 1;
    o.wrap_s = o.wrap_t = TEXOPT_WRAP_CLAMP;
    texopt_coverage c;
    texopt_status st = texopt_coverage_measure(mesh, &o, &c, err, err_len);
    if (st == TEXOPT_OK)
        *cost = (double)c.covered_texels;
    return st;
}

typedef struct work {
    const texopt_mesh *mesh;
    const double *texel;
    const texopt_pack_options *pack;
    double *scaled, *packed;
    int packings;
    int pack_order; /* texopt_pack_options.order of the next pack */
    const texopt_monitor *monitor;
} work;

/* Packs the layout scaled by s into width columns (height 0: as tall as needed) or into
 * width x height; *fits says whether it fit, *out_h the height used. */
static texopt_status pack_at(work *w, double s, int width, int height, int *fits, int *out_h,
                             char *err, size_t err_len)
{
    if (texopt_monitor_canceled(w->monitor))
        return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "packing canceled");
    scale_layout(w->texel, s, w->scaled, w->mesh->vertex_count);
    texopt_pack_options opt = *w->pack;
    opt.order = w->pack_order;
    texopt_pack_result r;
    texopt_status st = texopt_pack_charts(w->mesh, w->scaled, width, height, &opt, w->packed, &r,
                                          fits, err, err_len);
    w->packings++;
    if (st == TEXOPT_OK) {
        *out_h = r.height;
        if (height == 0 && r.height > MAX_SIDE)
            *fits = 0;
        texopt_pack_result_destroy(&r);
    }
    return st;
}

/* The width and placement order (of a few widths around the estimate, both orders for
 * small atlases) whose "as tall as needed" packing has the fewest texels; its positions go
 * to texel_out and its order stays in w->pack_order for the later rounds. */
static texopt_status best_width(work *w, double s, double area, double aspect, double *texel_out,
                                int *bw, int *bh, char *err, size_t err_len)
{
    double base = sqrt(area * s * s / 0.7 * aspect);
    long long best = -1;
    int small = w->mesh->chart_count <= SMALL_ATLAS_CHARTS;
    int tries = small ? 15 : 5, orders = small ? 2 : 1, best_order = 0;
    for (int order = 0; order < orders; order++)
        for (int i = 0; i < tries; i++) {
            int width = round_up4(base * (0.75 + 0.6 * i / (tries - 1)));
            if (width > MAX_SIDE)
                continue;
            int fits, h;
            w->pack_order = order;
            texopt_status st = pack_at(w, s, width, 0, &fits, &h, err, err_len);
            if (st != TEXOPT_OK)
                return st;
            if (fits && (best < 0 || (long long)width * h < best)) {
                best = (long long)width * h;
                *bw = width;
                *bh = h;
                best_order = order;
                memcpy(texel_out, w->packed, sizeof(double) * 2 * w->mesh->vertex_count);
            }
        }
    w->pack_order = best_order;
    if (best < 0)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                           "budget: the layout needs a texture larger than %d texels a side", MAX_SIDE);
    return TEXOPT_OK;
}

/* Cost depends on scale squared but also on how the scaled charts fall on the texel grid,
 * so each round repacks at the corrected scale and measures again; the round closest to the
 * target wins. */
static texopt_status fit_relative_cost(work *w, const texopt_budget_request *req, double area,
                                       double *texel_out, texopt_budget_result *res, char *err,
                                       size_t err_len)
{
    double target = req->relative_cost * req->input_cost;
    double s = sqrt(target / area);
    double aspect = (double)req->input_width / req->input_height;
    int width = 0, height = 0;
    texopt_status st = best_width(w, s, area, aspect, texel_out, &width, &height, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double cost = 0;
    st = measure_cost(w->mesh, texel_out, width, height, &cost, err, err_len);
    double best_miss = fabs(cost / target - 1);
    res->width = width;
    res->height = height;
    res->scale = s;
    res->cost = cost;
    for (int round = 0; st == TEXOPT_OK && round < COST_ROUNDS && best_miss > COST_TOLERANCE && cost > 0; round++) {
        double k = sqrt(target / cost);
        int fits, h, next_w = round_up4(width * k);
        if (next_w > MAX_SIDE)
            return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                               "budget: the layout needs a texture wider than %d texels", MAX_SIDE);
        st = pack_at(w, s * k, next_w, 0, &fits, &h, err, err_len);
        if (st == TEXOPT_OK && !fits)
            return texopt_fail(err, err_len, TEXOPT_E_LIMIT,
                               "budget: the layout needs a texture taller than %d texels", MAX_SIDE);
        if (st == TEXOPT_OK)
            st = measure_cost(w->mesh, w->packed, next_w, h, &cost, err, err_len);
        if (st != TEXOPT_OK)
            break;
        s *= k;
        width = next_w;
        if (fabs(cost / target - 1) < best_miss) {
            best_miss = fabs(cost / target - 1);
            res->width = next_w;
            res->height = h;
            res->scale = s;
            res->cost = cost;
            memcpy(texel_out, w->packed, sizeof(double) * 2 * w->mesh->vertex_count);
        }
    }
    return st;
}

static texopt_status fit_texture_size(work *w, const texopt_budget_request *req, double area,
                                      double *texel_out, texopt_budget_result *res, char *err,
                                      size_t err_len)
{
    int width = req->texture_width, height = req->texture_height;
    double hi = sqrt((double)width * height / area), lo = 0, s = hi * sqrt(0.75);
    texopt_status st = TEXOPT_OK;
    for (int i = 0; i < BISECTION_STEPS + 20 && st == TEXOPT_OK; i++) {
        if (lo > 0 && (hi - lo) <= 0.002 * hi)
            break;
        int fits, h;
        st = pack_at(w, s, width, height, &fits, &h, err, err_len);
        if (st != TEXOPT_OK)
            break;
        if (fits) {
            lo = s;
            memcpy(texel_out, w->packed, sizeof(double) * 2 * w->mesh->vertex_count);
        } else {
            hi = s;
        }
        s = lo > 0 ? 0.5 * (lo + hi) : 0.5 * hi;
        if (lo == 0 && hi < 1e-6)
            break;
    }
    if (st != TEXOPT_OK)
        return st;
    if (!(lo > 0))
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "budget: the charts do not fit in %dx%d at any scale",
                           width, height);
    res->width = width;
    res->height = height;
    res->scale = lo;
    return measure_cost(w->mesh, texel_out, width, height, &res->cost, err, err_len);
}

static texopt_status check_request(const texopt_budget_request *req, double area, char *err, size_t err_len)
{
    if (!(area > 0) || !isfinite(area))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: the layout has no area");
    if (!(req->input_cost > 0) || req->input_width < 1 || req->input_height < 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: the input cost and frame must be positive");
    if (req->kind == TEXOPT_BUDGET_RELATIVE_COST && !(req->relative_cost > 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: relative cost must be > 0");
    if (req->kind == TEXOPT_BUDGET_TEXTURE_SIZE &&
        (req->texture_width < 1 || req->texture_height < 1 || req->texture_width > MAX_SIDE ||
         req->texture_height > MAX_SIDE))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: texture size %dx%d is out of range",
                           req->texture_width, req->texture_height);
    if (req->kind != TEXOPT_BUDGET_RELATIVE_COST && req->kind != TEXOPT_BUDGET_TEXTURE_SIZE)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "budget: only relative cost and texture size are supported");
    return TEXOPT_OK;
}

texopt_status texopt_budget_fit(const texopt_mesh *mesh, const double *texel,
                                const texopt_budget_request *req, double *texel_out,
                                texopt_budget_result *res, char *err, size_t err_len)
{
    memset(res, 0, sizeof *res);
    double area = layout_area(mesh, texel);
    texopt_status st = check_request(req, area, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    work w = {mesh, texel, &req->pack, NULL, NULL, 0, req->pack.order, req->monitor};
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    w.scaled = malloc(n * sizeof(double));
    w.packed = malloc(n * sizeof(double));
    if (!w.scaled || !w.packed)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the budget search");
    else if (req->kind == TEXOPT_BUDGET_RELATIVE_COST)
        st = fit_relative_cost(&w, req, area, texel_out, res, err, err_len);
    else
        st = fit_texture_size(&w, req, area, texel_out, res, err, err_len);
    free(w.scaled);
    free(w.packed);
    if (st != TEXOPT_OK)
        return st;
    res->packings = w.packings;
    res->relative_cost = res->cost / req->input_cost;
    res->packing_efficiency = res->cost / ((double)res->width * res->height);
    return TEXOPT_OK;
}
