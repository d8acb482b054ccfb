/* texture_filter.c - box mip pyramid and anisotropic trilinear lookups (see texture_filter.h).
 *
 * Level l + 1, sized max(1, ceil(w / 2)), is the box average of level l over the same extent
 * (2 x 2 texels for even sides, a little less for odd ones), and a level-0 position x maps to
 * x * w_l / w_0 at level l: every level is read at the same place, and a texel-aligned 2x
 * reduction of an even side reads level 1 at its texel centres, an exact box filter.
 * Level 0 is not copied: the filter keeps a pointer to the caller's image. */
#include "texture_filter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"

#define MAX_LEVELS 32
#define MAX_PROBES 16
#define MAX_WORKERS 64

struct texopt_texture_filter {
    int level_count;
    texopt_image level[MAX_LEVELS]; /* level[0] borrows the caller's pixels */
    texopt_wrap wrap_s, wrap_t;
};

/* Farthest reach of texopt_texture_filter_range, in texels each way. */
#define RANGE_REACH 64.0

static int wrap_index(int i, int n, texopt_wrap mode)
{
    if (mode == TEXOPT_WRAP_CLAMP)
        return i < 0 ? 0 : (i >= n ? n - 1 : i);
    if (mode == TEXOPT_WRAP_MIRROR) {
        int period = 2 * n;
        int m = ((i % period) + period) % period;
        return m < n ? m : period - 1 - m;
    }
    return ((i % n) + n) % n;
}

/* Texel index range [first, last] of the bilinear taps of lookups in [c - h, c + h], h cut
 * to RANGE_REACH. */
static void tap_span(double c, double h, int *first, int *last)
{
    h = h < RANGE_REACH ? h : RANGE_REACH;
    double lo = floor(c - h - 0.5), hi = floor(c + h - 0.5) + 1;
    *first = isfinite(lo) ? (int)lo : 0;
    *last = isfinite(hi) ? (int)hi : 0;
}

void texopt_texture_filter_range(const texopt_texture_filter *filter, double x, double y, double hx, double hy,
                                 float *lo, float *hi)
{
    const texopt_image *img = &filter->level[0];
    int x0, x1, y0, y1;
    tap_span(x, hx, &x0, &x1);
    tap_span(y, hy, &y0, &y1);
    for (int k = 0; k < img->channels; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int j = y0; j <= y1; j++) {
        int row = wrap_index(j, img->height, filter->wrap_t);
        for (int i = x0; i <= x1; i++) {
            const float *v = texopt_image_at(img, wrap_index(i, img->width, filter->wrap_s), row);
            for (int k = 0; k < img->channels; k++) {
                lo[k] = v[k] < lo[k] ? v[k] : lo[k];
                hi[k] = v[k] > hi[k] ? v[k] : hi[k];
            }
        }
    }
}

static void bilinear(const texopt_image *img, texopt_wrap ws, texopt_wrap wt, double x, double y, float *out)
{
    double fx = x - 0.5, fy = y - 0.5;
    double flx = floor(fx), fly = floor(fy);
    double tx = fx - flx, ty = fy - fly;
    int x0, x1, y0, y1;
    if (flx >= 0 && fly >= 0 && flx + 1 < img->width && fly + 1 < img->height) {
        /* All four taps inside: no wrapping to do (most lookups of a bake). */
        x0 = (int)flx;
        y0 = (int)fly;
        x1 = x0 + 1;
        y1 = y0 + 1;
    } else {
        /* Positions far outside the texture (wrapped UVs) stay exact in double before the cast. */
        int ix = (int)fmod(flx, 1 << 30), iy = (int)fmod(fly, 1 << 30);
        x0 = wrap_index(ix, img->width, ws);
        x1 = wrap_index(ix + 1, img->width, ws);
        y0 = wrap_index(iy, img->height, wt);
        y1 = wrap_index(iy + 1, img->height, wt);
    }
    const float *p00 = texopt_image_at(img, x0, y0), *p10 = texopt_image_at(img, x1, y0);
    const float *p01 = texopt_image_at(img, x0, y1), *p11 = texopt_image_at(img, x1, y1);
    double w00 = (1 - tx) * (1 - ty), w10 = tx * (1 - ty), w01 = (1 - tx) * ty, w11 = tx * ty;
    for (int c = 0; c < img->channels; c++)
        out[c] = (float)(w00 * p00[c] + w10 * p10[c] + w01 * p01[c] + w11 * p11[c]);
}

/* Source texels under destination texel d along one axis, where the destination's n_dst
 * texels span the same extent as the source's n_src (1 <= n_src / n_dst <= 2): the box
 * weights of their overlaps, at most three taps. */
typedef struct axis_taps {
    int count;
    int index[3];
    float weight[3];
} axis_taps;

static axis_taps taps_under(int d, int n_src, int n_dst)
{
    axis_taps t = {0, {0, 0, 0}, {0, 0, 0}};
    double ratio = (double)n_src / n_dst, a = d * ratio, b = (d + 1) * ratio;
    for (int i = (int)floor(a); i < n_src && i < b && t.count < 3; i++) {
        double overlap = fmin(b, i + 1.0) - fmax(a, (double)i);
        if (overlap <= 0)
            continue;
        t.index[t.count] = i;
        t.weight[t.count++] = (float)(overlap / ratio);
    }
    return t;
}

/* Level l + 1 of max(1, ceil(w / 2)) texels spanning the same extent as level l: each texel
 * the box average of what it covers, so that a lookup at x * w_l / w_0 reads every level at
 * the same place. An even side pairs texels exactly (weights 1/2); an odd one spreads each
 * new texel over a little less than two (a plain 2 x 2 pairing would drift by up to a whole
 * texel of level l across the image, which shifts minified edges). */
static texopt_status build_next_level(const texopt_image *src, texopt_image *dst, char *err, size_t err_len)
{
    int w = src->width > 1 ? (src->width + 1) / 2 : 1;
    int h = src->height > 1 ? (src->height + 1) / 2 : 1;
    texopt_status st = texopt_image_create(dst, w, h, src->channels, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    axis_taps *columns = malloc((size_t)w * sizeof *columns); /* the same for every row */
    if (!columns) {
        texopt_image_destroy(dst);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a mip level");
    }
    for (int x = 0; x < w; x++)
        columns[x] = taps_under(x, src->width, w);
    int ch = src->channels;
    for (int y = 0; y < h; y++) {
        axis_taps ty = taps_under(y, src->height, h);
        for (int x = 0; x < w; x++) {
            const axis_taps *tx = &columns[x];
            /* Row tap by row tap, then column tap by column tap: with even sides (weights
             * 1/2) bit for bit the 2 x 2 mean ((a + b) + c) + d scaled by 1/4. */
            float acc[4] = {0, 0, 0, 0};
            for (int j = 0; j < ty.count; j++)
                for (int i = 0; i < tx->count; i++) {
                    const float *p = texopt_image_at(src, tx->index[i], ty.index[j]);
                    float wgt = ty.weight[j] * tx->weight[i];
                    for (int k = 0; k < ch; k++)
                        acc[k] += wgt * p[k];
                }
            memcpy(texopt_image_at(dst, x, y), acc, (size_t)ch * sizeof *acc);
        }
    }
    free(columns);
    return TEXOPT_OK;
}

texopt_status texopt_texture_filter_create(texopt_texture_filter **out, const texopt_image *img, texopt_wrap wrap_s,
                                           texopt_wrap wrap_t, char *err, size_t err_len)
{
    *out = NULL;
    if (!img || !img->pixels || img->width < 1 || img->height < 1 || img->channels < 1 || img->channels > 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "texture filter: the image is empty or has a bad channel count");
    texopt_texture_filter *f = calloc(1, sizeof *f);
    if (!f)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a texture filter");
    f->wrap_s = wrap_s;
    f->wrap_t = wrap_t;
    f->level[0] = *img;
    f->level_count = 1;
    while (f->level_count < MAX_LEVELS) {
        const texopt_image *prev = &f->level[f->level_count - 1];
        if (prev->width == 1 && prev->height == 1)
            break;
        texopt_status st = build_next_level(prev, &f->level[f->level_count], err, err_len);
        if (st != TEXOPT_OK) {
            texopt_texture_filter_destroy(f);
            return st;
        }
        f->level_count++;
    }
    *out = f;
    return TEXOPT_OK;
}

void texopt_texture_filter_destroy(texopt_texture_filter *filter)
{
    if (!filter)
        return;
    for (int l = 1; l < filter->level_count; l++)
        texopt_image_destroy(&filter->level[l]);
    free(filter);
}

int texopt_texture_filter_levels(const texopt_texture_filter *filter)
{
    return filter->level_count;
}

static void sample_level(const texopt_texture_filter *f, int l, double x, double y, float *out)
{
    const texopt_image *lv = &f->level[l];
    double sx = (double)lv->width / f->level[0].width, sy = (double)lv->height / f->level[0].height;
    bilinear(lv, f->wrap_s, f->wrap_t, x * sx, y * sy, out);
}

static void sample_trilinear(const texopt_texture_filter *f, double lod, double x, double y, float *out)
{
    int ch = f->level[0].channels;
    if (lod <= 0) {
        sample_level(f, 0, x, y, out);
        return;
    }
    int l0 = (int)floor(lod);
    if (l0 >= f->level_count - 1) {
        sample_level(f, f->level_count - 1, x, y, out);
        return;
    }
    double t = lod - l0;
    float a[4], b[4];
    sample_level(f, l0, x, y, a);
    sample_level(f, l0 + 1, x, y, b);
    for (int c = 0; c < ch; c++)
        out[c] = (float)((1 - t) * a[c] + t * b[c]);
}

/* Singular values (s1 >= s2) of the 2x2 jacobian and the unit input-space direction of s1. */
static void footprint_axes(const double j[4], double *s1, double *s2, double dir[2])
{
    double p = j[0] * j[0] + j[1] * j[1]; /* J J^T */
    double q = j[2] * j[2] + j[3] * j[3];
    double r = j[0] * j[2] + j[1] * j[3];
    double mean = 0.5 * (p + q);
    double dev = sqrt(0.25 * (p - q) * (p - q) + r * r);
    double e1 = mean + dev, e2 = mean - dev;
    *s1 = sqrt(e1 > 0 ? e1 : 0);
    *s2 = sqrt(e2 > 0 ? e2 : 0);
    /* Eigenvector of e1 without trigonometry (this runs once per lookup): the better
     * conditioned of (r, e1 - p) and (e1 - q, r). */
    double ax = r, ay = e1 - p, bx = e1 - q, by = r;
    double na = ax * ax + ay * ay, nb = bx * bx + by * by;
    if (na < nb) {
        ax = bx;
        ay = by;
        na = nb;
    }
    if (!(na > 0)) { /* isotropic: any direction */
        dir[0] = 1;
        dir[1] = 0;
        return;
    }
    double inv = 1.0 / sqrt(na);
    dir[0] = ax * inv;
    dir[1] = ay * inv;
}

void texopt_texture_filter_sample(const texopt_texture_filter *filter, double x, double y, const double jacobian[4],
                                  float *out)
{
    double s1, s2, dir[2];
    footprint_axes(jacobian, &s1, &s2, dir);
    if (!(s1 > 1.0)) {
        sample_level(filter, 0, x, y, out);
        return;
    }
    double minor = s2 > 1.0 ? s2 : 1.0;
    int n = (int)ceil(s1 / minor - 1e-9);
    if (n > MAX_PROBES)
        n = MAX_PROBES;
    if (n < 1)
        n = 1;
    double width = s1 / n > s2 ? s1 / n : s2;
    double lod = log2(width > 1 ? width : 1);
    int ch = filter->level[0].channels;
    if (n == 1) {
        sample_trilinear(filter, lod, x, y, out);
        return;
    }
    double acc[4] = {0, 0, 0, 0};
    float probe[4];
    for (int k = 0; k < n; k++) {
        double o = ((k + 0.5) / n - 0.5) * s1;
        sample_trilinear(filter, lod, x + o * dir[0], y + o * dir[1], probe);
        for (int c = 0; c < ch; c++)
            acc[c] += probe[c];
    }
    for (int c = 0; c < ch; c++)
        out[c] = (float)(acc[c] / n);
}

typedef struct resize_worker {
    const texopt_texture_filter *filter;
    texopt_image *dst;
    double kx, ky;
    int first_row, step;
} resize_worker;

static void *resize_rows(void *arg)
{
    resize_worker *w = arg;
    const double jac[4] = {w->kx, 0, 0, w->ky};
    for (int y = w->first_row; y < w->dst->height; y += w->step)
        for (int x = 0; x < w->dst->width; x++)
            texopt_texture_filter_sample(w->filter, (x + 0.5) * w->kx, (y + 0.5) * w->ky, jac,
                                         texopt_image_at(w->dst, x, y));
    return NULL;
}

texopt_status texopt_texture_resize(const texopt_image *src, texopt_wrap wrap_s, texopt_wrap wrap_t, texopt_image *dst,
                                    int threads, char *err, size_t err_len)
{
    if (!dst || !dst->pixels || dst->channels != src->channels)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "resize: destination must be allocated with %d channels", src->channels);
    texopt_texture_filter *f;
    texopt_status st = texopt_texture_filter_create(&f, src, wrap_s, wrap_t, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    threads = threads < 1 ? 1 : (threads > MAX_WORKERS ? MAX_WORKERS : threads);
    resize_worker w[MAX_WORKERS];
    for (int k = 0; k < threads; k++)
        w[k] = (resize_worker){.filter = f,
                               .dst = dst,
                               .kx = (double)src->width / dst->width,
                               .ky = (double)src->height / dst->height,
                               .first_row = k,
                               .step = threads};
    texopt_parallel_run(resize_rows, w, sizeof *w, threads);
    texopt_texture_filter_destroy(f);
    return TEXOPT_OK;
}
