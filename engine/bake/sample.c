/* sample.c - bilinear lookup in texel coordinates with glTF wrap modes (sample.h).
 * Implements the GL_LINEAR filter the glTF spec prescribes; no mipmapping, no colour
 * conversion. Weights feed the least-squares bake of Sun et al. 2022, eq. 11. */
#include "sample.h"

#include <math.h>

/* Beyond this, positions carry no sub-texel information in a double and floor() would
 * overflow an int; such lookups are clamped (they are bugs upstream, not crashes here). */
#define TEXOPT_SAMPLE_COORD_LIMIT 1.0e8

static int wrap_index(int i, int n, texopt_wrap wrap)
{
    if (i >= 0 && i < n) /* inside: every mode agrees, and the hot loops skip the modulo */
        return i;
    switch (wrap) {
    case TEXOPT_WRAP_CLAMP: return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case TEXOPT_WRAP_MIRROR: {
        int period = 2 * n;
        int m = i % period;
        if (m < 0)
            m += period;
        return m < n ? m : period - 1 - m;
    }
    case TEXOPT_WRAP_REPEAT:
    default: {
        int m = i % n;
        return m < 0 ? m + n : m;
    }
    }
}

/* floor() for |v| <= TEXOPT_SAMPLE_COORD_LIMIT: a truncation and a compare, where libm's
 * floor is a function call on baseline x86-64 (no SSE4.1 rounding) in the hot loop. */
static int floor_to_int(double v)
{
    int i = (int)v;
    return (double)i > v ? i - 1 : i;
}

static double sanitize_coordinate(double v)
{
    if (!isfinite(v))
        return 0.0;
    if (v > TEXOPT_SAMPLE_COORD_LIMIT)
        return TEXOPT_SAMPLE_COORD_LIMIT;
    if (v < -TEXOPT_SAMPLE_COORD_LIMIT)
        return -TEXOPT_SAMPLE_COORD_LIMIT;
    return v;
}

void texopt_bilinear_cells(int width, int height, texopt_wrap wrap_s, texopt_wrap wrap_t, double x, double y,
                           int col[2], int row[2], double weight[4])
{
    /* Texel centres sit at half-integers: shift so that they sit at integers. */
    double xs = sanitize_coordinate(x) - 0.5;
    double ys = sanitize_coordinate(y) - 0.5;
    int x0 = floor_to_int(xs), y0 = floor_to_int(ys);
    double fx = xs - x0, fy = ys - y0;
    col[0] = wrap_index(x0, width, wrap_s);
    col[1] = wrap_index(x0 + 1, width, wrap_s);
    row[0] = wrap_index(y0, height, wrap_t);
    row[1] = wrap_index(y0 + 1, height, wrap_t);
    weight[0] = (1.0 - fx) * (1.0 - fy);
    weight[1] = fx * (1.0 - fy);
    weight[2] = (1.0 - fx) * fy;
    weight[3] = fx * fy;
}

void texopt_bilinear_footprint(int width, int height, texopt_wrap wrap_s, texopt_wrap wrap_t, double x, double y,
                               int index[4], double weight[4])
{
    int col[2], row[2];
    texopt_bilinear_cells(width, height, wrap_s, wrap_t, x, y, col, row, weight);
    index[0] = row[0] * width + col[0];
    index[1] = row[0] * width + col[1];
    index[2] = row[1] * width + col[0];
    index[3] = row[1] * width + col[1];
}

/* x moved by whole periods of a repeating axis (REPEAT: n texels, MIRROR: 2n) into its first
 * period, when that is exact: for x >= k p with k = floor(x / p) >= 1, x - k p is exact
 * (Sterbenz: k p <= x < 2 k p), so the footprint's weights are the same bits and its texels
 * the same after wrapping. Anything else is returned as it is. Lookups on UVs beyond [0, 1]
 * (DamagedHelmet's v lies in [1, 2]) then take the in-grid path of texopt_sample_bilinear
 * instead of two integer divisions per lookup. */
static double into_first_period(double x, int n, texopt_wrap wrap)
{
    double period = wrap == TEXOPT_WRAP_REPEAT ? n : wrap == TEXOPT_WRAP_MIRROR ? 2.0 * n : 0.0;
    if (!(period > 0.0 && x >= period && x <= TEXOPT_SAMPLE_COORD_LIMIT))
        return x;
    double shifted = x - floor(x / period) * period;
    return shifted >= 0.0 && shifted < period ? shifted : x;
}

void texopt_sample_bilinear(const texopt_image *img, texopt_wrap ws, texopt_wrap wt, double x, double y, float *out)
{
    int index[4];
    double weight[4];
    int channels = img->channels, width = img->width;
    x = into_first_period(x, width, ws);
    y = into_first_period(y, img->height, wt);
    if (x >= 0.5 && y >= 0.5 && x < width - 0.5 && y < img->height - 0.5) {
        /* Inside the grid: texopt_bilinear_cells' arithmetic without its clamps and wraps
         * (xs, ys >= 0, so truncation is floor). */
        double xs = x - 0.5, ys = y - 0.5;
        int x0 = (int)xs, y0 = (int)ys;
        double fx = xs - x0, fy = ys - y0;
        index[0] = y0 * width + x0;
        index[1] = index[0] + 1;
        index[2] = index[0] + width;
        index[3] = index[2] + 1;
        weight[0] = (1.0 - fx) * (1.0 - fy);
        weight[1] = fx * (1.0 - fy);
        weight[2] = (1.0 - fx) * fy;
        weight[3] = fx * fy;
    } else {
        texopt_bilinear_footprint(width, img->height, ws, wt, x, y, index, weight);
    }
    for (int c = 0; c < channels; c++) {
        double sum = 0.0;
        for (int k = 0; k < 4; k++)
            sum += weight[k] * (double)img->pixels[(size_t)index[k] * (size_t)channels + (size_t)c];
        out[c] = (float)sum;
    }
}

float texopt_luma(const float *rgb, int channels)
{
    if (channels >= 3)
        return 0.299f * rgb[0] + 0.587f * rgb[1] + 0.114f * rgb[2];
    return rgb[0];
}
