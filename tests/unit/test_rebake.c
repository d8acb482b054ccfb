/* Tests of rebake.c, texture_filter.c and dilate.c: exact reproduction under the identity,
 * prefiltering on reduction, normal-map rotation, gutters. Images are generated in code. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dilate.h"
#include "rebake.h"
#include "test.h"
#include "texture_filter.h"

/* A pseudo-random image with detail at every texel (hash of x, y, c). */
static int make_noise(texopt_image *img, int w, int h, int ch)
{
    if (texopt_image_create(img, w, h, ch, NULL, 0) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < ch; c++) {
                unsigned v = (unsigned)(x * 73856093u) ^ (unsigned)(y * 19349663u) ^ (unsigned)(c * 83492791u);
                v = v * 2654435761u;
                texopt_image_at(img, x, y)[c] = (float)((v >> 8) & 0xffff) / 65535.0f;
            }
    return 0;
}

/* Texel checkerboard: squares of `side` texels, 0 and 1. */
static int make_checker(texopt_image *img, int w, int h, int side)
{
    if (texopt_image_create(img, w, h, 1, NULL, 0) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            texopt_image_at(img, x, y)[0] = (float)(((x / side) + (y / side)) & 1);
    return 0;
}

static const uint32_t quad_tris[6] = {0, 1, 2, 0, 2, 3};
static const double unit_quad[8] = {0, 0, 1, 0, 1, 1, 0, 1};

static double image_mean(const texopt_image *img, int c)
{
    double s = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            s += texopt_image_at(img, x, y)[c];
    return s / ((double)img->width * img->height);
}

TEST(identity_layout_reproduces_texture_exactly)
{
    texopt_image in, out;
    CHECK(make_noise(&in, 37, 29, 3) == 0);
    CHECK(texopt_image_create(&out, 37, 29, 3, NULL, 0) == TEXOPT_OK);
    texopt_rebake_layout layout = {2, quad_tris, unit_quad, unit_quad, 1};
    char err[256] = "";
    size_t covered = 0;
    CHECK_OK(texopt_rebake_image(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 0, &layout, &out, &covered, NULL, err,
                                 sizeof err),
             err);
    CHECK_EQ_INT(covered, 37 * 29);
    double max_err = 0;
    for (size_t i = 0; i < (size_t)37 * 29 * 3; i++)
        max_err = fmax(max_err, fabs(in.pixels[i] - out.pixels[i]));
    CHECK(max_err < 1e-6);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(half_size_prefiltered_bake_of_texel_checker_is_grey)
{
    /* A one-texel checker reduced 2x: point sampling would give pure black or white,
     * a box prefilter gives 0.5 everywhere. */
    texopt_image in, out;
    CHECK(make_checker(&in, 64, 64, 1) == 0);
    CHECK(texopt_image_create(&out, 32, 32, 1, NULL, 0) == TEXOPT_OK);
    texopt_rebake_layout layout = {2, quad_tris, unit_quad, unit_quad, 1};
    char err[256] = "";
    CHECK_OK(texopt_rebake_image_fit(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 0, &layout,
                                     TEXOPT_REBAKE_FIT_PREFILTER, &out, NULL, NULL, err, sizeof err),
             err);
    double lo = 1, hi = 0;
    for (int i = 0; i < 32 * 32; i++) {
        lo = fmin(lo, out.pixels[i]);
        hi = fmax(hi, out.pixels[i]);
    }
    CHECK_NEAR(lo, 0.5, 1e-6);
    CHECK_NEAR(hi, 0.5, 1e-6);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(coarse_checker_reduction_keeps_edges_and_mean)
{
    /* 8-texel squares reduced 2x are 4-texel squares of pure 0 and 1: the filter must not
     * blur across the square edges that stay texel-aligned, and the mean stays 0.5. */
    texopt_image in, out;
    CHECK(make_checker(&in, 64, 64, 8) == 0);
    CHECK(texopt_image_create(&out, 32, 32, 1, NULL, 0) == TEXOPT_OK);
    char err[256] = "";
    CHECK_OK(texopt_texture_resize(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, &out, 2, err, sizeof err), err);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++)
            CHECK_NEAR(texopt_image_at(&out, x, y)[0], (float)(((x / 4) + (y / 4)) & 1), 1e-6);
    CHECK_NEAR(image_mean(&out, 0), 0.5, 1e-9);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

/* A horizontal ramp: each texel holds the level-0 position of its centre, x + 0.5. */
static int make_ramp(texopt_image *img, int w, int h)
{
    if (texopt_image_create(img, w, h, 1, NULL, 0) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            texopt_image_at(img, x, y)[0] = (float)x + 0.5f;
    return 0;
}

TEST(odd_sided_mip_levels_stay_where_level_zero_is)
{
    /* A box filter keeps a ramp's value at its centre, so a prefiltered lookup of the ramp
     * at x reads x at every level. 229 texels halve to 115, 58, 29: a plain 2 x 2 pairing of
     * the odd sides read at x * w_l / w_0 drifts by 2.6 texels at x = 197 on levels 2-3. */
    texopt_image ramp;
    CHECK(make_ramp(&ramp, 229, 5) == 0);
    texopt_texture_filter *f = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texture_filter_create(&f, &ramp, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, err, sizeof err), err);
    const double footprints[3] = {2, 4, 6};
    double worst = 0;
    for (int k = 0; k < 3; k++) {
        const double j[4] = {footprints[k], 0, 0, footprints[k]};
        for (double x = 32; x <= 197; x += 0.75) {
            float v;
            texopt_texture_filter_sample(f, x, 2.5, j, &v);
            worst = fmax(worst, fabs(v - x));
        }
    }
    CHECK_MSG(worst < 0.05, "worst offset %.3f texels", worst);
    texopt_texture_filter_destroy(f);
    texopt_image_destroy(&ramp);
}

TEST(even_sided_mip_level_is_the_exact_two_by_two_mean)
{
    /* Read at its own texel centres with a footprint of two texels, level 1 of an even-sided
     * image is the mean of each 2 x 2 block, to the last bit of float. */
    texopt_image img;
    CHECK(make_noise(&img, 10, 6, 2) == 0);
    texopt_texture_filter *f = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texture_filter_create(&f, &img, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, err, sizeof err), err);
    const double j[4] = {2, 0, 0, 2};
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++) {
            float v[2];
            texopt_texture_filter_sample(f, 2 * x + 1, 2 * y + 1, j, v);
            for (int c = 0; c < 2; c++) {
                float want =
                    0.25f *
                    (texopt_image_at(&img, 2 * x, 2 * y)[c] + texopt_image_at(&img, 2 * x + 1, 2 * y)[c] +
                     texopt_image_at(&img, 2 * x, 2 * y + 1)[c] + texopt_image_at(&img, 2 * x + 1, 2 * y + 1)[c]);
                CHECK_MSG(v[c] == want, "texel %d,%d channel %d: %.9g, want %.9g", x, y, c, v[c], want);
            }
        }
    texopt_texture_filter_destroy(f);
    texopt_image_destroy(&img);
}

TEST(odd_sided_resize_keeps_a_ramp_in_place)
{
    /* The "input" method's resize of a texture with odd sides, 4x smaller on both axes (so
     * levels 2 and 3 are read): each new texel holds the ramp at its own centre. */
    texopt_image ramp, out;
    CHECK(make_ramp(&ramp, 229, 229) == 0);
    CHECK(texopt_image_create(&out, 57, 57, 1, NULL, 0) == TEXOPT_OK);
    char err[256] = "";
    CHECK_OK(texopt_texture_resize(&ramp, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, &out, 1, err, sizeof err), err);
    double worst = 0;
    for (int x = 4; x < 53; x++)
        worst = fmax(worst, fabs(texopt_image_at(&out, x, 28)[0] - (x + 0.5) * 229.0 / 57.0));
    CHECK_MSG(worst < 0.05, "worst offset %.3f texels", worst);
    texopt_image_destroy(&ramp);
    texopt_image_destroy(&out);
}

TEST(anisotropic_reduction_averages_along_the_squeezed_axis)
{
    /* Vertical one-texel stripes squeezed 4x in x only: every output texel is grey; a
     * horizontal-stripe image squeezed the same way keeps its stripes (no blur along y). */
    texopt_image in, out;
    CHECK(texopt_image_create(&in, 64, 16, 1, NULL, 0) == TEXOPT_OK);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 64; x++)
            texopt_image_at(&in, x, y)[0] = (float)(x & 1);
    CHECK(texopt_image_create(&out, 16, 16, 1, NULL, 0) == TEXOPT_OK);
    char err[256] = "";
    CHECK_OK(texopt_texture_resize(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, &out, 2, err, sizeof err), err);
    for (int i = 0; i < 16 * 16; i++)
        CHECK_NEAR(out.pixels[i], 0.5, 1e-6);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 64; x++)
            texopt_image_at(&in, x, y)[0] = (float)(y & 1);
    CHECK_OK(texopt_texture_resize(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, &out, 2, err, sizeof err), err);
    for (int y = 0; y < 16; y++)
        CHECK_NEAR(texopt_image_at(&out, 5, y)[0], (float)(y & 1), 1e-6);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(wrap_modes_decide_lookups_outside_the_texture)
{
    /* A 4x1 ramp read through UVs shifted by one whole texture: REPEAT reads the same texels,
     * CLAMP reads the last column everywhere. */
    texopt_image in, out;
    CHECK(texopt_image_create(&in, 4, 1, 1, NULL, 0) == TEXOPT_OK);
    for (int x = 0; x < 4; x++)
        in.pixels[x] = 0.1f + 0.2f * x;
    CHECK(texopt_image_create(&out, 4, 1, 1, NULL, 0) == TEXOPT_OK);
    const double shifted[8] = {1, 0, 2, 0, 2, 1, 1, 1};
    texopt_rebake_layout layout = {2, quad_tris, shifted, unit_quad, 1};
    char err[256] = "";
    CHECK_OK(
        texopt_rebake_image(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_CLAMP, 0, &layout, &out, NULL, NULL, err, sizeof err),
        err);
    for (int x = 0; x < 4; x++)
        CHECK_NEAR(out.pixels[x], in.pixels[x], 1e-6);
    CHECK_OK(
        texopt_rebake_image(&in, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 0, &layout, &out, NULL, NULL, err, sizeof err),
        err);
    for (int x = 0; x < 4; x++)
        CHECK_NEAR(out.pixels[x], in.pixels[3], 1e-6);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(quarter_turn_rotates_normal_map_xy)
{
    /* The output layout turns the quad by +90 degrees in the image frame (x right, y down):
     * input corner (u, v) goes to (1 - v, u). A normal tilted towards +u (map X = 1) now
     * tilts towards output +y, which is map -Y. */
    texopt_image in, out;
    CHECK(texopt_image_create(&in, 8, 8, 3, NULL, 0) == TEXOPT_OK);
    for (int i = 0; i < 64; i++) {
        in.pixels[3 * i] = 1.0f;     /* X = +1 */
        in.pixels[3 * i + 1] = 0.5f; /* Y = 0 */
        in.pixels[3 * i + 2] = 0.5f;
    }
    CHECK(texopt_image_create(&out, 8, 8, 3, NULL, 0) == TEXOPT_OK);
    const double turned[8] = {1, 0, 1, 1, 0, 1, 0, 0};
    texopt_rebake_layout layout = {2, quad_tris, unit_quad, turned, 1};
    char err[256] = "";
    CHECK_OK(
        texopt_rebake_image(&in, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 1, &layout, &out, NULL, NULL, err, sizeof err),
        err);
    const float *p = texopt_image_at(&out, 3, 4);
    CHECK_NEAR(p[0], 0.5, 1e-6);
    CHECK_NEAR(p[1], 0.0, 1e-6);
    CHECK_NEAR(p[2], 0.5, 1e-6);
    /* The same bake without the normal flag copies the values. */
    CHECK_OK(
        texopt_rebake_image(&in, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 0, &layout, &out, NULL, NULL, err, sizeof err),
        err);
    CHECK_NEAR(texopt_image_at(&out, 3, 4)[0], 1.0, 1e-6);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(gutter_takes_the_colour_of_the_nearest_chart)
{
    /* Two small charts of flat colours in a 32x32 output: every texel ends up with one of
     * the two colours, and texels next to each chart carry that chart's colour. */
    texopt_image in, out;
    CHECK(texopt_image_create(&in, 16, 16, 1, NULL, 0) == TEXOPT_OK);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++)
            texopt_image_at(&in, x, y)[0] = x < 8 ? 0.2f : 0.9f;
    const double uv_in[16] = {0.1, 0.1, 0.4, 0.1, 0.4, 0.9, 0.1, 0.9, 0.6, 0.1, 0.9, 0.1, 0.9, 0.9, 0.6, 0.9};
    const double uv_out[16] = {0.1, 0.1, 0.3, 0.1, 0.3, 0.4, 0.1, 0.4, 0.6, 0.6, 0.9, 0.6, 0.9, 0.9, 0.6, 0.9};
    const uint32_t tris[12] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    texopt_rebake_layout layout = {4, tris, uv_in, uv_out, 1};
    CHECK(texopt_image_create(&out, 32, 32, 1, NULL, 0) == TEXOPT_OK);
    char err[256] = "";
    CHECK_OK(
        texopt_rebake_image(&in, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 0, &layout, &out, NULL, NULL, err, sizeof err),
        err);
    CHECK_NEAR(texopt_image_at(&out, 1, 1)[0], 0.2, 1e-6);   /* outside chart 1, near it */
    CHECK_NEAR(texopt_image_at(&out, 10, 14)[0], 0.2, 1e-6); /* just past chart 1's corner */
    CHECK_NEAR(texopt_image_at(&out, 30, 30)[0], 0.9, 1e-6); /* near chart 2 */
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(dilate_fills_rings_from_covered_texels_only)
{
    texopt_image img;
    CHECK(texopt_image_create(&img, 5, 1, 1, NULL, 0) == TEXOPT_OK);
    uint8_t covered[5] = {1, 0, 0, 0, 1};
    img.pixels[0] = 0.0f;
    img.pixels[4] = 1.0f;
    img.pixels[2] = 123.0f; /* garbage in an uncovered texel must not leak */
    char err[128] = "";
    CHECK_OK(texopt_dilate(&img, covered, 1, err, sizeof err), err);
    CHECK_NEAR(img.pixels[1], 0.0, 0);
    CHECK_NEAR(img.pixels[3], 1.0, 0);
    CHECK(covered[2] == 0);
    CHECK_OK(texopt_dilate(&img, covered, 0, err, sizeof err), err);
    CHECK_NEAR(img.pixels[2], 0.5, 1e-7);
    CHECK(covered[2] == 1);
    texopt_image_destroy(&img);
}

TEST(rebake_refuses_mismatched_channels)
{
    texopt_image in, out;
    CHECK(texopt_image_create(&in, 4, 4, 3, NULL, 0) == TEXOPT_OK);
    CHECK(texopt_image_create(&out, 4, 4, 4, NULL, 0) == TEXOPT_OK);
    texopt_rebake_layout layout = {2, quad_tris, unit_quad, unit_quad, 1};
    char err[256] = "";
    CHECK(texopt_rebake_image(&in, 0, 0, 0, &layout, &out, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "channels") != NULL);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

TEST(threaded_bake_equals_single_threaded_bake)
{
    /* A layout that turns, squeezes and splits the texture into two charts: the result must
     * not depend on how rows are shared among workers. */
    texopt_image in, a, b;
    CHECK(make_noise(&in, 64, 48, 4) == 0);
    CHECK(texopt_image_create(&a, 40, 33, 4, NULL, 0) == TEXOPT_OK);
    CHECK(texopt_image_create(&b, 40, 33, 4, NULL, 0) == TEXOPT_OK);
    const double uv_in[16] = {0, 0, 0.5, 0, 0.5, 1, 0, 1, 0.5, 0, 1, 0, 1, 1, 0.5, 1};
    const double uv_out[16] = {0.05, 0.05, 0.45, 0.05, 0.45, 0.9, 0.05, 0.9, 0.9, 0.1, 0.9, 0.5, 0.55, 0.5, 0.55, 0.1};
    const uint32_t tris[12] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    texopt_rebake_layout one = {4, tris, uv_in, uv_out, 1}, three = {4, tris, uv_in, uv_out, 3};
    char err[256] = "";
    size_t ca = 0, cb = 0;
    CHECK_OK(texopt_rebake_image(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 1, &one, &a, &ca, NULL, err, sizeof err),
             err);
    CHECK_OK(
        texopt_rebake_image(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 1, &three, &b, &cb, NULL, err, sizeof err),
        err);
    CHECK_EQ_INT(ca, cb);
    CHECK(ca > 500);
    CHECK(memcmp(a.pixels, b.pixels, sizeof(float) * 40 * 33 * 4) == 0);
    texopt_image_destroy(&in);
    texopt_image_destroy(&a);
    texopt_image_destroy(&b);
}

/* RMS over interior input positions (4x4 per input texel) of the input seen bilinearly
 * against the output seen bilinearly where the layout puts the same point: what a renderer
 * shows against what the input showed. */
static double bilinear1(const texopt_image *img, double px, double py)
{
    px -= 0.5;
    py -= 0.5;
    int x0 = (int)floor(px), y0 = (int)floor(py);
    double tx = px - x0, ty = py - y0;
    return (1 - tx) * (1 - ty) * texopt_image_at(img, x0, y0)[0] + tx * (1 - ty) * texopt_image_at(img, x0 + 1, y0)[0] +
           (1 - tx) * ty * texopt_image_at(img, x0, y0 + 1)[0] + tx * ty * texopt_image_at(img, x0 + 1, y0 + 1)[0];
}

static double render_error(const texopt_image *in, const texopt_image *out, double scale, double shift)
{
    double sum = 0;
    int n = 0;
    for (double y = 2; y < in->height - 2; y += 0.25)
        for (double x = 2; x < in->width - 2; x += 0.25) {
            double d = bilinear1(out, shift + scale * x, shift + scale * y) - bilinear1(in, x, y);
            sum += d * d;
            n++;
        }
    return sqrt(sum / n);
}

/* Bakes `in` into `layout` twice, read through `wrap` on both axes: prefiltered into *pre and
 * with `fit` into *fitted (both allocated by the caller). */
static texopt_status bake_prefiltered_and(texopt_rebake_fit fit, const texopt_image *in, texopt_wrap wrap,
                                          const texopt_rebake_layout *layout, texopt_image *pre, texopt_image *fitted,
                                          char *err, size_t err_len)
{
    texopt_status st =
        texopt_rebake_image_fit(in, wrap, wrap, 0, layout, TEXOPT_REBAKE_FIT_PREFILTER, pre, NULL, NULL, err, err_len);
    return st != TEXOPT_OK ? st
                           : texopt_rebake_image_fit(in, wrap, wrap, 0, layout, fit, fitted, NULL, NULL, err, err_len);
}

TEST(least_squares_bake_undoes_the_second_bilinear_blur)
{
    /* The input moved by half a texel (every output centre falls between two input centres),
     * then also magnified 1.5x: the prefiltered bake interpolates the input once and the
     * renderer a second time; the fitted texels must reproduce the input more closely. */
    const double scale[2] = {1.0, 1.5};
    for (int k = 0; k < 2; k++) {
        texopt_image in, pre, fit;
        int side = (int)ceil(32 * scale[k]) + 8;
        CHECK(make_noise(&in, 32, 32, 1) == 0);
        CHECK(texopt_image_create(&pre, side, side, 1, NULL, 0) == TEXOPT_OK);
        CHECK(texopt_image_create(&fit, side, side, 1, NULL, 0) == TEXOPT_OK);
        double shift = 4.5, uv_out[8];
        for (int i = 0; i < 8; i++)
            uv_out[i] = (shift + 32 * scale[k] * unit_quad[i]) / side;
        texopt_rebake_layout layout = {2, quad_tris, unit_quad, uv_out, 2};
        char err[256] = "";
        CHECK_OK(bake_prefiltered_and(TEXOPT_REBAKE_FIT_LEAST_SQUARES, &in, TEXOPT_WRAP_CLAMP, &layout, &pre, &fit, err,
                                      sizeof err),
                 err);
        double e_pre = render_error(&in, &pre, scale[k], shift), e_fit = render_error(&in, &fit, scale[k], shift);
        /* Measured 0.110 vs 0.122 at 1:1 (white noise at the input's texel scale cannot be
         * held by a grid half a texel off) and 0.042 vs 0.061 at 1.5x. */
        CHECK_MSG(e_fit < (k == 0 ? 0.95 : 0.8) * e_pre, "scale %g: fitted %g, prefiltered %g", scale[k], e_fit, e_pre);
        for (int i = 0; i < side * side; i++)
            CHECK(fit.pixels[i] >= 0.0f && fit.pixels[i] <= 1.0f);
        texopt_image_destroy(&in);
        texopt_image_destroy(&pre);
        texopt_image_destroy(&fit);
    }
}

/* A smooth pattern, cos(2 pi x / 8) cos(2 pi y / 8) around 0.5: at half size 4 output texels
 * per period, half the output's Nyquist frequency, detail a half-size texture can hold. */
#define TWO_PI 6.283185307179586

static int make_waves(texopt_image *img, int w, int h)
{
    if (texopt_image_create(img, w, h, 1, NULL, 0) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            texopt_image_at(img, x, y)[0] =
                (float)(0.5 + 0.4 * cos(TWO_PI * (x + 0.5) / 8) * cos(TWO_PI * (y + 0.5) / 8));
    return 0;
}

TEST(least_squares_reduction_keeps_detail_the_output_can_hold)
{
    /* Reduced 2x, the fit's references are the input itself at the output's sub-texel points
     * (half an output texel's footprint: one input texel). With references averaged over a
     * whole output texel, the fit matched the box-blurred input and gave the prefiltered bake
     * back: render error 0.072 for both, against 0.049 with the half footprint. */
    texopt_image in, pre, fit;
    CHECK(make_waves(&in, 64, 64) == 0);
    CHECK(texopt_image_create(&pre, 32, 32, 1, NULL, 0) == TEXOPT_OK);
    CHECK(texopt_image_create(&fit, 32, 32, 1, NULL, 0) == TEXOPT_OK);
    texopt_rebake_layout layout = {2, quad_tris, unit_quad, unit_quad, 1};
    char err[256] = "";
    CHECK_OK(bake_prefiltered_and(TEXOPT_REBAKE_FIT_LEAST_SQUARES, &in, TEXOPT_WRAP_REPEAT, &layout, &pre, &fit, err,
                                  sizeof err),
             err);
    double e_pre = render_error(&in, &pre, 0.5, 0), e_fit = render_error(&in, &fit, 0.5, 0);
    CHECK_MSG(e_fit < 0.8 * e_pre, "fitted %g, prefiltered %g", e_fit, e_pre);
    texopt_image_destroy(&in);
    texopt_image_destroy(&pre);
    texopt_image_destroy(&fit);
}

TEST(magnified_fit_leaves_shrunk_triangles_prefiltered)
{
    /* Two charts: the left half of the input shrunk to half size, the right half magnified.
     * MAGNIFIED fits only the right chart; the left chart equals the prefiltered bake. */
    texopt_image in, pre, mag;
    CHECK(make_noise(&in, 32, 32, 1) == 0);
    CHECK(texopt_image_create(&pre, 64, 48, 1, NULL, 0) == TEXOPT_OK);
    CHECK(texopt_image_create(&mag, 64, 48, 1, NULL, 0) == TEXOPT_OK);
    const double uv_in[16] = {0, 0, 0.5, 0, 0.5, 1, 0, 1, 0.5, 0, 1, 0, 1, 1, 0.5, 1};
    const double uv_out[16] = {4 / 64.,    4 / 48.,    12 / 64.,   4 / 48.,   12 / 64.,   20 / 48.,
                               4 / 64.,    20 / 48.,   20.5 / 64., 4.5 / 48., 44.5 / 64., 4.5 / 48.,
                               44.5 / 64., 44.5 / 48., 20.5 / 64., 44.5 / 48.};
    const uint32_t tris[12] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    texopt_rebake_layout layout = {4, tris, uv_in, uv_out, 1};
    char err[256] = "";
    CHECK_OK(
        bake_prefiltered_and(TEXOPT_REBAKE_FIT_MAGNIFIED, &in, TEXOPT_WRAP_CLAMP, &layout, &pre, &mag, err, sizeof err),
        err);
    int same_left = 1, differs_right = 0;
    for (int y = 4; y < 20; y++)
        for (int x = 4; x < 12; x++)
            same_left &= texopt_image_at(&pre, x, y)[0] == texopt_image_at(&mag, x, y)[0];
    for (int y = 6; y < 42; y++)
        for (int x = 22; x < 42; x++)
            differs_right += fabsf(texopt_image_at(&pre, x, y)[0] - texopt_image_at(&mag, x, y)[0]) > 1e-3f;
    CHECK(same_left);
    CHECK(differs_right > 100);
    texopt_image_destroy(&in);
    texopt_image_destroy(&pre);
    texopt_image_destroy(&mag);
}

TEST(anisotropic_footprint_follows_its_direction)
{
    /* Diagonal stripes 8 texels wide (constant along (1, 1), alternating along (1, -1)); a
     * footprint 12 texels long and 1 wide averages along its long axis: along the stripes it
     * keeps the stripe's value, across them it gives the mean. */
    texopt_image in;
    CHECK(texopt_image_create(&in, 64, 64, 1, NULL, 0) == TEXOPT_OK);
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++)
            texopt_image_at(&in, x, y)[0] = (float)((((x - y) % 16 + 16) % 16) < 8);
    texopt_texture_filter *f = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texture_filter_create(&f, &in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, err, sizeof err), err);
    double a = 12, b = 1;
    /* J = R diag(a, b) R^T with R the 45-degree rotation: long axis along (1, 1). */
    const double along[4] = {0.5 * (a + b), 0.5 * (a - b), 0.5 * (a - b), 0.5 * (a + b)};
    const double across[4] = {0.5 * (a + b), -0.5 * (a - b), -0.5 * (a - b), 0.5 * (a + b)};
    float v_along, v_across;
    /* (36, 32): x - y = 4, the middle of a stripe of ones. */
    texopt_texture_filter_sample(f, 36.5, 32.5, along, &v_along);
    texopt_texture_filter_sample(f, 36.5, 32.5, across, &v_across);
    CHECK(v_along > 0.85f);
    CHECK_NEAR(v_across, 0.5, 0.15);
    texopt_texture_filter_destroy(f);
    texopt_image_destroy(&in);
}

TEST(least_squares_bake_of_tiny_outputs_stays_defined)
{
    /* At 1x1 no sub-texel sample has its four bilinear taps inside the image: the fit has no
     * unknowns and leaves the prefiltered bake as it is. At 2x2 only the inner samples count:
     * the result must still be finite and in [0, 1]. */
    for (int side = 1; side <= 2; side++) {
        texopt_image in, pre, fit;
        CHECK(make_noise(&in, 16, 16, 3) == 0);
        CHECK(texopt_image_create(&pre, side, side, 3, NULL, 0) == TEXOPT_OK);
        CHECK(texopt_image_create(&fit, side, side, 3, NULL, 0) == TEXOPT_OK);
        texopt_rebake_layout layout = {2, quad_tris, unit_quad, unit_quad, 2};
        char err[256] = "";
        CHECK_OK(texopt_rebake_image_fit(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 0, &layout,
                                         TEXOPT_REBAKE_FIT_PREFILTER, &pre, NULL, NULL, err, sizeof err),
                 err);
        CHECK_OK(texopt_rebake_image(&in, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, 0, &layout, &fit, NULL, NULL, err,
                                     sizeof err),
                 err);
        if (side == 1)
            CHECK(memcmp(pre.pixels, fit.pixels, sizeof(float) * 3) == 0);
        for (int i = 0; i < 3 * side * side; i++)
            CHECK(isfinite(fit.pixels[i]) && fit.pixels[i] >= 0.0f && fit.pixels[i] <= 1.0f);
        texopt_image_destroy(&in);
        texopt_image_destroy(&pre);
        texopt_image_destroy(&fit);
    }
}

TEST(filter_range_reads_every_tap_of_the_box_through_the_wrap)
{
    texopt_image img;
    CHECK(texopt_image_create(&img, 8, 8, 1, NULL, 0) == TEXOPT_OK);
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++)
            texopt_image_at(&img, x, y)[0] = x == 0 ? 1.0f : (x == 3 ? 0.25f : 0.5f);
    char err[256] = "";
    texopt_texture_filter *repeat = NULL, *clamp = NULL;
    CHECK_OK(texopt_texture_filter_create(&repeat, &img, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, err, sizeof err), err);
    CHECK_OK(texopt_texture_filter_create(&clamp, &img, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, err, sizeof err), err);
    float lo, hi;
    /* Past the last centre a lookup blends column 7 with column 0 (repeat) or with itself. */
    texopt_texture_filter_range(repeat, 7.6, 4.0, 0.05, 0.05, &lo, &hi);
    CHECK(lo == 0.5f && hi == 1.0f);
    texopt_texture_filter_range(clamp, 7.6, 4.0, 0.05, 0.05, &lo, &hi);
    CHECK(lo == 0.5f && hi == 0.5f);
    /* A box reaching column 3's centre's neighbourhood holds its 0.25. */
    texopt_texture_filter_range(clamp, 5.0, 4.0, 1.2, 0.0, &lo, &hi);
    CHECK(lo == 0.25f && hi == 0.5f);
    texopt_texture_filter_range(clamp, 5.5, 4.0, 1.0, 0.0, &lo, &hi);
    CHECK(lo == 0.5f && hi == 0.5f);
    texopt_texture_filter_destroy(repeat);
    texopt_texture_filter_destroy(clamp);
    texopt_image_destroy(&img);
}
