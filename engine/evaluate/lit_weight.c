/* lit_weight.c - lit visibility of each texture signal, sampled (lit_weight.h). Does not:
 * render or rasterise (one point at a time through texopt_lit_point). */
#include "lit_weight.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lit_shade.h"
#include "meshrender.h"
#include "rng.h"
#include "sample.h"
#include "vec3.h"

/* 4096 points x 8 directions: on the assets, two other seeds move each weight above 0.1 by at
 * most 4% (DamagedHelmet's normal x), about 0.05 s per model. */
#define LIT_WEIGHT_POINTS 4096
#define LIT_WEIGHT_DIRECTIONS 8
/* Half the central difference's step: small against the maps' range, large against float
 * rounding of the texels. */
#define LIT_WEIGHT_STEP (1.0 / 64.0)
#define LIT_WEIGHT_SEED 0x6c69745f77656967ULL
#define PI 3.14159265358979323846

/* What the lit render reads at one point: per slot, the image (-1: none) and its texel as
 * RGB (grey images repeated, as meshrender reads them). */
typedef struct point_maps {
    int image[TEXOPT_SLOT_COUNT];
    float rgb[TEXOPT_SLOT_COUNT][3];
    double metallic_factor, roughness_factor;
} point_maps;

/* The values texopt_lit_point takes, with lit_shade.h's defaults for empty slots. */
typedef struct point_values {
    double b, metallic, roughness, n[3], occlusion, emission;
} point_values;

static void values_of(const point_maps *p, point_values *v)
{
    v->b = p->image[TEXOPT_SLOT_BASE_COLOR] >= 0 ? texopt_luma(p->rgb[TEXOPT_SLOT_BASE_COLOR], 3) : 0.5;
    const float *mr = p->rgb[TEXOPT_SLOT_METALLIC_ROUGHNESS];
    int has_mr = p->image[TEXOPT_SLOT_METALLIC_ROUGHNESS] >= 0;
    v->metallic = p->metallic_factor * (has_mr ? mr[2] : 1.0);
    v->roughness = p->roughness_factor * (has_mr ? mr[1] : 1.0);
    v->n[0] = v->n[1] = 0.0;
    v->n[2] = 1.0;
    if (p->image[TEXOPT_SLOT_NORMAL] >= 0) {
        const float *t = p->rgb[TEXOPT_SLOT_NORMAL];
        double n[3] = {2.0 * t[0] - 1.0, 2.0 * t[1] - 1.0, 2.0 * t[2] - 1.0};
        if (texopt_normalize3(n))
            memcpy(v->n, n, sizeof n);
    }
    v->occlusion = p->image[TEXOPT_SLOT_OCCLUSION] >= 0 ? p->rgb[TEXOPT_SLOT_OCCLUSION][0] : 1.0;
    v->emission = p->image[TEXOPT_SLOT_EMISSIVE] >= 0 ? texopt_luma(p->rgb[TEXOPT_SLOT_EMISSIVE], 3) : 0.0;
}

static double lit(const point_maps *p, const double l[3], const double v[3])
{
    point_values x;
    values_of(p, &x);
    return texopt_lit_point(x.b, x.metallic, x.roughness, x.n, l, v, x.occlusion, x.emission);
}

/* p with signal k (0 luma, 1..3 a channel) of `image` moved by delta in every slot reading it. */
static void shift_signal(const point_maps *p, int image, int channels, int k, double delta, point_maps *out)
{
    *out = *p;
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++) {
        if (out->image[s] != image)
            continue;
        for (int c = 0; c < 3; c++)
            if (k == 0 || channels < 3 || c == k - 1)
                out->rgb[s][c] += (float)delta;
    }
}

/* The 3D area of triangle t; 0 when it names a vertex the model does not have. */
static double triangle_area(const texopt_model *m, size_t t)
{
    const uint32_t *c = m->triangles + 3 * t;
    if (c[0] >= m->vertex_count || c[1] >= m->vertex_count || c[2] >= m->vertex_count)
        return 0.0;
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)m->positions[3 * (size_t)c[1] + k] - m->positions[3 * (size_t)c[0] + k];
        e2[k] = (double)m->positions[3 * (size_t)c[2] + k] - m->positions[3 * (size_t)c[0] + k];
    }
    texopt_cross3(e1, e2, n);
    double area = 0.5 * sqrt(texopt_dot3(n, n));
    return isfinite(area) ? area : 0.0;
}

/* Per triangle, the running sum of the 3D areas of the textured triangles up to it. */
static double *cumulative_areas(const texopt_model *m)
{
    double *cum = malloc((m->triangle_count ? m->triangle_count : 1) * sizeof *cum);
    if (!cum)
        return NULL;
    unsigned char *textured = calloc(m->triangle_count ? m->triangle_count : 1, 1);
    if (!textured) {
        free(cum);
        return NULL;
    }
    for (int p = 0; p < m->primitive_count; p++) {
        const texopt_primitive *prim = &m->primitives[p];
        if (prim->domain < 0 || prim->material < 0 || prim->material >= m->material_count)
            continue;
        for (size_t t = prim->first_triangle; t < prim->first_triangle + prim->triangle_count && t < m->triangle_count;
             t++)
            textured[t] = 1;
    }
    double total = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (textured[t])
            total += triangle_area(m, t);
        cum[t] = total;
    }
    free(textured);
    return cum;
}

static size_t pick_triangle(const double *cum, size_t count, double u)
{
    double target = u * cum[count - 1];
    size_t lo = 0, hi = count - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cum[mid] > target)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

static int primitive_of(const texopt_model *m, size_t t)
{
    for (int p = 0; p < m->primitive_count; p++) {
        const texopt_primitive *prim = &m->primitives[p];
        if (t >= prim->first_triangle && t < prim->first_triangle + prim->triangle_count)
            return p;
    }
    return -1;
}

/* The maps at a uniformly drawn point of triangle t. */
static void sample_point(const texopt_model *m, size_t t, texopt_rng *rng, point_maps *p)
{
    double r1 = sqrt(texopt_rng_uniform(rng)), r2 = texopt_rng_uniform(rng);
    double w[3] = {1.0 - r1, r1 * (1.0 - r2), r1 * r2};
    double u = 0.0, v = 0.0;
    for (int k = 0; k < 3; k++) {
        const float *uv = m->uvs + 2 * (size_t)m->triangles[3 * t + k];
        u += w[k] * uv[0];
        v += w[k] * uv[1];
    }
    int prim = primitive_of(m, t), material = prim >= 0 ? m->primitives[prim].material : -1;
    const texopt_material *mat = material >= 0 && material < m->material_count ? &m->materials[material] : NULL;
    p->metallic_factor = mat ? mat->metallic_factor : 1.0;
    p->roughness_factor = mat ? mat->roughness_factor : 1.0;
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++) {
        p->image[s] = -1;
        const texopt_texture_ref *r = texopt_meshrender_binding(m, prim, (texopt_slot)s);
        if (!r)
            continue;
        const texopt_image *img = &m->images[r->image];
        float texel[4];
        texopt_sample_bilinear(img, r->wrap_s, r->wrap_t, u * img->width, v * img->height, texel);
        for (int c = 0; c < 3; c++)
            p->rgb[s][c] = texel[img->channels >= 3 ? c : 0];
        p->image[s] = r->image;
    }
}

/* A view direction about the face normal z (cosine-weighted) and its light: lit_shade.h's
 * light for a camera looking along -v with a random roll. */
static void sample_directions(texopt_rng *rng, double l[3], double v[3])
{
    double phi = 2.0 * PI * texopt_rng_uniform(rng), s2 = texopt_rng_uniform(rng);
    double s = sqrt(s2);
    texopt_view view;
    memset(&view, 0, sizeof view);
    view.direction[0] = s * cos(phi);
    view.direction[1] = s * sin(phi);
    view.direction[2] = sqrt(1.0 - s2);
    double a[3], b[3], helper[3] = {1.0, 0.0, 0.0};
    if (fabs(view.direction[0]) > 0.9) {
        helper[0] = 0.0;
        helper[1] = 1.0;
    }
    texopt_cross3(view.direction, helper, a);
    texopt_normalize3(a);
    texopt_cross3(view.direction, a, b);
    double roll = 2.0 * PI * texopt_rng_uniform(rng), c = cos(roll), sn = sin(roll);
    for (int k = 0; k < 3; k++) {
        view.right[k] = c * a[k] + sn * b[k];
        view.up[k] = -sn * a[k] + c * b[k];
    }
    texopt_lit_light(&view, l);
    memcpy(v, view.direction, 3 * sizeof *v);
}

/* |dL/dx| by central difference between the point moved down (minus) and up (plus). */
static double slope(const point_maps *minus, const point_maps *plus, const double l[3], const double v[3])
{
    return fabs(lit(plus, l, v) - lit(minus, l, v)) / (2.0 * LIT_WEIGHT_STEP);
}

static double base_colour_slope(const point_maps *p, const double l[3], const double v[3])
{
    point_values x;
    values_of(p, &x);
    double hi = texopt_lit_point(x.b + LIT_WEIGHT_STEP, x.metallic, x.roughness, x.n, l, v, x.occlusion, x.emission);
    double lo = texopt_lit_point(x.b - LIT_WEIGHT_STEP, x.metallic, x.roughness, x.n, l, v, x.occlusion, x.emission);
    return fabs(hi - lo) / (2.0 * LIT_WEIGHT_STEP);
}

/* The weights measured of an image with `channels` channels: its luma and its R, G, B (or its
 * grey); alpha is not lit. */
static int weighed_signals(int channels)
{
    return channels >= 3 ? 4 : 2;
}

/* Adds the point's slopes for every image it reads into sums, and counts it. */
static void accumulate_point(const texopt_model *m, const point_maps *p, const double l[3], const double v[3],
                             double *sums, size_t *counts)
{
    for (int s = 0; s < TEXOPT_SLOT_COUNT; s++) {
        int image = p->image[s], seen = 0;
        for (int e = 0; e < s; e++)
            seen |= p->image[e] == image;
        if (image < 0 || seen)
            continue;
        int channels = m->images[image].channels;
        int signals = weighed_signals(channels);
        counts[image]++;
        for (int k = 0; k < signals; k++) {
            point_maps plus, minus;
            shift_signal(p, image, channels, k, LIT_WEIGHT_STEP, &plus);
            shift_signal(p, image, channels, k, -LIT_WEIGHT_STEP, &minus);
            sums[TEXOPT_LIT_WEIGHT_STRIDE * (size_t)image + (size_t)k] += slope(&minus, &plus, l, v);
        }
    }
}

/* Sums every image's slopes over the sampled points and directions into sums (counts: the
 * samples that read the image); returns base colour's mean slope (0 when nothing is textured). */
static double mean_slopes(const texopt_model *model, const double *cum, double *sums, size_t *counts)
{
    if (!(cum[model->triangle_count - 1] > 0.0))
        return 0.0;
    double base = 0.0;
    texopt_rng rng;
    texopt_rng_seed(&rng, LIT_WEIGHT_SEED);
    for (int i = 0; i < LIT_WEIGHT_POINTS; i++) {
        size_t t = pick_triangle(cum, model->triangle_count, texopt_rng_uniform(&rng));
        point_maps p;
        sample_point(model, t, &rng, &p);
        for (int d = 0; d < LIT_WEIGHT_DIRECTIONS; d++) {
            double l[3], v[3];
            sample_directions(&rng, l, v);
            base += base_colour_slope(&p, l, v);
            accumulate_point(model, &p, l, v, sums, counts);
        }
    }
    return base / ((double)LIT_WEIGHT_POINTS * LIT_WEIGHT_DIRECTIONS);
}

texopt_status texopt_lit_signal_weights(const texopt_model *model, double *weights, char *err, size_t err_len)
{
    if (!model || !weights)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "lit weights: nothing to weigh");
    size_t slots = TEXOPT_LIT_WEIGHT_STRIDE * (size_t)model->image_count;
    for (size_t i = 0; i < slots; i++)
        weights[i] = 1.0;
    if (!texopt_lit_has_maps(model) || !model->uvs || !model->positions || model->triangle_count == 0)
        return TEXOPT_OK;
    double *cum = cumulative_areas(model);
    double *sums = calloc(slots ? slots : 1, sizeof *sums);
    size_t *counts = calloc(model->image_count ? (size_t)model->image_count : 1, sizeof *counts);
    if (!cum || !sums || !counts) {
        free(cum);
        free(sums);
        free(counts);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "lit weights: no memory");
    }
    double base_mean = mean_slopes(model, cum, sums, counts);
    for (int img = 0; base_mean > 0.0 && img < model->image_count; img++) {
        if (counts[img] == 0)
            continue;
        int signals = weighed_signals(model->images[img].channels);
        for (int k = 0; k < signals; k++) {
            size_t i = TEXOPT_LIT_WEIGHT_STRIDE * (size_t)img + (size_t)k;
            weights[i] = sums[i] / (double)counts[img] / base_mean;
        }
    }
    free(cum);
    free(sums);
    free(counts);
    return TEXOPT_OK;
}
