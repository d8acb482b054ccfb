/* test_sample.c - bilinear lookup: exactness on linear ramps, glTF wrap modes at edges. */
#include <stdlib.h>

#include "sample.h"
#include "test.h"

static texopt_image ramp_image(int w, int h, double a, double b, double c)
{
    texopt_image img;
    char err[128];
    if (texopt_image_create(&img, w, h, 2, err, sizeof err) != TEXOPT_OK)
        abort();
    for (int j = 0; j < h; j++) {
        for (int i = 0; i < w; i++) {
            float *p = texopt_image_at(&img, i, j);
            p[0] = (float)(a * (i + 0.5) + b * (j + 0.5) + c);
            p[1] = (float)((i + 0.5) * (j + 0.5) / (w * h)); /* bilinear: exact too */
        }
    }
    return img;
}

TEST(bilinear_is_exact_on_linear_ramps_between_texel_centres)
{
    texopt_image img = ramp_image(16, 9, 0.03, -0.05, 0.6);
    unsigned s = 1;
    for (int k = 0; k < 500; k++) {
        s = s * 1664525u + 1013904223u;
        double x = 0.5 + 15.0 * ((s >> 8) & 0xffff) / 65535.0;
        s = s * 1664525u + 1013904223u;
        double y = 0.5 + 8.0 * ((s >> 8) & 0xffff) / 65535.0;
        float out[2];
        texopt_sample_bilinear(&img, TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, x, y, out);
        CHECK_NEAR(out[0], 0.03 * x - 0.05 * y + 0.6, 2e-6);
        CHECK_NEAR(out[1], x * y / (16.0 * 9.0), 2e-6);
    }
    texopt_image_destroy(&img);
}

TEST(bilinear_at_texel_centre_returns_that_texel)
{
    texopt_image img = ramp_image(5, 4, 0.1, 0.2, 0.0);
    float out[2];
    texopt_sample_bilinear(&img, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 3.5, 2.5, out);
    CHECK(out[0] == texopt_image_at(&img, 3, 2)[0]);
    CHECK(out[1] == texopt_image_at(&img, 3, 2)[1]);
    texopt_image_destroy(&img);
}

/* The lookup written out from texopt_bilinear_footprint, the general (wrapping) path. */
static void lookup_through_footprint(const texopt_image *img, texopt_wrap wrap, double x, double y, float *out)
{
    int idx[4];
    double w[4];
    texopt_bilinear_footprint(img->width, img->height, wrap, wrap, x, y, idx, w);
    for (int c = 0; c < img->channels; c++) {
        double sum = 0.0;
        for (int k = 0; k < 4; k++)
            sum += w[k] * (double)img->pixels[(size_t)idx[k] * (size_t)img->channels + (size_t)c];
        out[c] = (float)sum;
    }
}

TEST(whole_periods_and_the_in_grid_path_give_the_same_bits)
{
    /* UVs beyond [0, 1] (DamagedHelmet's v lies in [1, 2]) are moved into the first period
     * and then read inside the grid: the same bits as the wrapping footprint at the original
     * position, for REPEAT (period 16) and MIRROR (period 32), inside and across the seams. */
    texopt_image img = ramp_image(16, 9, 0.37, -0.21, 0.6);
    for (int i = 0; i < img.width * img.height; i++)
        img.pixels[2 * i + 1] = (float)((i * 7919) % 101) / 101.0f; /* not bilinear */
    const texopt_wrap wraps[2] = {TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_MIRROR};
    unsigned s = 7;
    for (int m = 0; m < 2; m++) {
        int px = m ? 32 : 16, py = m ? 18 : 9;
        for (int k = 0; k < 400; k++) {
            /* anywhere in the first period (MIRROR's mirrored half too), in multiples of
             * 1/1024 so that adding whole periods is exact */
            s = s * 1664525u + 1013904223u;
            double x = (double)((s >> 8) % (unsigned)(px * 1024)) / 1024.0;
            s = s * 1664525u + 1013904223u;
            double y = (double)((s >> 8) % (unsigned)(py * 1024)) / 1024.0;
            float base[2], far[2], general[2];
            texopt_sample_bilinear(&img, wraps[m], wraps[m], x, y, base);
            lookup_through_footprint(&img, wraps[m], x, y, general);
            double fx = x + px * (1 + k % 3), fy = y + py * (3 - k % 3);
            texopt_sample_bilinear(&img, wraps[m], wraps[m], fx, fy, far);
            CHECK_MSG(base[0] == general[0] && base[1] == general[1], "(%g, %g)", x, y);
            CHECK_MSG(far[0] == base[0] && far[1] == base[1], "(%g, %g) vs (%g, %g)", fx, fy, x, y);
        }
    }
    texopt_image_destroy(&img);
}

static void footprint_x(texopt_wrap wrap, double x, int idx[4], double w[4])
{
    texopt_bilinear_footprint(4, 3, wrap, TEXOPT_WRAP_CLAMP, x, 1.5, idx, w);
}

TEST(wrap_modes_pick_the_gltf_texel_beyond_each_edge)
{
    int idx[4];
    double w[4];
    /* x = 0.25: a quarter texel left of texel 0's centre -> texel -1 with weight 0.25. */
    footprint_x(TEXOPT_WRAP_REPEAT, 0.25, idx, w);
    CHECK_EQ_INT(idx[0], 1 * 4 + 3);
    CHECK_EQ_INT(idx[1], 1 * 4 + 0);
    CHECK_NEAR(w[0], 0.25, 1e-15);
    CHECK_NEAR(w[1], 0.75, 1e-15);
    footprint_x(TEXOPT_WRAP_CLAMP, 0.25, idx, w);
    CHECK_EQ_INT(idx[0], 4);
    CHECK_EQ_INT(idx[1], 4);
    footprint_x(TEXOPT_WRAP_MIRROR, 0.25, idx, w);
    CHECK_EQ_INT(idx[0], 4);
    /* Right edge: texel 4. */
    footprint_x(TEXOPT_WRAP_REPEAT, 3.75, idx, w);
    CHECK_EQ_INT(idx[0], 4 + 3);
    CHECK_EQ_INT(idx[1], 4 + 0);
    CHECK_NEAR(w[1], 0.25, 1e-15);
    footprint_x(TEXOPT_WRAP_CLAMP, 3.75, idx, w);
    CHECK_EQ_INT(idx[1], 4 + 3);
    footprint_x(TEXOPT_WRAP_MIRROR, 3.75, idx, w);
    CHECK_EQ_INT(idx[1], 4 + 3);
    /* Further out: texel 5 mirrors to 2, texel -2 to 1; repeat gives 1 and 2. */
    footprint_x(TEXOPT_WRAP_MIRROR, 5.5, idx, w);
    CHECK_EQ_INT(idx[0], 4 + 2);
    CHECK_NEAR(w[0], 1.0, 1e-15);
    footprint_x(TEXOPT_WRAP_MIRROR, -1.5, idx, w);
    CHECK_EQ_INT(idx[0], 4 + 1);
    footprint_x(TEXOPT_WRAP_REPEAT, 5.5, idx, w);
    CHECK_EQ_INT(idx[0], 4 + 1);
    footprint_x(TEXOPT_WRAP_REPEAT, -1.5, idx, w);
    CHECK_EQ_INT(idx[0], 4 + 2);
    footprint_x(TEXOPT_WRAP_CLAMP, -7.0, idx, w);
    CHECK_EQ_INT(idx[0], 4);
    CHECK_EQ_INT(idx[1], 4);
    /* Rows wrap with wrap_t: y = 0.25 under REPEAT on 3 rows reaches row 2. */
    texopt_bilinear_footprint(4, 3, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_REPEAT, 1.5, 0.25, idx, w);
    CHECK_EQ_INT(idx[0], 2 * 4 + 1);
    CHECK_EQ_INT(idx[2], 0 * 4 + 1);
    CHECK_NEAR(w[0], 0.25, 1e-15);
}

TEST(footprints_stay_in_range_for_any_coordinate)
{
    const double xs[] = {-1e300, -123456.7, -0.5, 0.0, 0.49, 1e-300, 7.999, 1e9, 1e300, NAN, INFINITY};
    for (int wrap = 0; wrap < 3; wrap++) {
        for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++) {
            int idx[4];
            double w[4];
            texopt_bilinear_footprint(7, 5, (texopt_wrap)wrap, (texopt_wrap)wrap, xs[i], xs[(i + 3) % 11], idx, w);
            double sum = 0.0;
            for (int k = 0; k < 4; k++) {
                CHECK(idx[k] >= 0 && idx[k] < 35);
                CHECK(w[k] >= 0.0);
                sum += w[k];
            }
            CHECK_NEAR(sum, 1.0, 1e-12);
        }
    }
}

TEST(luma_uses_bt601_weights_and_first_channel_for_grey)
{
    const float rgb[4] = {1.0f, 0.0f, 0.0f, 0.3f};
    CHECK_NEAR(texopt_luma(rgb, 3), 0.299, 1e-7);
    const float g[3] = {0.0f, 1.0f, 0.0f};
    CHECK_NEAR(texopt_luma(g, 4 - 1), 0.587, 1e-7);
    const float b[4] = {0.0f, 0.0f, 1.0f, 1.0f};
    CHECK_NEAR(texopt_luma(b, 4), 0.114, 1e-7);
    const float grey[2] = {0.42f, 0.9f};
    CHECK(texopt_luma(grey, 2) == 0.42f);
    CHECK(texopt_luma(grey, 1) == 0.42f);
}
