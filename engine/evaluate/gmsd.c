/* gmsd.c - Gradient Magnitude Similarity Deviation, Xue et al. 2013, following the
 * authors' MATLAB reference step by step (see gmsd.h for the definition and the mask rule).
 * Works on luma only; does not convert colour or resize beyond the reference's 2x2 step. */
#include "gmsd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The reference's T = 170 is on the 0..255 scale; GMS is invariant when T scales with the
 * square of the intensity scale, so on 0..1 it is 170 / 255^2. */
#define GMSD_T (170.0 / (255.0 * 255.0))

struct texopt_gmsd_workspace {
    int max_width, max_height;
    double *down_ref, *down_dist; /* ceil(w/2) x ceil(h/2) inside a one-pixel zero frame */
    unsigned char *down_covered;
    double *gms; /* counted GMS values */
};

texopt_gmsd_workspace *texopt_gmsd_workspace_create(int max_width, int max_height)
{
    if (max_width <= 0 || max_height <= 0 || max_width > 65536 || max_height > 65536)
        return NULL;
    texopt_gmsd_workspace *ws = calloc(1, sizeof *ws);
    if (!ws)
        return NULL;
    size_t n = (size_t)((max_width + 1) / 2) * (size_t)((max_height + 1) / 2);
    size_t padded = (size_t)((max_width + 1) / 2 + 2) * (size_t)((max_height + 1) / 2 + 2);
    ws->max_width = max_width;
    ws->max_height = max_height;
    ws->down_ref = malloc(padded * sizeof *ws->down_ref);
    ws->down_dist = malloc(padded * sizeof *ws->down_dist);
    ws->down_covered = malloc(n);
    ws->gms = malloc(n * sizeof *ws->gms);
    if (!ws->down_ref || !ws->down_dist || !ws->down_covered || !ws->gms) {
        texopt_gmsd_workspace_destroy(ws);
        return NULL;
    }
    return ws;
}

void texopt_gmsd_workspace_destroy(texopt_gmsd_workspace *ws)
{
    if (!ws)
        return;
    free(ws->down_ref);
    free(ws->down_dist);
    free(ws->down_covered);
    free(ws->gms);
    free(ws);
}

/* conv2(Y, ones(2)/4, 'same') sampled at odd MATLAB indices: the mean of a 2x2 block whose
 * missing row/column (odd sizes) counts as zero, still divided by 4. Written inside a frame
 * of zeros one pixel wide (row stride dw + 2): the Prewitt filter's zero padding, so the
 * gradient needs no bounds checks. */
static void average_downsample_rows(const float *src, int width, int height, double *dst, int row_lo, int row_hi)
{
    int dw = (width + 1) / 2, dh = (height + 1) / 2, stride = dw + 2;
    memset(dst, 0, (size_t)stride * sizeof *dst);
    memset(dst + (size_t)(dh + 1) * stride, 0, (size_t)stride * sizeof *dst);
    for (int i = row_lo; i <= row_hi; i++) {
        int r0 = 2 * i, r1 = 2 * i + 1;
        double *out = dst + (size_t)(i + 1) * stride;
        out[0] = 0.0;
        out[dw + 1] = 0.0;
        if (width % 2 == 0 && r1 < height) {
            /* Whole 2x2 blocks: the general loop's sums without its tests. */
            const float *a = src + (size_t)r0 * width, *b = src + (size_t)r1 * width;
            for (int j = 0; j < dw; j++)
                out[j + 1] = ((((double)a[2 * j] + a[2 * j + 1]) + b[2 * j]) + b[2 * j + 1]) / 4.0;
            continue;
        }
        for (int j = 0; j < dw; j++) {
            int c0 = 2 * j, c1 = 2 * j + 1;
            double sum = src[(size_t)r0 * width + c0];
            if (c1 < width)
                sum += src[(size_t)r0 * width + c1];
            if (r1 < height) {
                sum += src[(size_t)r1 * width + c0];
                if (c1 < width)
                    sum += src[(size_t)r1 * width + c1];
            }
            out[j + 1] = sum / 4.0;
        }
    }
}

static void average_downsample(const float *src, int width, int height, double *dst)
{
    average_downsample_rows(src, width, height, dst, 0, (height + 1) / 2 - 1);
}

static void downsample_mask(const unsigned char *mask, int width, int height, unsigned char *dst)
{
    int dw = (width + 1) / 2, dh = (height + 1) / 2;
    for (int i = 0; i < dh; i++) {
        for (int j = 0; j < dw; j++) {
            int covered = 1;
            for (int r = 2 * i; r < 2 * i + 2 && r < height; r++)
                for (int c = 2 * j; c < 2 * j + 2 && c < width; c++)
                    covered &= mask[(size_t)r * width + c] != 0;
            dst[(size_t)i * dw + j] = (unsigned char)covered;
        }
    }
}

/* A downsampled pixel counts when it and its in-image 3x3 neighbours are covered. */
static int support_covered(const unsigned char *covered, int dw, int dh, int i, int j)
{
    for (int r = i - 1; r <= i + 1; r++) {
        if (r < 0 || r >= dh)
            continue;
        for (int c = j - 1; c <= j + 1; c++) {
            if (c >= 0 && c < dw && !covered[(size_t)r * dw + c])
                return 0;
        }
    }
    return 1;
}

/* Prewitt gradient magnitude with the reference's /3 at downsampled pixel (i, j) of a
 * zero-framed image (see average_downsample). */
static inline double prewitt_at(const double *up, int dw)
{
    int stride = dw + 2;
    const double *mid = up + stride, *down = mid + stride;
    double gx = (up[0] + mid[0] + down[0]) - (up[2] + mid[2] + down[2]);
    double gy = (up[0] + up[1] + up[2]) - (down[0] + down[1] + down[2]);
    gx /= 3.0;
    gy /= 3.0;
    return sqrt(gx * gx + gy * gy);
}

/* The same at downsampled pixel (i, j): `up` is row i-1, column j-1 of the framed image. */
static double prewitt_magnitude(const double *framed, int dw, int i, int j)
{
    return prewitt_at(framed + (size_t)i * (dw + 2) + j, dw);
}

/* MATLAB std2: sample standard deviation with N-1. */
static double sample_deviation(const double *v, size_t n)
{
    if (n < 2)
        return 0.0;
    double mean = 0.0;
    for (size_t i = 0; i < n; i++)
        mean += v[i];
    mean /= (double)n;
    double ss = 0.0;
    for (size_t i = 0; i < n; i++)
        ss += (v[i] - mean) * (v[i] - mean);
    return sqrt(ss / (double)(n - 1));
}

double texopt_gmsd_ws(texopt_gmsd_workspace *ws, const float *reference, const float *distorted,
                      const unsigned char *mask, int width, int height)
{
    if (!ws || !reference || !distorted || width <= 0 || height <= 0 || width > ws->max_width ||
        height > ws->max_height)
        return NAN;
    int dw = (width + 1) / 2, dh = (height + 1) / 2;
    average_downsample(reference, width, height, ws->down_ref);
    average_downsample(distorted, width, height, ws->down_dist);
    if (mask)
        downsample_mask(mask, width, height, ws->down_covered);
    size_t counted = 0;
    for (int i = 0; i < dh; i++) {
        for (int j = 0; j < dw; j++) {
            if (mask && !support_covered(ws->down_covered, dw, dh, i, j))
                continue;
            double m1 = prewitt_magnitude(ws->down_ref, dw, i, j);
            double m2 = prewitt_magnitude(ws->down_dist, dw, i, j);
            ws->gms[counted++] = (2.0 * m1 * m2 + GMSD_T) / (m1 * m1 + m2 * m2 + GMSD_T);
        }
    }
    return sample_deviation(ws->gms, counted);
}

struct texopt_gmsd_reference {
    int max_width, max_height, width, height;
    double *down; /* framed downsampled reference */
    unsigned char *down_covered;
    int *counted;       /* downsampled pixels entering the deviation, row-major, as offsets
                         * of their upper-left Prewitt neighbour in the framed image */
    int row_lo, row_hi; /* downsampled rows the counted pixels' gradients read */
    double *magnitude;  /* the reference's Prewitt magnitude at each of them */
    size_t count;
};

texopt_gmsd_reference *texopt_gmsd_reference_create(int max_width, int max_height)
{
    if (max_width <= 0 || max_height <= 0 || max_width > 65536 || max_height > 65536)
        return NULL;
    texopt_gmsd_reference *r = calloc(1, sizeof *r);
    if (!r)
        return NULL;
    size_t n = (size_t)((max_width + 1) / 2) * (size_t)((max_height + 1) / 2);
    size_t padded = (size_t)((max_width + 1) / 2 + 2) * (size_t)((max_height + 1) / 2 + 2);
    r->max_width = max_width;
    r->max_height = max_height;
    r->down = malloc(padded * sizeof *r->down);
    r->down_covered = malloc(n);
    r->counted = malloc(n * sizeof *r->counted);
    r->magnitude = malloc(n * sizeof *r->magnitude);
    if (!r->down || !r->down_covered || !r->counted || !r->magnitude) {
        texopt_gmsd_reference_destroy(r);
        return NULL;
    }
    return r;
}

void texopt_gmsd_reference_destroy(texopt_gmsd_reference *r)
{
    if (!r)
        return;
    free(r->down);
    free(r->down_covered);
    free(r->counted);
    free(r->magnitude);
    free(r);
}

int texopt_gmsd_reference_set(texopt_gmsd_reference *r, const float *reference, const unsigned char *mask, int width,
                              int height)
{
    if (!r || !reference || width <= 0 || height <= 0 || width > r->max_width || height > r->max_height)
        return 0;
    int dw = (width + 1) / 2, dh = (height + 1) / 2;
    r->width = width;
    r->height = height;
    average_downsample(reference, width, height, r->down);
    if (mask)
        downsample_mask(mask, width, height, r->down_covered);
    r->count = 0;
    for (int i = 0; i < dh; i++) {
        for (int j = 0; j < dw; j++) {
            if (mask && !support_covered(r->down_covered, dw, dh, i, j))
                continue;
            r->counted[r->count] = i * (dw + 2) + j;
            r->row_lo = r->count == 0 ? (i > 0 ? i - 1 : 0) : r->row_lo;
            r->row_hi = i + 1 < dh ? i + 1 : dh - 1;
            r->magnitude[r->count++] = prewitt_magnitude(r->down, dw, i, j);
        }
    }
    return 1;
}

double texopt_gmsd_against(texopt_gmsd_workspace *ws, const texopt_gmsd_reference *r, const float *distorted)
{
    if (!ws || !r || !distorted || r->width <= 0 || r->width > ws->max_width || r->height > ws->max_height)
        return NAN;
    int dw = (r->width + 1) / 2;
    if (r->count == 0)
        return 0.0;
    /* Only the rows the counted gradients read (frame rows included). */
    average_downsample_rows(distorted, r->width, r->height, ws->down_dist, r->row_lo, r->row_hi);
    /* Same operations in the same order as texopt_gmsd_ws, so the same bits. */
    for (size_t k = 0; k < r->count; k++) {
        double m1 = r->magnitude[k];
        double m2 = prewitt_at(ws->down_dist + r->counted[k], dw);
        ws->gms[k] = (2.0 * m1 * m2 + GMSD_T) / (m1 * m1 + m2 * m2 + GMSD_T);
    }
    return sample_deviation(ws->gms, r->count);
}

void texopt_gmsd_similarity_map(const texopt_gmsd_workspace *ws, const texopt_gmsd_reference *r, float *map)
{
    size_t n = (size_t)r->width * (size_t)r->height;
    for (size_t i = 0; i < n; i++)
        map[i] = -1.0f;
    int framed_width = (r->width + 1) / 2 + 2;
    for (size_t k = 0; k < r->count; k++) {
        /* counted[k] is the offset of the upper-left Prewitt neighbour, which in the framed
         * image is the downsampled pixel's own (row, column) position. */
        int i = r->counted[k] / framed_width, j = r->counted[k] % framed_width;
        for (int y = 2 * i; y < 2 * i + 2 && y < r->height; y++)
            for (int x = 2 * j; x < 2 * j + 2 && x < r->width; x++)
                map[(size_t)y * (size_t)r->width + (size_t)x] = (float)ws->gms[k];
    }
}

double texopt_gmsd(const float *reference, const float *distorted, const unsigned char *mask, int width, int height)
{
    if (width <= 0 || height <= 0)
        return NAN;
    texopt_gmsd_workspace *ws = texopt_gmsd_workspace_create(width, height);
    if (!ws)
        return NAN;
    double result = texopt_gmsd_ws(ws, reference, distorted, mask, width, height);
    texopt_gmsd_workspace_destroy(ws);
    return result;
}
