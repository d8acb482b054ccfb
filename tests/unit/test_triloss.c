/* test_triloss.c - the one-ring perceptual loss of a candidate Jacobian. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "lit_weight.h"
#include "mesh.h"
#include "test.h"
#include "triloss.h"

#define PI 3.14159265358979323846

typedef struct loss_fixture {
    texopt_model *model;
    texopt_mesh *mesh;
    texopt_triloss *loss;
} loss_fixture;

/* A loss evaluator over domain 0 of `model`, which the fixture then owns (NULL fails). */
static int fixture_open_model(loss_fixture *f, texopt_model *model, int viewport)
{
    char err[256] = "";
    f->model = model;
    f->mesh = NULL;
    f->loss = NULL;
    if (!f->model || texopt_mesh_create(&f->mesh, f->model, 0, err, sizeof err) != TEXOPT_OK)
        return 0;
    return texopt_triloss_create(&f->loss, f->model, f->mesh, viewport, err, sizeof err) == TEXOPT_OK;
}

static int fixture_open(loss_fixture *f, int n, int tex, const char *pattern, int viewport)
{
    return fixture_open_model(f, fixture_grid(n, tex, pattern), viewport);
}

static void fixture_close(loss_fixture *f)
{
    texopt_triloss_destroy(f->loss);
    texopt_mesh_destroy(f->mesh);
    texopt_model_destroy(f->model);
}

static double loss_of(loss_fixture *f, uint32_t t, double a, double l1, double l2, double b)
{
    char err[256] = "";
    double J[4], e = -1.0;
    texopt_jacobian_from_params(a, l1, l2, b, J);
    if (texopt_triloss_prepare(f->loss, t, err, sizeof err) != TEXOPT_OK)
        return NAN;
    if (texopt_triloss_eval(f->loss, J, INFINITY, &e, err, sizeof err) != TEXOPT_OK)
        return NAN;
    return e;
}

TEST(jacobian_matches_its_factors)
{
    double J[4];
    /* Pure rotation by 30 degrees. */
    texopt_jacobian_from_params(PI / 6, 1, 1, 0.7, J);
    CHECK_NEAR(J[0], cos(PI / 6), 1e-15);
    CHECK_NEAR(J[1], -sin(PI / 6), 1e-15);
    CHECK_NEAR(J[2], sin(PI / 6), 1e-15);
    CHECK_NEAR(J[3], cos(PI / 6), 1e-15);
    /* Stretch along the axis at beta = 90 degrees: diag(l2, l1). */
    texopt_jacobian_from_params(0, 0.5, 0.25, PI / 2, J);
    CHECK_NEAR(J[0], 0.25, 1e-15);
    CHECK_NEAR(J[3], 0.5, 1e-15);
    CHECK_NEAR(J[1], 0.0, 1e-15);
    /* det J = l1 l2 whatever the angles. */
    texopt_jacobian_from_params(0.3, 0.8, 0.4, 1.1, J);
    CHECK_NEAR(J[0] * J[3] - J[1] * J[2], 0.32, 1e-14);
}

TEST(identity_has_zero_loss)
{
    const char *patterns[] = {"half", "stripes0", "stripes45", "checker"};
    for (int p = 0; p < 4; p++) {
        loss_fixture f;
        CHECK(fixture_open(&f, 8, 64, patterns[p], 64));
        for (uint32_t t = 0; t < 128; t += 9) {
            double e = loss_of(&f, t, 0, 1, 1, 0);
            CHECK_MSG(e >= 0 && e < 1e-6, "%s triangle %u: E(I) = %g", patterns[p], t, e);
        }
        fixture_close(&f);
    }
}

TEST(flat_texture_survives_any_shrink)
{
    loss_fixture f;
    CHECK(fixture_open(&f, 8, 64, "flat", 64));
    double e = loss_of(&f, 2 * (3 * 8 + 3), 0.4, 0.1, 0.1, 0.2);
    CHECK(e >= 0 && e < 1e-6);
    fixture_close(&f);
}

TEST(detail_breaks_under_shrink_flat_half_does_not)
{
    /* "half" on 128 texels: x < 64 flat, x >= 64 text-like strokes; quads are 8 texels.
     * Quad (3, 7) has its one-ring in x in [16, 40] (flat, and away from the wrap at x = 0
     * whose bilinear lookups see the strokes of the last column); quad (11, 7) sits in the
     * strokes. */
    loss_fixture f;
    CHECK(fixture_open(&f, 16, 128, "half", 64));
    double flat = loss_of(&f, 2 * (7 * 16 + 3), 0, 0.2, 0.2, 0);
    double detail = loss_of(&f, 2 * (7 * 16 + 11), 0, 0.2, 0.2, 0);
    double detail_mild = loss_of(&f, 2 * (7 * 16 + 11), 0, 0.9, 0.9, 0);
    CHECK_MSG(flat < 1e-6, "flat half E = %g", flat);
    CHECK_MSG(detail > 0.05, "strokes at 0.2x: E = %g", detail);
    CHECK_MSG(detail_mild < detail, "mild %g vs strong %g", detail_mild, detail);
    fixture_close(&f);
}

TEST(stripes_tolerate_shrink_along_them_not_across)
{
    /* Vertical stripes vary along x only: squeezing y loses nothing a bilinear texture can
     * show, squeezing x blurs them. */
    loss_fixture f;
    CHECK(fixture_open(&f, 8, 64, "stripes0", 64));
    uint32_t t = 2 * (4 * 8 + 4);
    double along = loss_of(&f, t, 0, 1.0, 0.3, 0);
    double across = loss_of(&f, t, 0, 0.3, 1.0, 0);
    CHECK_MSG(along < 1e-3, "squeeze along stripes: E = %g", along);
    CHECK_MSG(across > 0.05, "squeeze across stripes: E = %g", across);
    fixture_close(&f);
}

TEST(quarter_turn_symmetry_of_the_pixel_grid)
{
    /* Paper Fig. 7: turning the new texels by 90 degrees costs nothing, by 45 it does. */
    const char *patterns[] = {"stripes0", "stripes45", "checker", "half"};
    for (int p = 0; p < 4; p++) {
        loss_fixture f;
        CHECK(fixture_open(&f, 8, 64, patterns[p], 64));
        for (uint32_t t = 36; t < 100; t += 21) {
            double e0 = loss_of(&f, t, 0, 1.0, 0.6, 0.3);
            double e90 = loss_of(&f, t, PI / 2, 1.0, 0.6, 0.3);
            CHECK_MSG(fabs(e0 - e90) < 1e-9, "%s t %u: E(0) %g E(90) %g", patterns[p], t, e0, e90);
        }
        fixture_close(&f);
    }
    loss_fixture f;
    CHECK(fixture_open(&f, 8, 64, "stripes0", 64));
    double e0 = loss_of(&f, 2 * (4 * 8 + 4), 0, 1.0, 0.6, 0);
    double e45 = loss_of(&f, 2 * (4 * 8 + 4), PI / 4, 1.0, 0.6, 0);
    CHECK_MSG(e0 < 1e-6 && e45 > 0.01, "stripes0: E(0) %g, E(45) %g", e0, e45);
    fixture_close(&f);
}

/* A 4 x 4 grid whose UVs are scaled by `scale` (REPEAT): each triangle reads scale / 4
 * periods of its 64 x 64 texture. Returns the status of preparing triangle 10, its message
 * in err. */
static texopt_status prepare_repeated_grid(double scale, char *err, size_t err_len)
{
    texopt_model *m = fixture_grid(4, 64, "checker");
    if (!m)
        return TEXOPT_E_NOMEM;
    for (size_t k = 0; k < 2 * m->vertex_count; k++)
        m->uvs[k] = (float)(m->uvs[k] * scale);
    loss_fixture f;
    texopt_status st =
        fixture_open_model(&f, m, 64) ? texopt_triloss_prepare(f.loss, 10, err, err_len) : TEXOPT_E_INTERNAL;
    fixture_close(&f);
    return st;
}

/* A neighbourhood spanning hundreds of repeats of its texture would need a re-bake texture
 * past the bake's 2^31 texels: refused at preparation, saying so, where the bake would have
 * refused each evaluation with a bare size. */
TEST(a_neighbourhood_too_wide_to_rebake_is_refused_with_what_it_spans)
{
    char err[256] = "";
    CHECK_OK(prepare_repeated_grid(20, err, sizeof err), err);
    texopt_status st = prepare_repeated_grid(8000, err, sizeof err);
    CHECK_MSG(st == TEXOPT_E_LIMIT, "status %d: %s", (int)st, err);
    CHECK_MSG(strstr(err, "repeats of its 64x64 texture") != NULL, "%s", err);
}

TEST(loss_is_deterministic_and_stop_above_is_honoured)
{
    loss_fixture f;
    CHECK(fixture_open(&f, 8, 64, "checker", 64));
    char err[256] = "";
    double J[4], e1, e2, e3, e4;
    texopt_jacobian_from_params(0.3, 0.6, 0.45, 0.9, J);
    CHECK_OK(texopt_triloss_prepare(f.loss, 20, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(f.loss, J, INFINITY, &e1, err, sizeof err), err);
    CHECK_OK(texopt_triloss_prepare(f.loss, 77, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(f.loss, J, INFINITY, &e3, err, sizeof err), err);
    CHECK_OK(texopt_triloss_prepare(f.loss, 20, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(f.loss, J, INFINITY, &e2, err, sizeof err), err);
    CHECK(e1 == e2);
    CHECK(e1 > 0.0);
    CHECK_OK(texopt_triloss_eval(f.loss, J, 0.5 * e1, &e4, err, sizeof err), err);
    CHECK(e4 >= 0.5 * e1);
    CHECK(e3 >= 0.0);
    fixture_close(&f);
}

/* A flat 8 x 8 grid whose second image (64 x 64, unbound) varies only in its blue channel:
 * fine vertical stripes. NULL when something fails. */
static texopt_model *grid_with_blue_stripes(void)
{
    texopt_model *m = fixture_grid(8, 64, "flat");
    texopt_image *images = m ? realloc(m->images, 2 * sizeof *images) : NULL;
    if (!images)
        return texopt_model_destroy(m), NULL;
    m->images = images;
    char **names = realloc(m->image_names, 2 * sizeof *names);
    if (!names)
        return texopt_model_destroy(m), NULL;
    m->image_names = names;
    names[1] = NULL;
    if (texopt_image_create(&m->images[1], 64, 64, 3, NULL, 0) != TEXOPT_OK)
        return texopt_model_destroy(m), NULL;
    m->image_count = 2;
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            float *px = texopt_image_at(&m->images[1], x, y);
            px[0] = 0.5f;
            px[1] = 0.5f;
            px[2] = ((x / 2) % 2) ? 1.0f : 0.2f;
        }
    return m;
}

/* Signals stage 1 compares on the grid of grid_with_blue_stripes with its second image (made
 * RGBA when `alpha`) bound as an extension texture of the given kind reading `channels` through
 * TEXCOORD_`texcoord`, and base colour bound to the first image (base 1), to the second (2) or
 * to none (0); -1 on failure. */
static int signals_through(texopt_texture_kind kind, unsigned channels, int alpha, int base, int texcoord)
{
    texopt_model *m = grid_with_blue_stripes();
    char err[256] = "";
    int count = -1;
    if (!m || (alpha && fixture_add_alpha(&m->images[1], "stripes0") != 0))
        return texopt_model_destroy(m), -1;
    texopt_material *mat = &m->materials[0];
    mat->extra[0].ref = mat->slot[TEXOPT_SLOT_BASE_COLOR];
    mat->extra[0].ref.image = 1;
    mat->extra[0].ref.texcoord = texcoord;
    mat->extra[0].kind = kind;
    mat->extra[0].channels = channels;
    mat->extra[0].name = "clearcoatTexture";
    mat->extra_count = 1;
    if (base != 1)
        mat->slot[TEXOPT_SLOT_BASE_COLOR].image = base ? 1 : -1;
    texopt_mesh *mesh = NULL;
    texopt_triloss *loss = NULL;
    if (texopt_model_build_domains(m, err, sizeof err) == TEXOPT_OK &&
        texopt_mesh_create(&mesh, m, 0, err, sizeof err) == TEXOPT_OK &&
        texopt_triloss_create(&loss, m, mesh, 64, err, sizeof err) == TEXOPT_OK)
        count = texopt_triloss_signal_count(loss);
    texopt_triloss_destroy(loss);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
    return count;
}

static int signals_with_extension_texture(texopt_texture_kind kind, unsigned channels, int alpha, int base)
{
    return signals_through(kind, channels, alpha, base, 0);
}

TEST(extension_textures_are_compared_by_their_kind_and_channels)
{
    /* Base colour's luma, then the extension texture's luma or the channels it reads. */
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB, 0, 1), 2);
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R, 0, 1), 2);
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R | TEXOPT_CHANNEL_G, 0, 1), 3);
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_NORMAL, TEXOPT_CHANNELS_RGB, 0, 1), 4);
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A, 1, 1), 2);
    /* The second image alone, read as base colour and as clearcoat's R: R, G and B, the colour's
     * luma being theirs. */
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R, 0, 2), 3);
    /* A colour with a shown alpha (sheen colour reads no alpha, so this is the rule alone). */
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB | TEXOPT_CHANNEL_A, 1, 1), 3);
    /* Alpha read from a file without one is 1 everywhere: nothing to compare... */
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A, 0, 1), 1);
    /* ...unless nothing else is: then its R, G and B, so that stage 1 has a signal. */
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A, 0, 0), 3);
    CHECK_EQ_INT(signals_with_extension_texture(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A, 1, 0), 1);
}

TEST(a_binding_through_another_uv_set_adds_no_signal)
{
    /* The second image as base colour and, through TEXCOORD_1, as clearcoat's R: that R is read
     * along a layout texopt leaves, so the new one keeps the colour's luma alone. */
    CHECK_EQ_INT(signals_through(TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_R, 0, 2, 1), 1);
    CHECK_EQ_INT(signals_through(TEXOPT_TEXTURE_NORMAL, TEXOPT_CHANNELS_RGB, 0, 1, 1), 1);
}

/* E under J of a triangle in the middle of m (an 8 x 8 grid on 64 texels; taken), its signals
 * weighed by `weights` (NULL: not weighed); NAN on failure or when `signals` > 0 is not the
 * number of signals. */
static double middle_triangle_loss(texopt_model *m, const double J[4], const double *weights, int signals)
{
    char err[256] = "";
    loss_fixture f;
    double e = NAN;
    if (fixture_open_model(&f, m, 64) && (signals <= 0 || texopt_triloss_signal_count(f.loss) == signals)) {
        texopt_triloss_weigh_signals(f.loss, weights);
        if (texopt_triloss_prepare(f.loss, 2 * (4 * 8 + 4), err, sizeof err) != TEXOPT_OK ||
            texopt_triloss_eval(f.loss, J, INFINITY, &e, err, sizeof err) != TEXOPT_OK)
            e = NAN;
    }
    fixture_close(&f);
    return e;
}

/* E of a squeeze across the alpha stripes of base colour (RGB flat, 4-texel columns cut out),
 * with its material's alpha shown or not. */
static double striped_alpha_loss(int shown)
{
    texopt_model *m = fixture_grid(8, 64, "flat");
    if (!m || fixture_add_alpha(&m->images[0], "stripes0") != 0)
        return texopt_model_destroy(m), NAN;
    m->materials[0].alpha_mode = shown ? TEXOPT_ALPHA_BLEND : TEXOPT_ALPHA_OPAQUE;
    double J[4];
    texopt_jacobian_from_params(0.0, 0.3, 1.0, 0.0, J);
    return middle_triangle_loss(m, J, NULL, 0);
}

TEST(base_colour_alpha_counts_when_the_material_shows_it)
{
    /* alphaMode MASK or BLEND: the cut-out's edges are part of the picture; OPAQUE: they are
     * not rendered, and the flat colour is lossless. */
    double shown = striped_alpha_loss(1), hidden = striped_alpha_loss(0);
    CHECK_MSG(shown > 0.05, "alpha shown: E = %g", shown);
    CHECK_MSG(hidden < 1e-6, "alpha hidden: E = %g", hidden);
}

TEST(normal_map_adds_three_channel_signals)
{
    /* A second texture used as the normal map: colour gives one luma signal, the normal map
     * one per channel; a normal map that varies only in its blue channel must still count. */
    texopt_model *m = grid_with_blue_stripes();
    CHECK(m);
    char err[256] = "";
    m->materials[0].slot[TEXOPT_SLOT_NORMAL] = m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR];
    m->materials[0].slot[TEXOPT_SLOT_NORMAL].image = 1;
    CHECK_OK(texopt_model_build_domains(m, err, sizeof err), err);
    texopt_mesh *mesh = NULL;
    texopt_triloss *loss = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    CHECK_OK(texopt_triloss_create(&loss, m, mesh, 64, err, sizeof err), err);
    CHECK_EQ_INT(texopt_triloss_signal_count(loss), 4);
    double J[4], e;
    texopt_jacobian_from_params(0, 0.3, 1.0, 0, J);
    CHECK_OK(texopt_triloss_prepare(loss, 2 * (4 * 8 + 4), err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(loss, J, INFINITY, &e, err, sizeof err), err);
    CHECK_MSG(e > 0.05, "blue-only normal detail squeezed across: E = %g", e);
    texopt_jacobian_from_params(0, 1.0, 1.0, 0, J);
    CHECK_OK(texopt_triloss_eval(loss, J, INFINITY, &e, err, sizeof err), err);
    CHECK(e < 1e-6);
    texopt_triloss_destroy(loss);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

/* fixture_grid(8, 64, "flat") plus a 64x64 occlusion-roughness-metallic texture (occlusion
 * reads its R, metallic-roughness its G and B) whose red channel has fine vertical stripes and
 * whose green and blue are `green` and `blue` (-1: the same stripes, -2: coarser horizontal
 * stripes). */
static texopt_model *with_occlusion(double green, double blue)
{
    char err[256] = "";
    texopt_model *m = fixture_grid(8, 64, "flat");
    texopt_image *images = m ? realloc(m->images, 2 * sizeof *images) : NULL;
    char **names = images ? realloc(m->image_names, 2 * sizeof *names) : NULL;
    if (images)
        m->images = images;
    if (names) {
        m->image_names = names;
        names[1] = NULL;
    }
    if (!names || texopt_image_create(&m->images[1], 64, 64, 3, err, sizeof err) != TEXOPT_OK) {
        texopt_model_destroy(m);
        return NULL;
    }
    m->image_count = 2;
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            float *px = texopt_image_at(&m->images[1], x, y);
            px[0] = ((x / 2) % 2) ? 0.9f : 0.1f;
            float across = ((y / 4) % 2) ? 0.8f : 0.3f;
            px[1] = green == -1 ? px[0] : green == -2 ? across : (float)green;
            px[2] = blue == -1 ? px[0] : blue == -2 ? across : (float)blue;
        }
    m->materials[0].slot[TEXOPT_SLOT_OCCLUSION] = m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR];
    m->materials[0].slot[TEXOPT_SLOT_OCCLUSION].image = 1;
    m->materials[0].slot[TEXOPT_SLOT_METALLIC_ROUGHNESS] = m->materials[0].slot[TEXOPT_SLOT_OCCLUSION];
    if (texopt_model_build_domains(m, err, sizeof err) != TEXOPT_OK) {
        texopt_model_destroy(m);
        return NULL;
    }
    return m;
}

TEST(constant_and_repeated_signals_do_not_change_the_loss)
{
    /* Grey occlusion stored as RGB (three equal channels) and a texture with one detailed
     * channel and two constant ones are skipped down to the same single bake: the same E
     * bit for bit, for squeezes across the stripes (large E) and along them. */
    for (int k = 0; k < 3; k++) {
        double J[4];
        texopt_jacobian_from_params(0.1 * k, k == 1 ? 1.0 : 0.3, k == 1 ? 0.3 : 1.0, 0.0, J);
        double grey = middle_triangle_loss(with_occlusion(-1, -1), J, NULL, 4);
        double one = middle_triangle_loss(with_occlusion(0.3, 0.7), J, NULL, 4);
        double red_green = middle_triangle_loss(with_occlusion(-1, 0.7), J, NULL, 4);
        CHECK_MSG(grey == one && one == red_green, "J %d: E %.17g %.17g %.17g", k, grey, one, red_green);
        CHECK_MSG(k == 1 || grey > 0.05, "squeezed across the stripes: E = %g", grey);
    }
}

TEST(early_stop_solves_the_leading_signal_first_and_agrees_with_the_full_loss)
{
    /* Two different signals (vertical and horizontal stripes): with a stop that is not
     * reached the lead-first evaluation gives the full maximum (to rounding); a stop below
     * the leading signal's E returns at least the stop; the next evaluations agree again. */
    loss_fixture f;
    CHECK(fixture_open_model(&f, with_occlusion(-2, 0.5), 64));
    texopt_triloss *loss = f.loss;
    char err[256] = "";
    CHECK_OK(texopt_triloss_prepare(loss, 2 * (4 * 8 + 4), err, sizeof err), err);
    for (int k = 0; k < 3; k++) {
        double J[4], full, lead_first, cut;
        /* squeezed across the vertical stripes, across the horizontal ones, both */
        texopt_jacobian_from_params(0.0, k == 1 ? 1.0 : 0.4, k == 0 ? 1.0 : 0.4, 0.0, J);
        CHECK_OK(texopt_triloss_eval(loss, J, INFINITY, &full, err, sizeof err), err);
        CHECK(full > 0.02);
        CHECK_OK(texopt_triloss_eval(loss, J, 2.0 * full, &lead_first, err, sizeof err), err);
        CHECK_MSG(fabs(lead_first - full) < 1e-9 * full, "J %d: %.17g vs %.17g", k, lead_first, full);
        CHECK_OK(texopt_triloss_eval(loss, J, 0.5 * full, &cut, err, sizeof err), err);
        CHECK(cut >= 0.5 * full && cut <= full * (1 + 1e-9));
    }
    fixture_close(&f);
}

TEST(keep_deciding_compares_only_the_signals_that_gave_e_until_the_next_prepare)
{
    /* Vertical stripes in red, horizontal ones in green: squeezed across x only red breaks
     * and decides E. Kept to the deciding signals, a squeeze across y (where green decides)
     * sees red alone, so its E falls to red's; the squeeze across x keeps its E; the next
     * prepare compares every signal again. */
    loss_fixture f;
    CHECK(fixture_open_model(&f, with_occlusion(-2, 0.5), 64));
    texopt_triloss *loss = f.loss;
    char err[256] = "";
    const uint32_t t = 2 * (4 * 8 + 4);
    double across_x[4], across_y[4], ex, ey, ex_kept, ey_kept, ey_again;
    texopt_jacobian_from_params(0.0, 0.4, 1.0, 0.0, across_x);
    texopt_jacobian_from_params(0.0, 1.0, 0.4, 0.0, across_y);
    CHECK_OK(texopt_triloss_prepare(loss, t, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(loss, across_y, INFINITY, &ey, err, sizeof err), err);
    CHECK_OK(texopt_triloss_prepare(loss, t, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(loss, across_x, INFINITY, &ex, err, sizeof err), err);
    texopt_triloss_keep_deciding(loss);
    CHECK_OK(texopt_triloss_eval(loss, across_x, INFINITY, &ex_kept, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(loss, across_y, INFINITY, &ey_kept, err, sizeof err), err);
    CHECK(ex > 0.05 && ey > 0.05);
    CHECK_MSG(fabs(ex_kept - ex) < 1e-9 * ex, "%.17g vs %.17g", ex_kept, ex);
    CHECK_MSG(ey_kept < 0.5 * ey, "green ignored: %g vs %g", ey_kept, ey);
    CHECK_OK(texopt_triloss_prepare(loss, t, err, sizeof err), err);
    CHECK_OK(texopt_triloss_eval(loss, across_y, INFINITY, &ey_again, err, sizeof err), err);
    CHECK_MSG(fabs(ey_again - ey) < 1e-9 * ey, "%.17g vs %.17g", ey_again, ey);
    fixture_close(&f);
}

/* E of a squeeze across with_occlusion(0.5, 0.5)'s red stripes (the only detail: base colour
 * is flat, green and blue constant) with the red channel weighed `red` (NAN: not weighed). */
static double weighed_occlusion_loss(double red)
{
    double weights[2 * TEXOPT_LIT_WEIGHT_STRIDE];
    for (int k = 0; k < 2 * TEXOPT_LIT_WEIGHT_STRIDE; k++)
        weights[k] = 1.0;
    weights[TEXOPT_LIT_WEIGHT_STRIDE + 1] = red;
    double J[4];
    texopt_jacobian_from_params(0, 0.3, 1.0, 0, J);
    return middle_triangle_loss(with_occlusion(0.5, 0.5), J, isnan(red) ? NULL : weights, 0);
}

TEST(a_weighed_signal_counts_with_the_contrast_its_weight_leaves)
{
    double plain = weighed_occlusion_loss(NAN), one = weighed_occlusion_loss(1.0);
    double quarter = weighed_occlusion_loss(0.25), none = weighed_occlusion_loss(0.0);
    printf("  E unweighed %.5f, weight 1 %.5f, 0.25 %.5f, 0 %.5f\n", plain, one, quarter, none);
    CHECK(plain > 0.05);
    CHECK(one == plain);
    CHECK(quarter > 0.0 && quarter < plain);
    CHECK(none == 0.0);
}

TEST(triloss_rejects_bad_input)
{
    loss_fixture f;
    CHECK(fixture_open(&f, 2, 16, "flat", 16));
    char err[256] = "";
    CHECK(texopt_triloss_prepare(f.loss, 8, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_triloss *l = NULL;
    CHECK(texopt_triloss_create(&l, f.model, f.mesh, 1, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(l == NULL);
    texopt_triloss_destroy(NULL);
    fixture_close(&f);
}

TEST(close_ups_see_fine_detail_in_a_triangle_its_window_blurs)
{
    /* The unit quad over 512 texels of "half" (1-texel strokes right of x = 256): triangle 0
     * spans the texture, so its window shows 8 texels a pixel and a shrink to a quarter
     * changes nothing it can see; close-ups at the zoom limit see the strokes break. */
    loss_fixture f;
    CHECK(fixture_open_model(&f, fixture_textured_quad(512, "half"), 64));
    double identity = loss_of(&f, 0, 0, 1, 1, 0);
    CHECK_MSG(identity < 1e-6, "E(I) = %g", identity);
    double close = loss_of(&f, 0, 0, 0.25, 0.25, 0);
    int close_ups = texopt_triloss_close_up_count(f.loss);
    CHECK(close_ups >= 1 && close_ups <= TEXOPT_TRILOSS_CLOSE_UPS);
    /* The paper's window alone (as in test_camera_zoom, through the raster's limit, which
     * also turns the close-ups off). */
    ((texopt_uvraster *)texopt_triloss_raster(f.loss))->max_zoom = 0;
    double window_only = loss_of(&f, 0, 0, 0.25, 0.25, 0);
    CHECK_EQ_INT(texopt_triloss_close_up_count(f.loss), 0);
    CHECK_MSG(window_only < 0.01 && close > 0.05, "window %g, close-ups %g", window_only, close);
    fixture_close(&f);
    /* Triangles their window shows near the limit get none. */
    CHECK(fixture_open(&f, 8, 64, "half", 64));
    for (uint32_t t = 0; t < 128; t += 9) {
        loss_of(&f, t, 0, 0.5, 0.5, 0);
        CHECK_EQ_INT(texopt_triloss_close_up_count(f.loss), 0);
    }
    fixture_close(&f);
}
