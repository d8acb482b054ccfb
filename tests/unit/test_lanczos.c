/* test_lanczos.c - the Lanczos-3 resize against Pillow's (tests/vectors/lanczos_vectors.py),
 * its identity, its edges on a constant image, and threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "lanczos.h"
#include "test.h"

#define VECTORS TEXOPT_SOURCE_DIR "/tests/vectors/lanczos_vectors.txt"

/* Pillow rounds to 8 bits after each pass, the engine does not: the intermediate's rounding
 * (half a code, through weights whose absolute values add up to about 1.3) plus the final
 * one bound the difference by about 1.2 codes, and the final rounding alone averages a
 * quarter code. Measured: at most 1.06 codes, mean 0.12-0.29 over the six sizes; a kernel
 * not stretched on downsizing, two lobes, or windows off by half a texel miss by 22-210. */
#define MAX_CODE_DIFFERENCE 1.25
#define MEAN_CODE_DIFFERENCE 0.35

static int read_image(FILE *f, texopt_image *img, int w, int h)
{
    char err[256];
    if (texopt_image_create(img, w, h, 3, err, sizeof err) != TEXOPT_OK)
        return 0;
    for (size_t i = 0; i < (size_t)w * h * 3; i++) {
        int code;
        if (fscanf(f, "%d", &code) != 1)
            return 0;
        img->pixels[i] = (float)code / 255.0f;
    }
    return 1;
}

TEST(lanczos_matches_pillow_within_its_8_bit_rounding)
{
    FILE *f = fopen(VECTORS, "r");
    CHECK_MSG(f != NULL, "cannot open %s", VECTORS);
    char line[512], err[256];
    CHECK(fgets(line, sizeof line, f) != NULL); /* header comment */
    int w, h, cases = 0;
    texopt_image in = {0};
    CHECK(fscanf(f, "%d %d", &w, &h) == 2 && read_image(f, &in, w, h));
    while (fscanf(f, "%d %d", &w, &h) == 2) {
        texopt_image pillow = {0}, ours = {0};
        CHECK(read_image(f, &pillow, w, h));
        CHECK_OK(texopt_image_create(&ours, w, h, 3, err, sizeof err), err);
        CHECK_OK(texopt_lanczos_resize(&in, &ours, 2, err, sizeof err), err);
        double max = 0, sum = 0;
        size_t n = (size_t)w * h * 3;
        for (size_t i = 0; i < n; i++) {
            double d = fabs(255.0 * ours.pixels[i] - 255.0 * pillow.pixels[i]);
            max = fmax(max, d);
            sum += d;
        }
        CHECK_MSG(max <= MAX_CODE_DIFFERENCE && sum / n <= MEAN_CODE_DIFFERENCE,
                  "%dx%d: max %.3f, mean %.3f codes from Pillow", w, h, max, sum / n);
        texopt_image_destroy(&pillow);
        texopt_image_destroy(&ours);
        cases++;
    }
    fclose(f);
    texopt_image_destroy(&in);
    CHECK(cases >= 6);
}

static void fill(texopt_image *img, unsigned seed)
{
    for (size_t i = 0; i < (size_t)img->width * img->height * img->channels; i++) {
        seed = seed * 1664525u + 1013904223u;
        img->pixels[i] = (float)((seed >> 8) & 0xffff) / 65535.0f;
    }
}

TEST(lanczos_at_the_same_size_is_the_identity)
{
    char err[256];
    texopt_image in = {0}, out = {0};
    CHECK_OK(texopt_image_create(&in, 23, 17, 4, err, sizeof err), err);
    CHECK_OK(texopt_image_create(&out, 23, 17, 4, err, sizeof err), err);
    fill(&in, 5);
    CHECK_OK(texopt_lanczos_resize(&in, &out, 1, err, sizeof err), err);
    for (size_t i = 0; i < (size_t)23 * 17 * 4; i++)
        CHECK_NEAR(out.pixels[i], in.pixels[i], 1e-6);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}

/* Cut windows are renormalised: a constant stays constant up to the edges, both ways. */
TEST(lanczos_keeps_a_constant_to_the_edges)
{
    char err[256];
    const int sizes[][2] = {{7, 5}, {90, 3}, {1, 1}};
    texopt_image in = {0};
    CHECK_OK(texopt_image_create(&in, 31, 19, 2, err, sizeof err), err);
    for (size_t i = 0; i < (size_t)31 * 19 * 2; i++)
        in.pixels[i] = i % 2 ? 0.25f : 0.75f;
    for (int s = 0; s < 3; s++) {
        texopt_image out = {0};
        CHECK_OK(texopt_image_create(&out, sizes[s][0], sizes[s][1], 2, err, sizeof err), err);
        CHECK_OK(texopt_lanczos_resize(&in, &out, 1, err, sizeof err), err);
        for (size_t i = 0; i < (size_t)sizes[s][0] * sizes[s][1] * 2; i++)
            CHECK_NEAR(out.pixels[i], i % 2 ? 0.25 : 0.75, 1e-6);
        texopt_image_destroy(&out);
    }
    texopt_image_destroy(&in);
}

TEST(lanczos_gives_the_same_result_with_any_number_of_threads)
{
    char err[256];
    texopt_image in = {0}, a = {0}, b = {0};
    CHECK_OK(texopt_image_create(&in, 64, 48, 3, err, sizeof err), err);
    CHECK_OK(texopt_image_create(&a, 21, 37, 3, err, sizeof err), err);
    CHECK_OK(texopt_image_create(&b, 21, 37, 3, err, sizeof err), err);
    fill(&in, 9);
    CHECK_OK(texopt_lanczos_resize(&in, &a, 1, err, sizeof err), err);
    CHECK_OK(texopt_lanczos_resize(&in, &b, 3, err, sizeof err), err);
    for (size_t i = 0; i < (size_t)21 * 37 * 3; i++)
        CHECK(a.pixels[i] == b.pixels[i]);
    texopt_image_destroy(&in);
    texopt_image_destroy(&a);
    texopt_image_destroy(&b);
}

TEST(lanczos_refuses_a_destination_of_other_channels)
{
    char err[256];
    texopt_image in = {0}, out = {0};
    CHECK_OK(texopt_image_create(&in, 4, 4, 3, err, sizeof err), err);
    CHECK_OK(texopt_image_create(&out, 2, 2, 4, err, sizeof err), err);
    CHECK(texopt_lanczos_resize(&in, &out, 1, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_image_destroy(&in);
    texopt_image_destroy(&out);
}
