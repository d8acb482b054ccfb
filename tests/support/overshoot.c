/* overshoot.c - the ringing measure of overshoot.h: texel-centre rasterisation of the new
 * layout, each texel once (the first triangle that holds its centre), and a min/max window in
 * the source around the mapped point. */
#include "overshoot.h"

#include <math.h>
#include <stdlib.h>

#include "texel_map.h"

typedef struct window_range {
    float lo[4], hi[4];
} window_range;

/* Range of src's texels whose centres lie within r texels (a square) of (px, py). */
static void source_range(const texopt_image *src, double px, double py, double r, window_range *wr)
{
    int x0 = (int)ceil(px - r - 0.5), x1 = (int)floor(px + r - 0.5);
    int y0 = (int)ceil(py - r - 0.5), y1 = (int)floor(py + r - 0.5);
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= src->width ? src->width - 1 : x1;
    y1 = y1 >= src->height ? src->height - 1 : y1;
    for (int k = 0; k < src->channels; k++) {
        wr->lo[k] = INFINITY;
        wr->hi[k] = -INFINITY;
    }
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            const float *v = texopt_image_at(src, x, y);
            for (int k = 0; k < src->channels; k++) {
                wr->lo[k] = v[k] < wr->lo[k] ? v[k] : wr->lo[k];
                wr->hi[k] = v[k] > wr->hi[k] ? v[k] : wr->hi[k];
            }
        }
}

/* Largest singular value of a 2x2 row-major matrix. */
static double largest_singular(const double m[4])
{
    double a = m[0] * m[0] + m[1] * m[1], d = m[2] * m[2] + m[3] * m[3], b = m[0] * m[2] + m[1] * m[3];
    return sqrt(0.5 * (a + d) + sqrt(0.25 * (a - d) * (a - d) + b * b));
}

typedef struct measure_ctx {
    const texopt_image *src, *out;
    const int *mask;
    uint8_t *seen;
    double radius;
    size_t over, counted;
    overshoot *res;
} measure_ctx;

static void measure_texel(measure_ctx *c, const float *texel, double px, double py, double r)
{
    window_range wr;
    if (px < -0.5 || py < -0.5 || px > c->src->width + 0.5 || py > c->src->height + 0.5)
        return;
    source_range(c->src, px, py, r, &wr);
    for (int k = 0; k < c->src->channels; k++) {
        if (c->mask && !c->mask[k])
            continue;
        if (!(wr.lo[k] <= wr.hi[k]))
            return;
        double above = 255.0 * (texel[k] - wr.hi[k]), below = 255.0 * (wr.lo[k] - texel[k]);
        c->res->above = above > c->res->above ? above : c->res->above;
        c->res->below = below > c->res->below ? below : c->res->below;
        c->over += above > 1.0 || below > 1.0;
        c->counted++;
    }
    c->res->texels++;
}

static void measure_triangle(measure_ctx *c, const float *uv_in, const float *uv_out, const uint32_t *t)
{
    double q[3][2], p[3][2], m[4], area2;
    for (int i = 0; i < 3; i++) {
        q[i][0] = uv_out[2 * t[i]] * c->out->width;
        q[i][1] = uv_out[2 * t[i] + 1] * c->out->height;
        p[i][0] = uv_in[2 * t[i]] * c->src->width;
        p[i][1] = uv_in[2 * t[i] + 1] * c->src->height;
    }
    if (!texopt_texel_map((const double(*)[2])p, (const double(*)[2])q, m, &area2))
        return;
    double r = c->radius * largest_singular(m);
    r = r > 1.0 ? r : 1.0;
    double lo[2] = {fmin(q[0][0], fmin(q[1][0], q[2][0])), fmin(q[0][1], fmin(q[1][1], q[2][1]))};
    double hi[2] = {fmax(q[0][0], fmax(q[1][0], q[2][0])), fmax(q[0][1], fmax(q[1][1], q[2][1]))};
    int x0 = (int)fmax(0, floor(lo[0])), y0 = (int)fmax(0, floor(lo[1]));
    int x1 = (int)fmin(c->out->width - 1, ceil(hi[0])), y1 = (int)fmin(c->out->height - 1, ceil(hi[1]));
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            size_t i = (size_t)y * c->out->width + x;
            double w[3], cx = x + 0.5, cy = y + 0.5;
            for (int k = 0; k < 3; k++) {
                const double *a = q[(k + 1) % 3], *b = q[(k + 2) % 3];
                w[k] = ((b[0] - a[0]) * (cy - a[1]) - (b[1] - a[1]) * (cx - a[0])) / area2;
            }
            if (c->seen[i] || w[0] < 0 || w[1] < 0 || w[2] < 0)
                continue;
            c->seen[i] = 1;
            double px = w[0] * p[0][0] + w[1] * p[1][0] + w[2] * p[2][0];
            double py = w[0] * p[0][1] + w[1] * p[1][1] + w[2] * p[2][1];
            measure_texel(c, texopt_image_at(c->out, x, y), px, py, r);
        }
}

int overshoot_measure(const texopt_image *src, const texopt_image *out, const float *uv_in, const float *uv_out,
                      const uint32_t *triangles, size_t triangle_count, double radius, const int *channel_mask,
                      overshoot *result)
{
    if (!src || !out || !uv_in || !uv_out || !triangles || !result || triangle_count == 0 ||
        src->channels != out->channels || src->channels > 4 || !(radius > 0))
        return -1;
    uint8_t *seen = calloc((size_t)out->width * (size_t)out->height, 1);
    if (!seen)
        return -1;
    *result = (overshoot){0};
    measure_ctx c = {.src = src, .out = out, .mask = channel_mask, .seen = seen, .radius = radius, .res = result};
    for (size_t t = 0; t < triangle_count; t++)
        measure_triangle(&c, uv_in, uv_out, triangles + 3 * t);
    result->share = c.counted ? (double)c.over / (double)c.counted : 0;
    free(seen);
    return 0;
}
