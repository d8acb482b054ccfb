/* layout_check.c - the validity check of a new layout; see layout_check.h. */
#include "layout_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "texel_share.h"
#include "vec2.h"

const char *texopt_layout_failure_name(texopt_layout_failure failure)
{
    switch (failure) {
    case TEXOPT_LAYOUT_OVERLAP: return "overlap";
    case TEXOPT_LAYOUT_FOLDOVER: return "foldover";
    case TEXOPT_LAYOUT_AREA: return "area";
    default: return NULL;
    }
}

static double texel_area(const texopt_mesh *mesh, const double *texel, size_t t)
{
    const uint32_t *v = mesh->triangle + 3 * t;
    const double *a = texel + 2 * (size_t)v[0], *b = texel + 2 * (size_t)v[1], *c = texel + 2 * (size_t)v[2];
    if (texopt_texel_triangle_degenerate(a, b, c))
        return 0.0;
    return texopt_signed_area(a, b, c);
}

/* Counts one offending triangle of check `kind`, listing it when that check is the one that
 * failed first. */
static void offend(texopt_layout_check *out, texopt_layout_failure kind, size_t *count, uint32_t model_triangle)
{
    (*count)++;
    if (out->failed == TEXOPT_LAYOUT_PASSED)
        out->failed = kind;
    if (out->failed == kind && out->listed < TEXOPT_LAYOUT_CHECK_LISTED)
        out->triangles[out->listed++] = model_triangle;
}

/* Frames past this many texels get no overlap check (4 bytes a texel). */
#define OWNER_MAX_TEXELS (1u << 26)
#define NO_OWNER UINT32_MAX

/* Whether texel centre (x, y) lies strictly inside triangle (a, b, c) of either orientation
 * (a centre on an edge belongs to neither, so that charts that touch never overlap). */
static int centre_inside(const double *a, const double *b, const double *c, double x, double y)
{
    double d0 = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
    double d1 = (c[0] - b[0]) * (y - b[1]) - (c[1] - b[1]) * (x - b[0]);
    double d2 = (a[0] - c[0]) * (y - c[1]) - (a[1] - c[1]) * (x - c[0]);
    const double e = 1e-9;
    return (d0 > e && d1 > e && d2 > e) || (d0 < -e && d1 < -e && d2 < -e);
}

/* v within [0, limit], as an int: a texel position far outside the frame (a file's UVs may
 * be anything finite) must not reach the conversion, whose overflow is undefined. */
static int clamp_to_frame(double v, int limit)
{
    return v <= 0 ? 0 : v >= limit ? limit : (int)v;
}

/* The rasterised ownership of texel centres: per texel the last triangle whose interior
 * holds its centre. */
typedef struct texel_owners {
    const texopt_mesh *mesh;
    const double *texel;
    int width, height;
    const uint32_t *group_of_chart; /* NULL: every chart its own group */
    uint32_t *owner;
} texel_owners;

enum { CLASH_GROUPS = 1, CLASH_WITHIN = 2 };

static uint32_t group_of(const texel_owners *o, uint32_t t)
{
    uint32_t chart = o->mesh->chart_of[t];
    return o->group_of_chart ? o->group_of_chart[chart] : chart;
}

/* What a centre already owned by triangle `had` means for triangle t: another sharing
 * group's texel, or a texel of its own chart under the same orientation (the chart over
 * itself; the two sides of a fold have opposite orientations and may share). */
static int clash_kind(const texel_owners *o, uint32_t t, uint32_t had, double area_t)
{
    if (group_of(o, t) != group_of(o, had))
        return CLASH_GROUPS;
    if (o->mesh->chart_of[t] == o->mesh->chart_of[had] && (texel_area(o->mesh, o->texel, had) > 0) == (area_t > 0))
        return CLASH_WITHIN;
    return 0;
}

/* Claims the texel centres inside triangle t; returns the CLASH_ bits of what it found
 * there, and adds the centres its own chart already held to *within_texels. */
static int claim_texels(const texel_owners *o, uint32_t t, size_t *within_texels)
{
    const uint32_t *v = o->mesh->triangle + 3 * (size_t)t;
    const double *a = o->texel + 2 * (size_t)v[0], *b = o->texel + 2 * (size_t)v[1], *c = o->texel + 2 * (size_t)v[2];
    double area = texel_area(o->mesh, o->texel, t);
    int x0 = clamp_to_frame(floor(fmin(a[0], fmin(b[0], c[0]))), o->width);
    int x1 = clamp_to_frame(ceil(fmax(a[0], fmax(b[0], c[0]))), o->width);
    int y0 = clamp_to_frame(floor(fmin(a[1], fmin(b[1], c[1]))), o->height);
    int y1 = clamp_to_frame(ceil(fmax(a[1], fmax(b[1], c[1]))), o->height);
    int clash = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            if (!centre_inside(a, b, c, x + 0.5, y + 0.5))
                continue;
            uint32_t *had = &o->owner[(size_t)y * (size_t)o->width + (size_t)x];
            int kind = *had == NO_OWNER ? 0 : clash_kind(o, t, *had, area);
            *within_texels += kind == CLASH_WITHIN;
            clash |= kind;
            *had = t;
        }
    return clash;
}

/* Per chart, 1 when it covers a texel centre twice with one orientation in the layout
 * texel, rastered over its whole extent (a file's UVs may leave the frame: a chart over
 * itself through REPEAT counts); NULL on no memory or an extent too large to raster. */
static uint8_t *charts_over_themselves(const texopt_mesh *m, const double *texel)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t k = 0; k < 3 * m->triangle_count; k++)
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], texel[2 * (size_t)m->triangle[k] + d]);
            hi[d] = fmax(hi[d], texel[2 * (size_t)m->triangle[k] + d]);
        }
    double width = ceil(hi[0]) - floor(lo[0]), height = ceil(hi[1]) - floor(lo[1]);
    if (!(width > 0 && height > 0 && width * height <= OWNER_MAX_TEXELS))
        return NULL;
    double *shifted = malloc(2 * (m->vertex_count ? m->vertex_count : 1) * sizeof *shifted);
    texel_owners o = {m, shifted, (int)width, (int)height, NULL, malloc((size_t)(width * height) * sizeof(uint32_t))};
    uint8_t *over = calloc(m->chart_count ? m->chart_count : 1, 1);
    if (!shifted || !o.owner || !over) {
        free(shifted);
        free(o.owner);
        free(over);
        return NULL;
    }
    for (size_t v = 0; v < m->vertex_count; v++) { /* whole texels: the centres stay centres */
        shifted[2 * v] = texel[2 * v] - floor(lo[0]);
        shifted[2 * v + 1] = texel[2 * v + 1] - floor(lo[1]);
    }
    memset(o.owner, 0xff, (size_t)(width * height) * sizeof *o.owner);
    size_t within = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        if (texel_area(m, shifted, t) != 0.0 && (claim_texels(&o, (uint32_t)t, &within) & CLASH_WITHIN))
            over[m->chart_of[t]] = 1;
    free(shifted);
    free(o.owner);
    return over;
}

/* Triangles covering a texel of another sharing group (group_of_chart) in the new layout,
 * and those covering a texel of their own chart again where the input did not (own_layout:
 * texel is the input's layout, and every chart over itself counts). */
static texopt_status check_overlaps(const texopt_mesh *m, const double *texel, int width, int height,
                                    const uint32_t *group_of_chart, int own_layout, texopt_layout_check *out, char *err,
                                    size_t err_len)
{
    if ((uint64_t)width * (uint64_t)height > OWNER_MAX_TEXELS || width <= 0 || height <= 0)
        return TEXOPT_OK;
    uint8_t *over_in_input = own_layout ? NULL : charts_over_themselves(m, m->texel);
    texel_owners o = {m,      texel,          width,
                      height, group_of_chart, malloc((size_t)width * (size_t)height * sizeof(uint32_t))};
    if (!o.owner) {
        free(over_in_input);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "layout check: no memory for a %dx%d frame", width, height);
    }
    memset(o.owner, 0xff, (size_t)width * (size_t)height * sizeof *o.owner);
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (texel_area(m, texel, t) == 0.0)
            continue;
        size_t within = 0;
        int clash = claim_texels(&o, (uint32_t)t, &within);
        if (clash & CLASH_GROUPS)
            offend(out, TEXOPT_LAYOUT_OVERLAP, &out->overlapping, m->model_triangle[t]);
        if ((clash & CLASH_WITHIN) && !(over_in_input && over_in_input[m->chart_of[t]])) {
            if (out->overlapping_within++ == 0)
                out->first_within = m->model_triangle[t];
            out->overlap_within_texels += within;
        }
    }
    free(over_in_input);
    free(o.owner);
    return TEXOPT_OK;
}

/* The area scale that takes the targets' areas to the layout's total. */
static double target_scale(const texopt_mesh *m, const double *texel, const texopt_triangle_target *targets)
{
    double want = 0, have = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        want += targets[t].lambda1 * targets[t].lambda2 * fabs(m->area_texel[t]) *
                !(m->flags[t] & TEXOPT_TRI_DEGENERATE_UV);
        have += fabs(texel_area(m, texel, t));
    }
    return want > 0 ? have / want : 0;
}

static texopt_status run_checks(const texopt_mesh *input, const double *texel, int width, int height,
                                const uint32_t *group_of_chart, const texopt_triangle_target *targets, int own_layout,
                                texopt_layout_check *out, char *err, size_t err_len)
{
    memset(out, 0, sizeof *out);
    texopt_status st = check_overlaps(input, texel, width, height, group_of_chart, own_layout, out, err, err_len);
    double scale = st == TEXOPT_OK && targets ? target_scale(input, texel, targets) : 0;
    double total = texopt_layout_area(input, texel, NULL), total_in = texopt_layout_area(input, input->texel, NULL);
    double mean = input->triangle_count ? total / (double)input->triangle_count : 0;
    double uniform_scale = total_in > 0 ? total / total_in : 0;
    for (size_t t = 0; st == TEXOPT_OK && t < input->triangle_count; t++) {
        uint32_t mt = input->model_triangle[t];
        double a = texel_area(input, texel, t), a_in = input->area_texel[t];
        int had_area = !(input->flags[t] & (TEXOPT_TRI_DEGENERATE_UV | TEXOPT_TRI_FLIPPED));
        if (had_area && a != 0.0 && (a < 0) != (a_in < 0))
            offend(out, TEXOPT_LAYOUT_FOLDOVER, &out->folded, mt);
        int collapsed_in = (input->flags[t] & TEXOPT_TRI_DEGENERATE_UV) != 0;
        double target = targets && !collapsed_in ? targets[t].lambda1 * targets[t].lambda2 * fabs(a_in) * scale : 0;
        double uniform = collapsed_in ? 0 : fabs(a_in) * uniform_scale;
        if (fabs(a) > TEXOPT_LAYOUT_CHECK_AREA_FACTOR * fmax(target, uniform) + mean)
            offend(out, TEXOPT_LAYOUT_AREA, &out->oversized, mt);
    }
    return st;
}

texopt_status texopt_layout_check_run(const texopt_mesh *input, const double *texel, int width, int height,
                                      const uint32_t *group_of_chart, const texopt_triangle_target *targets,
                                      texopt_layout_check *out, char *err, size_t err_len)
{
    return run_checks(input, texel, width, height, group_of_chart, targets, 0, out, err, err_len);
}

texopt_status texopt_layout_check_own(const texopt_mesh *mesh, texopt_layout_check *out, char *err, size_t err_len)
{
    texopt_texel_share *share = NULL;
    texopt_status st = texopt_texel_share_create(&share, mesh, err, err_len);
    if (st == TEXOPT_OK)
        st = run_checks(mesh, mesh->texel, mesh->width, mesh->height, share->primary_of, NULL, 1, out, err, err_len);
    texopt_texel_share_destroy(share);
    out->oversized = 0; /* its own areas: nothing to compare with */
    if (out->failed == TEXOPT_LAYOUT_AREA) {
        out->failed = TEXOPT_LAYOUT_PASSED;
        out->listed = 0;
    }
    for (size_t t = 0; st == TEXOPT_OK && t < mesh->triangle_count; t++)
        if (mesh->flags[t] & TEXOPT_TRI_FLIPPED)
            offend(out, TEXOPT_LAYOUT_FOLDOVER, &out->folded, mesh->model_triangle[t]);
    return st;
}

cJSON *texopt_layout_check_json(const texopt_layout_check *c)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddBoolToObject(o, "passed", c->failed == TEXOPT_LAYOUT_PASSED);
    const char *failed = texopt_layout_failure_name(c->failed);
    if (failed)
        cJSON_AddStringToObject(o, "failed", failed);
    else
        cJSON_AddNullToObject(o, "failed");
    cJSON *t = cJSON_AddArrayToObject(o, "triangles");
    for (size_t i = 0; t && i < c->listed; i++)
        cJSON_AddItemToArray(t, cJSON_CreateNumber(c->triangles[i]));
    cJSON_AddNumberToObject(o, "overlapping_triangles", (double)c->overlapping);
    cJSON_AddNumberToObject(o, "overlapping_within_chart_triangles", (double)c->overlapping_within);
    cJSON_AddNumberToObject(o, "overlap_within_chart_texels", (double)c->overlap_within_texels);
    cJSON_AddNumberToObject(o, "foldover_triangles", (double)c->folded);
    cJSON_AddNumberToObject(o, "oversized_triangles", (double)c->oversized);
    return o;
}
