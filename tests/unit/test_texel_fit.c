/* Tests of texel_fit.c: texels recovered from their own bilinear sub-texel samples, fixed
 * texels kept, thread-count independence, clamping, argument checks. Images generated here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "texel_fit.h"

static float noise(int x, int y, int c)
{
    unsigned v = (unsigned)(x * 73856093u) ^ (unsigned)(y * 19349663u) ^ (unsigned)(c * 83492791u);
    v = v * 2654435761u;
    return (float)((v >> 8) & 0xffff) / 65535.0f;
}

/* Bilinear value of img at texel position (px, py) (centres at i + 0.5), no wrapping. */
static double bilinear(const texopt_image *img, double px, double py, int c)
{
    double fx = px - 0.5, fy = py - 0.5;
    int x0 = (int)floor(fx), y0 = (int)floor(fy);
    double tx = fx - x0, ty = fy - y0;
    return (1 - tx) * (1 - ty) * texopt_image_at(img, x0, y0)[c] + tx * (1 - ty) * texopt_image_at(img, x0 + 1, y0)[c] +
           (1 - tx) * ty * texopt_image_at(img, x0, y0 + 1)[c] + tx * ty * texopt_image_at(img, x0 + 1, y0 + 1)[c];
}

/* References of every texel whose samples stay inside the image: truth seen bilinearly at
 * the four sub-texel points; sampled marks them. */
static float *references_of(const texopt_image *truth, uint8_t *sampled)
{
    int w = truth->width, h = truth->height, ch = truth->channels;
    float *ref = calloc((size_t)w * h * TEXOPT_TEXEL_FIT_SAMPLES * ch, sizeof *ref);
    if (!ref)
        return NULL;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            sampled[(size_t)y * w + x] = 1;
            for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES; s++) {
                double px = x + 0.25 + 0.5 * (s & 1), py = y + 0.25 + 0.5 * (s >> 1);
                if (px < 0.5 || py < 0.5 || px > w - 0.5 || py > h - 0.5)
                    continue; /* the fit ignores these samples: their taps leave the image */
                for (int c = 0; c < ch; c++)
                    ref[((size_t)y * w + x) * TEXOPT_TEXEL_FIT_SAMPLES * ch + (size_t)s * ch + c] =
                        (float)bilinear(truth, px, py, c);
            }
        }
    return ref;
}

/* The fit's reference callback over a table made by references_of. */
typedef struct table {
    const float *ref;
    int width, channels;
} table;

static void table_reference(void *user, int x, int y, float *out)
{
    const table *t = user;
    size_t per = TEXOPT_TEXEL_FIT_SAMPLES * (size_t)t->channels;
    memcpy(out, t->ref + ((size_t)y * t->width + x) * per, per * sizeof *out);
}

static int make_noise(texopt_image *img, int w, int h, int ch)
{
    if (texopt_image_create(img, w, h, ch, NULL, 0) != TEXOPT_OK)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < ch; c++)
                texopt_image_at(img, x, y)[c] = noise(x, y, c);
    return 0;
}

static void fill(texopt_image *img, float v)
{
    for (size_t i = 0; i < (size_t)img->width * img->height * img->channels; i++)
        img->pixels[i] = v;
}

TEST(fit_recovers_texels_from_their_bilinear_samples)
{
    texopt_image truth, x;
    CHECK(make_noise(&truth, 24, 20, 2) == 0);
    CHECK(make_noise(&x, 24, 20, 2) == 0);
    fill(&x, 0.5f); /* start far from the answer */
    uint8_t sampled[24 * 20];
    float *ref = references_of(&truth, sampled);
    CHECK(ref != NULL);
    table tab = {ref, 24, 2};
    texopt_texel_fit_problem pb = {.image = &x,
                                   .sampled = sampled,
                                   .reference = table_reference,
                                   .user = &tab,
                                   .ridge = 1e-7,
                                   .tolerance = 1e-7,
                                   .max_iterations = 300,
                                   .threads = 2};
    texopt_texel_fit_report rep;
    char err[256] = "";
    CHECK_OK(texopt_texel_fit(&pb, NULL, &rep, err, sizeof err), err);
    CHECK_EQ_INT(rep.unknowns, 24 * 20);
    CHECK(rep.iterations > 1);
    double max_err = 0;
    for (size_t i = 0; i < (size_t)24 * 20 * 2; i++)
        max_err = fmax(max_err, fabs(x.pixels[i] - truth.pixels[i]));
    CHECK_MSG(max_err < 1e-3, "max error %g", max_err);
    free(ref);
    texopt_image_destroy(&truth);
    texopt_image_destroy(&x);
}

TEST(fixed_texels_keep_their_values_and_threads_do_not_change_the_result)
{
    texopt_image truth, a, b;
    CHECK(make_noise(&truth, 33, 21, 3) == 0);
    CHECK(make_noise(&a, 33, 21, 3) == 0);
    CHECK(make_noise(&b, 33, 21, 3) == 0);
    fill(&a, 0.25f);
    fill(&b, 0.25f);
    uint8_t sampled[33 * 21], fixed[33 * 21], changed[33 * 21];
    float *ref = references_of(&truth, sampled);
    CHECK(ref != NULL);
    for (int i = 0; i < 33 * 21; i++) {
        fixed[i] = (i % 33) < 10;   /* left columns fixed */
        sampled[i] = (i / 33) < 15; /* bottom rows have no samples */
    }
    memset(changed, 0, sizeof changed);
    table tab = {ref, 33, 3};
    texopt_texel_fit_problem pb = {.image = &a,
                                   .sampled = sampled,
                                   .reference = table_reference,
                                   .user = &tab,
                                   .fixed = fixed,
                                   .ridge = 1e-3,
                                   .tolerance = 1e-4,
                                   .max_iterations = 100,
                                   .threads = 1};
    char err[256] = "";
    CHECK_OK(texopt_texel_fit(&pb, changed, NULL, err, sizeof err), err);
    pb.image = &b;
    pb.threads = 4;
    CHECK_OK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err), err);
    CHECK(memcmp(a.pixels, b.pixels, sizeof(float) * 33 * 21 * 3) == 0);
    for (int y = 0; y < 21; y++)
        for (int x = 0; x < 33; x++) {
            const float *v = texopt_image_at(&a, x, y);
            int i = y * 33 + x;
            if (x < 10 || y > 15) { /* fixed, or beyond the rows any sample touches */
                CHECK(changed[i] == 0);
                CHECK(v[0] == 0.25f && v[1] == 0.25f && v[2] == 0.25f);
            } else {
                CHECK(changed[i] == 1);
            }
        }
    /* Well inside the free, sampled part the fit approaches the truth. */
    CHECK_NEAR(texopt_image_at(&a, 20, 7)[1], texopt_image_at(&truth, 20, 7)[1], 0.02);
    free(ref);
    texopt_image_destroy(&truth);
    texopt_image_destroy(&a);
    texopt_image_destroy(&b);
}

TEST(fit_clamps_to_the_unit_range)
{
    texopt_image x;
    CHECK(texopt_image_create(&x, 8, 8, 1, NULL, 0) == TEXOPT_OK);
    fill(&x, 0.5f);
    uint8_t sampled[64];
    float ref[64 * TEXOPT_TEXEL_FIT_SAMPLES];
    memset(sampled, 1, sizeof sampled);
    for (int i = 0; i < 64 * TEXOPT_TEXEL_FIT_SAMPLES; i++)
        ref[i] = 1.5f;
    table tab = {ref, 8, 1};
    texopt_texel_fit_problem pb = {.image = &x,
                                   .sampled = sampled,
                                   .reference = table_reference,
                                   .user = &tab,
                                   .ridge = 1e-3,
                                   .tolerance = 1e-6,
                                   .max_iterations = 100,
                                   .threads = 1};
    char err[256] = "";
    CHECK_OK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err), err);
    for (int i = 0; i < 64; i++)
        CHECK(x.pixels[i] == 1.0f);
    texopt_image_destroy(&x);
}

TEST(fit_refuses_bad_arguments)
{
    texopt_image x;
    CHECK(texopt_image_create(&x, 4, 4, 1, NULL, 0) == TEXOPT_OK);
    uint8_t sampled[16] = {0};
    texopt_texel_fit_problem pb = {.image = &x,
                                   .sampled = sampled,
                                   .reference = table_reference,
                                   .ridge = 0,
                                   .tolerance = 1e-3,
                                   .max_iterations = 10,
                                   .threads = 1};
    char err[256] = "";
    CHECK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "ridge") != NULL);
    pb.ridge = 1e-3;
    pb.reference = NULL;
    CHECK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_texel_fit(NULL, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_image_destroy(&x);
}

TEST(fit_does_not_depend_on_what_freed_memory_held)
{
    /* The CG buffers come from malloc: blocks of their size freed full of NaN just before
     * (the allocator hands them out again) must not change the result. */
    texopt_image truth, a, b;
    CHECK(make_noise(&truth, 20, 12, 3) == 0);
    CHECK(make_noise(&a, 20, 12, 3) == 0);
    CHECK(make_noise(&b, 20, 12, 3) == 0);
    fill(&a, 0.5f);
    fill(&b, 0.5f);
    uint8_t sampled[20 * 12];
    float *ref = references_of(&truth, sampled);
    CHECK(ref != NULL);
    table tab = {ref, 20, 3};
    texopt_texel_fit_problem pb = {.image = &a,
                                   .sampled = sampled,
                                   .reference = table_reference,
                                   .user = &tab,
                                   .ridge = 1e-3,
                                   .tolerance = 1e-3,
                                   .max_iterations = 50,
                                   .threads = 1};
    char err[256] = "";
    CHECK_OK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err), err);
    float *junk[8];
    for (int k = 0; k < 8; k++) {
        junk[k] = malloc(20 * 12 * 3 * sizeof(float));
        CHECK(junk[k] != NULL);
        for (int i = 0; i < 20 * 12 * 3; i++)
            junk[k][i] = NAN;
    }
    for (int k = 0; k < 8; k++)
        free(junk[k]);
    pb.image = &b;
    CHECK_OK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err), err);
    CHECK(memcmp(a.pixels, b.pixels, sizeof(float) * 20 * 12 * 3) == 0);
    free(ref);
    texopt_image_destroy(&truth);
    texopt_image_destroy(&a);
    texopt_image_destroy(&b);
}

/* References of a sharp step (0.2 left of x = 8.4 texels, 0.8 right of it), point-sampled:
 * no bilinear texel image reproduces it, and the least-squares fit overshoots on both sides. */
static void step_reference(void *user, int x, int y, float *out)
{
    (void)user;
    (void)y;
    for (int s = 0; s < TEXOPT_TEXEL_FIT_SAMPLES; s++)
        out[s] = x + 0.25 + 0.5 * (s & 1) < 8.4 ? 0.2f : 0.8f;
}

static void step_range(void *user, int x, int y, float *lo, float *hi)
{
    (void)user;
    (void)x;
    (void)y;
    lo[0] = 0.2f;
    hi[0] = 0.8f;
}

/* The fit of the step into a 16 x 8 one-channel image started at 0.5; its extreme values. */
static void fit_step(int bounded, float *lowest, float *highest)
{
    texopt_image x;
    uint8_t sampled[16 * 8];
    memset(sampled, 1, sizeof sampled);
    CHECK(texopt_image_create(&x, 16, 8, 1, NULL, 0) == TEXOPT_OK);
    for (int i = 0; i < 16 * 8; i++)
        x.pixels[i] = 0.5f;
    texopt_texel_fit_problem pb = {.image = &x,
                                   .sampled = sampled,
                                   .reference = step_reference,
                                   .range = bounded ? step_range : NULL,
                                   .ridge = 1e-3,
                                   .tolerance = 1e-4,
                                   .max_iterations = 100,
                                   .threads = 2};
    char err[256] = "";
    CHECK_OK(texopt_texel_fit(&pb, NULL, NULL, err, sizeof err), err);
    *lowest = 1, *highest = 0;
    for (int y = 2; y < 6; y++) /* away from the image's edges, where samples do not count */
        for (int i = 2; i < 14; i++) {
            float v = texopt_image_at(&x, i, y)[0];
            *lowest = v < *lowest ? v : *lowest;
            *highest = v > *highest ? v : *highest;
        }
    texopt_image_destroy(&x);
}

TEST(range_bounds_keep_a_sharp_step_from_ringing)
{
    float lo, hi;
    fit_step(0, &lo, &hi);
    CHECK_MSG(lo < 0.2f - 2.0f / 255 && hi > 0.8f + 2.0f / 255, "unbounded fit %g..%g does not ring", lo, hi);
    fit_step(1, &lo, &hi);
    CHECK_MSG(lo >= 0.2f - 1.0f / 255 && hi <= 0.8f + 1.0f / 255, "bounded fit %g..%g", lo, hi);
    CHECK(lo < 0.21f && hi > 0.79f); /* still both levels, not a blur */
}
