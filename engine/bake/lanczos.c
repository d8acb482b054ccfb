/* lanczos.c - the separable Lanczos-3 resize of lanczos.h, Pillow's rules (see there). */
#include "lanczos.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"

#define LANCZOS_LOBES 3.0
#define PI 3.14159265358979323846
#define MAX_WORKERS 16

static double sinc(double x)
{
    if (x == 0.0)
        return 1.0;
    x *= PI;
    return sin(x) / x;
}

static double lanczos3(double x)
{
    return x > -LANCZOS_LOBES && x < LANCZOS_LOBES ? sinc(x) * sinc(x / LANCZOS_LOBES) : 0.0;
}

/* The weights of one axis: output i reads `count[i]` inputs from `first[i]` on, with weights
 * weight[i * width ...]. */
typedef struct axis_kernel {
    int *first, *count;
    float *weight;
    int width; /* weights per output, the most any reads */
} axis_kernel;

static void axis_kernel_destroy(axis_kernel *k)
{
    free(k->first);
    free(k->count);
    free(k->weight);
}

/* Pillow's precompute_coeffs: the window of output i is centred at (i + 0.5) * scale input
 * texels, half-width 3 * max(scale, 1), cut at the edges and renormalised. */
static texopt_status axis_kernel_create(axis_kernel *k, int in, int out, char *err, size_t err_len)
{
    double scale = (double)in / out, stretch = scale > 1 ? scale : 1, support = LANCZOS_LOBES * stretch;
    k->width = (int)ceil(support) * 2 + 1;
    k->first = malloc((size_t)out * sizeof *k->first);
    k->count = malloc((size_t)out * sizeof *k->count);
    k->weight = calloc((size_t)out * (size_t)k->width, sizeof *k->weight);
    double *w = malloc((size_t)k->width * sizeof *w);
    if (!k->first || !k->count || !k->weight || !w) {
        free(w);
        axis_kernel_destroy(k);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %d -> %d resize", in, out);
    }
    for (int i = 0; i < out; i++) {
        double center = (i + 0.5) * scale;
        int lo = (int)floor(center - support + 0.5), hi = (int)floor(center + support + 0.5);
        lo = lo < 0 ? 0 : lo;
        hi = hi > in ? in : hi;
        if (hi - lo > k->width)
            hi = lo + k->width;
        double sum = 0;
        for (int x = lo; x < hi; x++)
            sum += w[x - lo] = lanczos3((x - center + 0.5) / stretch);
        float *row = k->weight + (size_t)i * (size_t)k->width;
        for (int x = lo; x < hi; x++)
            row[x - lo] = (float)(sum != 0 ? w[x - lo] / sum : 0);
        k->first[i] = lo;
        k->count[i] = hi - lo;
    }
    free(w);
    return TEXOPT_OK;
}

static float clamp01(double v)
{
    return v < 0 ? 0.0f : v > 1 ? 1.0f : (float)v;
}

/* One pass: rows of `to` from `from`, along x (horizontal) or y. */
typedef struct pass_worker {
    const texopt_image *from;
    texopt_image *to;
    const axis_kernel *k;
    int horizontal, first_row, step;
} pass_worker;

static void *resize_pass_rows(void *arg)
{
    const pass_worker *w = arg;
    int c = w->to->channels;
    double acc[4];
    for (int y = w->first_row; y < w->to->height; y += w->step)
        for (int x = 0; x < w->to->width; x++) {
            int i = w->horizontal ? x : y;
            const float *kw = w->k->weight + (size_t)i * (size_t)w->k->width;
            memset(acc, 0, sizeof acc);
            for (int j = 0; j < w->k->count[i]; j++) {
                int s = w->k->first[i] + j;
                const float *p = w->horizontal ? texopt_image_at(w->from, s, y) : texopt_image_at(w->from, x, s);
                for (int ch = 0; ch < c; ch++)
                    acc[ch] += (double)kw[j] * p[ch];
            }
            float *o = texopt_image_at(w->to, x, y);
            for (int ch = 0; ch < c; ch++)
                o[ch] = clamp01(acc[ch]);
        }
    return NULL;
}

static void run_pass(const texopt_image *from, texopt_image *to, const axis_kernel *k, int horizontal, int threads)
{
    pass_worker w[MAX_WORKERS];
    for (int i = 0; i < threads; i++)
        w[i] = (pass_worker){from, to, k, horizontal, i, threads};
    texopt_parallel_run(resize_pass_rows, w, sizeof *w, threads);
}

texopt_status texopt_lanczos_resize(const texopt_image *src, texopt_image *dst, int threads, char *err, size_t err_len)
{
    if (!src || !src->pixels || !dst || !dst->pixels || dst->channels != src->channels || src->channels < 1 ||
        src->channels > 4 || dst->width < 1 || dst->height < 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "resize: a decoded source and a destination allocated with its channels are needed");
    threads = threads < 1 ? 1 : (threads > MAX_WORKERS ? MAX_WORKERS : threads);
    axis_kernel kx = {0}, ky = {0};
    texopt_image rows = {0};
    texopt_status st = axis_kernel_create(&kx, src->width, dst->width, err, err_len);
    if (st == TEXOPT_OK)
        st = axis_kernel_create(&ky, src->height, dst->height, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_image_create(&rows, dst->width, src->height, src->channels, err, err_len);
    if (st == TEXOPT_OK) {
        run_pass(src, &rows, &kx, 1, threads);
        run_pass(&rows, dst, &ky, 0, threads);
    }
    texopt_image_destroy(&rows);
    axis_kernel_destroy(&kx);
    axis_kernel_destroy(&ky);
    return st;
}
