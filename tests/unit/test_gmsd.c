/* test_gmsd.c - GMSD against vectors from an independent numpy implementation of the
 * reference (tests/vectors/gmsd_vectors.py), identity, and the mask rule. */
#include <stdlib.h>
#include <string.h>

#include "gmsd.h"
#include "test.h"

#define VECTORS TEXOPT_SOURCE_DIR "/tests/vectors/gmsd_vectors.txt"

static int read_codes(FILE *f, float *img, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        int code;
        if (fscanf(f, "%d", &code) != 1)
            return 0;
        img[i] = (float)code / 255.0f;
    }
    return 1;
}

static int read_mask(FILE *f, unsigned char *mask, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        int v;
        if (fscanf(f, "%d", &v) != 1)
            return 0;
        mask[i] = (unsigned char)v;
    }
    return 1;
}

TEST(gmsd_matches_numpy_reference_vectors)
{
    FILE *f = fopen(VECTORS, "r");
    CHECK_MSG(f != NULL, "cannot open %s", VECTORS);
    char line[512];
    CHECK(fgets(line, sizeof line, f) != NULL); /* header comment */
    int cases = 0, masked = 0;
    char name[128];
    int w, h, has_mask;
    double expected;
    while (fscanf(f, "%127s %d %d %d %lf", name, &w, &h, &has_mask, &expected) == 5) {
        size_t n = (size_t)w * (size_t)h;
        float *ref = malloc(n * sizeof *ref), *dist = malloc(n * sizeof *dist);
        unsigned char *mask = malloc(n);
        int ok = ref && dist && mask && read_codes(f, ref, n) && read_codes(f, dist, n) &&
                 (!has_mask || read_mask(f, mask, n));
        double got = ok ? texopt_gmsd(ref, dist, has_mask ? mask : NULL, w, h) : NAN;
        free(ref);
        free(dist);
        free(mask);
        if (!ok)
            fclose(f);
        CHECK_MSG(ok, "vector %s: truncated", name);
        if (!(fabs(got - expected) <= 1e-6)) {
            fclose(f);
            CHECK_MSG(0, "vector %s: %.12g, numpy %.12g", name, got, expected);
        }
        cases++;
        masked += has_mask;
    }
    fclose(f);
    CHECK(cases >= 20);
    CHECK(masked >= 5);
}

static void fill_pattern(float *img, int w, int h, unsigned seed)
{
    for (int i = 0; i < w * h; i++) {
        seed = seed * 1664525u + 1013904223u;
        img[i] = (float)((seed >> 8) & 0xffff) / 65535.0f;
    }
}

TEST(gmsd_of_an_image_with_itself_is_exactly_zero)
{
    enum { W = 64, H = 64 };
    static float img[W * H];
    fill_pattern(img, W, H, 7);
    CHECK(texopt_gmsd(img, img, NULL, W, H) == 0.0);
    unsigned char mask[W * H];
    for (int i = 0; i < W * H; i++)
        mask[i] = (unsigned char)((i % W) > 10);
    CHECK(texopt_gmsd(img, img, mask, W, H) == 0.0);
}

/* A hand-checkable case: a vertical step edge. Downsampled 4x4 of 8x8; the GMS map is 1
 * wherever both gradients agree, and a uniform brightness change does not move it. */
TEST(gmsd_constant_offset_away_from_borders_is_small_but_not_zero_at_borders)
{
    enum { W = 8, H = 8 };
    float a[W * H], b[W * H];
    for (int i = 0; i < W * H; i++) {
        a[i] = 0.5f;
        b[i] = 0.6f;
    }
    /* Zero padding makes the borders edges of height 0.5 vs 0.6: the interior GMS is 1,
     * the border GMS is (2*0.5*0.6 s^2 + T)/((0.25+0.36) s^2 + T) < 1, so GMSD > 0. */
    double g = texopt_gmsd(a, b, NULL, W, H);
    CHECK(g > 1e-3);
    CHECK(g < 0.1);
}

TEST(gmsd_all_covered_mask_equals_no_mask)
{
    enum { W = 33, H = 21 };
    float a[W * H], b[W * H];
    unsigned char mask[W * H];
    fill_pattern(a, W, H, 3);
    fill_pattern(b, W, H, 4);
    memset(mask, 1, sizeof mask);
    CHECK(texopt_gmsd(a, b, mask, W, H) == texopt_gmsd(a, b, NULL, W, H));
}

TEST(gmsd_ignores_whatever_uncovered_pixels_hold)
{
    enum { W = 40, H = 40 };
    float a[W * H], b[W * H], b2[W * H];
    unsigned char mask[W * H];
    fill_pattern(a, W, H, 11);
    for (int i = 0; i < W * H; i++)
        b[i] = 0.8f * a[i] + 0.1f;
    memcpy(b2, b, sizeof b);
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            int covered = (x - 20) * (x - 20) + (y - 20) * (y - 20) < 15 * 15;
            mask[y * W + x] = (unsigned char)covered;
            if (!covered)
                b2[y * W + x] = (x + y) % 2 ? 1.0f : 0.0f; /* loud checkerboard */
        }
    }
    double g1 = texopt_gmsd(a, b, mask, W, H), g2 = texopt_gmsd(a, b2, mask, W, H);
    CHECK(g1 > 0.0);
    CHECK(g1 == g2);
    /* Without the mask the checkerboard dominates. */
    CHECK(texopt_gmsd(a, b2, NULL, W, H) > 2.0 * g1);
}

TEST(gmsd_workspace_reuse_and_bad_arguments)
{
    enum { W = 30, H = 30 };
    float a[W * H], b[W * H];
    fill_pattern(a, W, H, 5);
    fill_pattern(b, W, H, 6);
    texopt_gmsd_workspace *ws = texopt_gmsd_workspace_create(W, H);
    CHECK(ws != NULL);
    double first = texopt_gmsd_ws(ws, a, b, NULL, W, H);
    double smaller = texopt_gmsd_ws(ws, a, b, NULL, 17, 9);
    double again = texopt_gmsd_ws(ws, a, b, NULL, W, H);
    CHECK(first == again);
    CHECK(smaller == texopt_gmsd(a, b, NULL, 17, 9));
    CHECK(isnan(texopt_gmsd_ws(ws, a, b, NULL, W + 1, H)));
    CHECK(isnan(texopt_gmsd_ws(ws, NULL, b, NULL, W, H)));
    CHECK(isnan(texopt_gmsd(a, b, NULL, 0, H)));
    texopt_gmsd_workspace_destroy(ws);
    texopt_gmsd_workspace_destroy(NULL);
    CHECK(texopt_gmsd_workspace_create(0, 4) == NULL);
}

/* The prepared reference gives texopt_gmsd_ws's value bit for bit, for several distorted
 * images against one reference, with and without a mask, odd sizes, and after re-preparing
 * a smaller image. */
/* Even sizes (the stage's 64x64 screen) take the whole-block downsampling, and the prepared
 * side downsamples only the rows its counted pixels read: a mask over the middle rows and a
 * workspace left holding another image must still give gmsd_ws's bits. */
TEST(prepared_reference_on_even_sizes_reads_only_fresh_rows)
{
    enum { W = 40, H = 36 };
    float a[W * H], b[W * H], c[W * H];
    unsigned char mask[W * H];
    fill_pattern(a, W, H, 41);
    fill_pattern(b, W, H, 42);
    fill_pattern(c, W, H, 43);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            mask[y * W + x] = (unsigned char)((x - 21) * (x - 21) + (y - 18) * (y - 18) < 9 * 9);
    texopt_gmsd_workspace *ws = texopt_gmsd_workspace_create(W, H);
    texopt_gmsd_workspace *fresh = texopt_gmsd_workspace_create(W, H);
    texopt_gmsd_reference *ref = texopt_gmsd_reference_create(W, H);
    CHECK(ws != NULL && fresh != NULL && ref != NULL);
    CHECK(texopt_gmsd_reference_set(ref, a, mask, W, H));
    double expect = texopt_gmsd_ws(fresh, a, b, mask, W, H);
    CHECK(expect > 0.0);
    CHECK(texopt_gmsd_ws(ws, c, c, NULL, W, H) == 0.0); /* leaves c's rows in ws */
    CHECK(texopt_gmsd_against(ws, ref, b) == expect);
    CHECK(texopt_gmsd_against(ws, ref, a) == 0.0);
    texopt_gmsd_reference_destroy(ref);
    texopt_gmsd_workspace_destroy(ws);
    texopt_gmsd_workspace_destroy(fresh);
}

TEST(prepared_reference_equals_gmsd_ws_exactly)
{
    enum { W = 41, H = 37 };
    float a[W * H], b[W * H];
    unsigned char mask[W * H];
    fill_pattern(a, W, H, 21);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            mask[y * W + x] = (unsigned char)((x - 19) * (x - 19) + (y - 17) * (y - 17) < 16 * 16);
    texopt_gmsd_workspace *ws = texopt_gmsd_workspace_create(W, H);
    texopt_gmsd_reference *ref = texopt_gmsd_reference_create(W, H);
    CHECK(ws != NULL && ref != NULL);
    for (int masked = 0; masked < 2; masked++) {
        const unsigned char *m = masked ? mask : NULL;
        CHECK(texopt_gmsd_reference_set(ref, a, m, W, H));
        for (int seed = 22; seed < 26; seed++) {
            fill_pattern(b, W, H, seed);
            double expect = texopt_gmsd_ws(ws, a, b, m, W, H);
            CHECK(expect > 0.0);
            CHECK(texopt_gmsd_against(ws, ref, b) == expect);
        }
        CHECK(texopt_gmsd_against(ws, ref, a) == 0.0);
    }
    CHECK(texopt_gmsd_reference_set(ref, a, mask, 17, 9));
    fill_pattern(b, W, H, 30);
    CHECK(texopt_gmsd_against(ws, ref, b) == texopt_gmsd_ws(ws, a, b, mask, 17, 9));
    CHECK(!texopt_gmsd_reference_set(ref, a, mask, W + 1, H));
    CHECK(!texopt_gmsd_reference_set(ref, NULL, mask, W, H));
    CHECK(isnan(texopt_gmsd_against(ws, ref, NULL)));
    CHECK(texopt_gmsd_reference_create(0, 3) == NULL);
    texopt_gmsd_reference_destroy(ref);
    texopt_gmsd_reference_destroy(NULL);
    texopt_gmsd_workspace_destroy(ws);
}

/* The similarity map holds the values GMSD deviates over: one per downsampled pixel that
 * counts, repeated over its 2 x 2 source pixels, -1 elsewhere; 1 where nothing changed. */
TEST(similarity_map_holds_the_counted_gms_values)
{
    enum { W = 41, H = 37 };
    float a[W * H], b[W * H], map[W * H];
    unsigned char mask[W * H];
    fill_pattern(a, W, H, 21);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            mask[y * W + x] = (unsigned char)((x - 19) * (x - 19) + (y - 17) * (y - 17) < 16 * 16);
            b[y * W + x] = x < 16 ? a[y * W + x] * 0.5f : a[y * W + x]; /* only the left part changes */
        }
    texopt_gmsd_workspace *ws = texopt_gmsd_workspace_create(W, H);
    texopt_gmsd_reference *ref = texopt_gmsd_reference_create(W, H);
    CHECK(ws != NULL && ref != NULL);
    CHECK(texopt_gmsd_reference_set(ref, a, mask, W, H));
    double g = texopt_gmsd_against(ws, ref, b);
    texopt_gmsd_similarity_map(ws, ref, map);
    double values[(W + 1) / 2 * ((H + 1) / 2)], sum = 0;
    size_t n = 0, changed = 0;
    for (int i = 0; 2 * i < H; i++)
        for (int j = 0; 2 * j < W; j++) {
            float v = map[2 * i * W + 2 * j];
            for (int y = 2 * i; y < 2 * i + 2 && y < H; y++)
                for (int x = 2 * j; x < 2 * j + 2 && x < W; x++) {
                    CHECK(map[y * W + x] == v);
                    CHECK(mask[y * W + x] || v == -1.0f); /* an uncovered pixel never counts */
                }
            if (v == -1.0f)
                continue;
            CHECK(v > 0.0f && v <= 1.0f + 1e-6f);
            if (2 * j >= 16 + 4) /* the Prewitt support does not reach the change */
                CHECK_NEAR(v, 1.0, 1e-6);
            changed += v < 0.99f;
            values[n++] = v;
            sum += v;
        }
    CHECK(n > 100 && changed > 20);
    double mean = sum / (double)n, ss = 0;
    for (size_t k = 0; k < n; k++)
        ss += (values[k] - mean) * (values[k] - mean);
    CHECK_NEAR(sqrt(ss / (double)(n - 1)), g, 1e-6);
    CHECK(texopt_gmsd_against(ws, ref, a) == 0.0);
    texopt_gmsd_similarity_map(ws, ref, map);
    for (int k = 0; k < W * H; k++)
        CHECK(map[k] == -1.0f || map[k] == 1.0f);
    texopt_gmsd_reference_destroy(ref);
    texopt_gmsd_workspace_destroy(ws);
}
