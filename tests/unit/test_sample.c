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
            texopt_bilinear_footprint(7, 5, (texopt_wrap)wrap, (texopt_wrap)wrap, xs[i],
                                      xs[(i + 3) % 11], idx, w);
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
