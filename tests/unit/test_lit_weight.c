/* test_lit_weight.c - how much of each texture signal the lit render shows (lit_weight.h), on
 * a generated quad: base colour alone weighs 1; channels the light does not read weigh 0 and
 * a factor of 0 hides its channel; emission shows more than base colour on a matte surface; a
 * flat normal map's tilts show and its length does not; the weights repeat. */
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "lit_weight.h"
#include "test.h"

#define TEX 32

static double *weights_of(const texopt_model *m)
{
    char err[256] = "";
    double *w = m ? malloc((size_t)m->image_count * TEXOPT_LIT_WEIGHT_STRIDE * sizeof *w) : NULL;
    if (w && texopt_lit_signal_weights(m, w, err, sizeof err) != TEXOPT_OK) {
        printf("  weights: %s\n", err);
        free(w);
        return NULL;
    }
    return w;
}

/* weights_of(m), then m destroyed. */
static double *weights_of_taken(texopt_model *m)
{
    double *w = weights_of(m);
    texopt_model_destroy(m);
    return w;
}

static void fill_rgb(texopt_image *img, float r, float g, float b)
{
    for (size_t i = 0; i < (size_t)img->width * (size_t)img->height; i++) {
        img->pixels[3 * i] = r;
        img->pixels[3 * i + 1] = g;
        img->pixels[3 * i + 2] = b;
    }
}

/* A grey, rough dielectric quad (image 0) with one more image bound to `slot` (image 1),
 * filled with (r, g, b). */
static texopt_model *quad_with(texopt_slot slot, float r, float g, float b)
{
    texopt_model *m = fixture_textured_quad(TEX, "flat");
    texopt_image *img = m ? fixture_add_slot_image(m, slot, TEX) : NULL;
    if (!img) {
        texopt_model_destroy(m);
        return NULL;
    }
    fill_rgb(img, r, g, b);
    fill_rgb(&m->images[0], 0.5f, 0.5f, 0.5f);
    m->materials[0].metallic_factor = 0.0;
    m->materials[0].roughness_factor = 1.0;
    return m;
}

TEST(base_colour_alone_weighs_one)
{
    double *w = weights_of_taken(fixture_textured_quad(TEX, "checker"));
    CHECK(w);
    for (int k = 0; k < TEXOPT_LIT_WEIGHT_STRIDE; k++)
        CHECK(w[k] == 1.0);
    free(w);
}

TEST(unread_channels_weigh_zero_and_a_zero_factor_hides_its_channel)
{
    /* Metallic-roughness reads B and G, never R; with roughnessFactor 0 the map's G is
     * multiplied away, with metallicFactor 1 its B shows. */
    texopt_model *m = quad_with(TEXOPT_SLOT_METALLIC_ROUGHNESS, 0.3f, 0.5f, 0.5f);
    CHECK(m);
    m->materials[0].metallic_factor = 1.0;
    m->materials[0].roughness_factor = 0.0;
    double *w = weights_of_taken(m);
    CHECK(w);
    const double *mr = w + TEXOPT_LIT_WEIGHT_STRIDE;
    printf("  metallic-roughness R %.4f G %.4f B %.4f\n", mr[1], mr[2], mr[3]);
    CHECK(mr[1] == 0.0);
    CHECK(mr[2] == 0.0);
    CHECK_MSG(mr[3] > 0.05, "metallic B weighs %g", mr[3]); /* measured 0.39 */
    free(w);

    /* Occlusion reads R only. */
    w = weights_of_taken(quad_with(TEXOPT_SLOT_OCCLUSION, 0.8f, 0.8f, 0.8f));
    CHECK(w);
    const double *occ = w + TEXOPT_LIT_WEIGHT_STRIDE;
    printf("  occlusion R %.4f G %.4f B %.4f\n", occ[1], occ[2], occ[3]);
    CHECK(occ[1] > 0.3); /* dL/docclusion is L before occlusion, about the grey's shading */
    CHECK(occ[2] == 0.0 && occ[3] == 0.0);
    free(w);
}

TEST(emission_shows_more_than_base_colour_on_a_matte_surface)
{
    /* L = b (0.3 + 0.7 max(0, n.l)) + ... + e: one unit of emission is one unit of L, one
     * unit of base colour at most one and on average less. */
    double *w = weights_of_taken(quad_with(TEXOPT_SLOT_EMISSIVE, 0.0f, 0.0f, 0.0f));
    CHECK(w);
    double emissive = w[TEXOPT_LIT_WEIGHT_STRIDE];
    printf("  emissive luma %.4f\n", emissive);
    CHECK_MSG(emissive > 1.1 && emissive < 3.4, "emissive weighs %g", emissive); /* measured 1.54 */
    CHECK(w[0] > 0.95 && w[0] < 1.05); /* the base colour image: 1 by definition */
    free(w);
}

TEST(a_flat_normal_map_shows_its_tilts_not_its_length)
{
    double *w = weights_of_taken(quad_with(TEXOPT_SLOT_NORMAL, 0.5f, 0.5f, 1.0f));
    CHECK(w);
    const double *n = w + TEXOPT_LIT_WEIGHT_STRIDE;
    printf("  normal x %.4f y %.4f z %.6f\n", n[1], n[2], n[3]);
    CHECK(n[1] > 0.2 && n[2] > 0.2);
    CHECK(n[3] < 1e-9); /* renormalised: a longer (0, 0, z) is the same normal */
    /* No preferred direction about the normal: x and y alike to sampling noise. */
    CHECK_NEAR(n[1] / n[2], 1.0, 0.1);
    free(w);
}

TEST(weights_repeat_bit_for_bit)
{
    texopt_model *m = quad_with(TEXOPT_SLOT_NORMAL, 0.5f, 0.5f, 1.0f);
    CHECK(m);
    fixture_fill_normal_map(&m->images[1]);
    double *a = weights_of(m), *b = weights_of(m);
    CHECK(a && b);
    CHECK(memcmp(a, b, (size_t)m->image_count * TEXOPT_LIT_WEIGHT_STRIDE * sizeof *a) == 0);
    free(a);
    free(b);
    texopt_model_destroy(m);
}

TEST(lit_weights_refuse_missing_arguments)
{
    char err[256] = "";
    double w[TEXOPT_LIT_WEIGHT_STRIDE];
    CHECK_EQ_INT(texopt_lit_signal_weights(NULL, w, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    texopt_model *m = fixture_textured_quad(TEX, "flat");
    CHECK(m);
    CHECK_EQ_INT(texopt_lit_signal_weights(m, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    texopt_model_destroy(m);
}
