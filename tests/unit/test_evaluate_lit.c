/* test_evaluate_lit.c - the lit whole-mesh loss (evaluate.h `lit`, lit_shade.h): it sees the
 * normal, occlusion and metallic-roughness maps that base-colour q does not, it compares a
 * re-baked normal map in the reference's tangent frame (a quarter-turned layout whose map was
 * turned scores near 0, the same bake without the turn does not), its specular highlight
 * follows roughness and metallic, and it refuses a model with nothing to light. Models are a
 * generated quad with separate base-colour, normal, occlusion (and metallic-roughness) images. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "evaluate.h"
#include "fixtures.h"
#include "lit_shade.h"
#include "test.h"

#define TEX 64

static const float quad_pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float quad_uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
static const float quarter_turned_uv[8] = {1, 0, 1, 1, 0, 1, 0, 0};
static const uint32_t quad_tris[6] = {0, 1, 2, 0, 2, 3};

/* Occlusion in stripes across v: 1 and 0.6. */
static void fill_occlusion(texopt_image *img, double scale)
{
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            float *p = texopt_image_at(img, x, y);
            p[0] = p[1] = p[2] = (float)(scale * ((y / 6) % 2 ? 1.0 : 0.6));
        }
}

static void fill_flat_normal(texopt_image *img)
{
    for (size_t i = 0; i < (size_t)img->width * (size_t)img->height; i++) {
        img->pixels[3 * i] = img->pixels[3 * i + 1] = 0.5f;
        img->pixels[3 * i + 2] = 1.0f;
    }
}

/* The quad over `uv`: image 0 a checker base colour, image 1 a normal map, image 2 an
 * occlusion map (filled as the reference's unless a test overwrites them). */
static texopt_model *lit_quad(const float *uv)
{
    texopt_model *m = fixture_model_from_arrays(quad_pos, uv, 4, quad_tris, 2, TEX, TEX, "checker");
    if (!m)
        return NULL;
    /* Each addition may move the image array: fill them once both are there. */
    if (!fixture_add_slot_image(m, TEXOPT_SLOT_NORMAL, TEX) || !fixture_add_slot_image(m, TEXOPT_SLOT_OCCLUSION, TEX)) {
        texopt_model_destroy(m);
        return NULL;
    }
    fixture_fill_normal_map(&m->images[1]);
    fill_occlusion(&m->images[2], 1.0);
    return m;
}

static double q_of(const texopt_model *ref, const texopt_model *cand, int lit)
{
    texopt_evaluate_options opt = {.resolution = 128, .threads = 2, .lit = lit};
    texopt_evaluation ev;
    char err[256] = "";
    texopt_status st = texopt_evaluate(ref, cand, &opt, &ev, err, sizeof err);
    if (st != TEXOPT_OK) {
        printf("  evaluate: %s\n", err);
        return NAN;
    }
    return ev.q;
}

TEST(lit_q_of_a_model_against_itself_is_zero)
{
    texopt_model *ref = lit_quad(quad_uv), *same = lit_quad(quad_uv);
    CHECK(ref && same);
    CHECK(q_of(ref, ref, 1) == 0.0);
    CHECK(q_of(ref, same, 1) == 0.0);
    texopt_model_destroy(ref);
    texopt_model_destroy(same);
}

/* A candidate with the reference's base colour and one other map changed: base-colour q
 * must be exactly 0 and lit q at least min_lit. */
static void check_only_lit_sees(const char *what, const texopt_model *ref, texopt_model *cand, double min_lit)
{
    double base = q_of(ref, cand, 0), lit = q_of(ref, cand, 1);
    printf("  %s: base-colour q %.5f, lit q %.5f\n", what, base, lit);
    CHECK(base == 0.0);
    CHECK_MSG(lit > min_lit, "%s: lit q %.5f", what, lit);
}

TEST(lit_q_sees_a_flattened_normal_map_that_base_colour_q_does_not)
{
    texopt_model *ref = lit_quad(quad_uv), *flat = lit_quad(quad_uv);
    CHECK(ref && flat);
    fill_flat_normal(&flat->images[1]);
    check_only_lit_sees("flattened normal map", ref, flat, 0.02); /* measured 0.069 */
    texopt_model_destroy(ref);
    texopt_model_destroy(flat);
}

TEST(lit_q_sees_the_occlusion_map)
{
    texopt_model *ref = lit_quad(quad_uv), *dark = lit_quad(quad_uv);
    CHECK(ref && dark);
    fill_occlusion(&dark->images[2], 0.5);
    check_only_lit_sees("halved occlusion", ref, dark, 0.01); /* measured 0.032 */
    texopt_model_destroy(ref);
    texopt_model_destroy(dark);
}

/* lit_quad with a metallic-roughness image (image 3): roughness (G) in stripes across u,
 * metallic (B) `metallic` everywhere; the material's factors 1, so the texture decides. */
static texopt_model *lit_quad_with_material(const float *uv, float metallic)
{
    texopt_model *m = lit_quad(uv);
    texopt_image *mr = m ? fixture_add_slot_image(m, TEXOPT_SLOT_METALLIC_ROUGHNESS, TEX) : NULL;
    if (!mr) {
        texopt_model_destroy(m);
        return NULL;
    }
    for (int y = 0; y < TEX; y++)
        for (int x = 0; x < TEX; x++) {
            float *p = texopt_image_at(mr, x, y);
            p[0] = 1.0f;
            p[1] = (x / 4) % 2 ? 0.9f : 0.2f;
            p[2] = metallic;
        }
    m->materials[0].metallic_factor = m->materials[0].roughness_factor = 1;
    return m;
}

TEST(lit_q_sees_the_metallic_roughness_map)
{
    texopt_model *ref = lit_quad_with_material(quad_uv, 0.0f), *metal = lit_quad_with_material(quad_uv, 1.0f);
    texopt_model *smooth = lit_quad_with_material(quad_uv, 0.0f);
    CHECK(ref && metal && smooth);
    CHECK(texopt_lit_has_maps(ref));
    CHECK(q_of(ref, ref, 1) == 0.0);
    texopt_image *mr = &smooth->images[3];
    for (size_t i = 0; i < (size_t)TEX * TEX; i++)
        mr->pixels[3 * i + 1] = 0.2f;
    check_only_lit_sees("metallic instead of dielectric", ref, metal, 0.01); /* measured 0.073 */
    check_only_lit_sees("roughness stripes smoothed", ref, smooth, 0.0005);  /* measured 0.00107 */
    /* metallicFactor 0 (the reference's: both renders use its materials) makes the texture's
     * B count for nothing, as in a glTF viewer. */
    ref->materials[0].metallic_factor = 0;
    CHECK(q_of(ref, metal, 1) == 0.0);
    texopt_model_destroy(ref);
    texopt_model_destroy(metal);
    texopt_model_destroy(smooth);
}

/* The reference quad laid out again over `uv`, every image re-baked into it; the normal map
 * turned with its triangles when turn_normals (as the pipeline does without stored tangents). */
static texopt_model *rebaked(const texopt_model *ref, const float *uv, int turn_normals)
{
    texopt_model *cand = lit_quad(uv);
    for (int i = 0; cand && i < 3; i++)
        if (fixture_rebake(ref, cand, i, turn_normals && i == 1) != 0) {
            texopt_model_destroy(cand);
            return NULL;
        }
    return cand;
}

TEST(quarter_turned_layout_shades_like_the_reference_when_its_normal_map_was_turned)
{
    texopt_model *ref = lit_quad(quad_uv);
    CHECK(ref);
    texopt_model *turned = rebaked(ref, quarter_turned_uv, 1), *unturned = rebaked(ref, quarter_turned_uv, 0);
    CHECK(turned && unturned);
    double base = q_of(ref, turned, 0), lit = q_of(ref, turned, 1), wrong = q_of(ref, unturned, 1);
    printf("  quarter turn: base-colour q %.5f, lit q %.5f, lit q without the turn %.5f\n", base, lit, wrong);
    /* A quarter turn of a square moves texel centres onto texel centres: the re-bake only
     * resamples (bilinear, same size), so what is left is that resampling, which the base
     * colour shows as well; lit may not add more than it. Measured: 0 / 0 / 0.078. */
    CHECK_MSG(lit < 0.005 && lit <= base + 0.002, "lit q %.5f (base colour %.5f)", lit, base);
    CHECK_MSG(wrong > 0.02 && wrong > 10 * lit, "lit q without the turn %.5f", wrong);
    texopt_model_destroy(ref);
    texopt_model_destroy(turned);
    texopt_model_destroy(unturned);
}

/* One evaluation of cand against ref on the icosahedron's cameras, with the reference's views
 * kept in `views` or shaded anew (NULL), its per-triangle errors into tri_error (2). */
static texopt_status evaluate_with(const texopt_model *ref, const texopt_model *cand, int lit,
                                   const texopt_evaluate_reference *views, double *tri_error, texopt_evaluation *ev)
{
    texopt_evaluate_options opt = {.resolution = 128,
                                   .threads = 2,
                                   .lit = lit,
                                   .cameras = TEXOPT_CAMERAS_ICOSAHEDRON,
                                   .triangle_error = tri_error,
                                   .reference_views = views};
    char err[256] = "";
    texopt_status st = texopt_evaluate(ref, cand, &opt, ev, err, sizeof err);
    if (st != TEXOPT_OK)
        printf("  evaluate: %s\n", err);
    return st;
}

/* The refinement keeps the reference's views across its rounds: reading them gives bit for
 * bit the evaluation that shades the reference anew, and views kept for another measure,
 * screen or reference are refused. */
TEST(kept_reference_views_evaluate_as_shading_anew)
{
    texopt_model *ref = lit_quad_with_material(quad_uv, 0.0f), *other = lit_quad_with_material(quad_uv, 0.0f);
    texopt_model *cand = lit_quad_with_material(quad_uv, 1.0f);
    CHECK(ref && other && cand);
    for (int lit = 0; lit < 2 && ref && other && cand; lit++) {
        /* A candidate darker in base colour as well, so that both measures see it. */
        for (size_t i = 0; i < 3 * (size_t)TEX * TEX; i++)
            cand->images[0].pixels[i] *= 0.8f;
        texopt_evaluate_options opt = {
            .resolution = 128, .threads = 2, .lit = lit, .cameras = TEXOPT_CAMERAS_ICOSAHEDRON};
        texopt_evaluate_reference *views = NULL;
        char err[256] = "";
        CHECK_OK(texopt_evaluate_reference_create(ref, &opt, &views, err, sizeof err), err);
        double anew[2], kept[2];
        texopt_evaluation a, k;
        CHECK(evaluate_with(ref, cand, lit, NULL, anew, &a) == TEXOPT_OK);
        CHECK(evaluate_with(ref, cand, lit, views, kept, &k) == TEXOPT_OK);
        printf("  %s: q %.5f shaded anew, %.5f from kept views\n", lit ? "lit" : "base colour", a.q, k.q);
        CHECK(a.q > 0.001 && a.q == k.q && a.view_count == 12 && k.view_count == 12);
        CHECK(memcmp(a.view_gmsd, k.view_gmsd, sizeof a.view_gmsd) == 0);
        /* Per-triangle sums add the workers' views in whichever order they took them: equal
         * to rounding. */
        for (int t = 0; t < 2; t++)
            CHECK_MSG(anew[t] > 0 && fabs(anew[t] - kept[t]) <= 1e-12 * anew[t], "triangle %d: %.17g against %.17g", t,
                      anew[t], kept[t]);
        /* Kept for the other measure, another screen, another reference: refused. */
        CHECK(evaluate_with(ref, cand, !lit, views, NULL, &k) == TEXOPT_E_INVALID_ARGUMENT);
        CHECK(evaluate_with(other, cand, lit, views, NULL, &k) == TEXOPT_E_INVALID_ARGUMENT);
        opt.resolution = 96;
        opt.reference_views = views;
        CHECK(texopt_evaluate(ref, cand, &opt, &k, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
        opt.resolution = 128;
        opt.cameras = TEXOPT_CAMERAS_DODECAHEDRON;
        CHECK(texopt_evaluate(ref, cand, &opt, &k, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
        texopt_evaluate_reference_destroy(views);
    }
    texopt_model_destroy(ref);
    texopt_model_destroy(other);
    texopt_model_destroy(cand);
}

/* Only base colour: lit luma is base colour's luma times one shading both renders share, so
 * a darker candidate is worse under both measures and an identical one is 0. */
TEST(base_colour_only_model_is_lit_by_its_base_colour)
{
    texopt_model *ref = fixture_textured_quad(TEX, "checker"), *dark = fixture_textured_quad(TEX, "checker");
    CHECK(ref && dark);
    CHECK(!texopt_lit_has_maps(ref));
    for (size_t i = 0; i < 3 * (size_t)TEX * TEX; i++)
        dark->images[0].pixels[i] *= 0.5f;
    double base = q_of(ref, dark, 0), lit = q_of(ref, dark, 1);
    printf("  darker base colour: base-colour q %.5f, lit q %.5f\n", base, lit);
    CHECK(q_of(ref, ref, 1) == 0.0);
    CHECK_MSG(base > 0.01 && lit > 0.01, "base %.5f lit %.5f", base, lit);
    texopt_model_destroy(ref);
    texopt_model_destroy(dark);
}

TEST(model_without_textures_is_refused)
{
    texopt_model *m = fixture_textured_quad(TEX, "checker");
    CHECK(m);
    m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR].image = -1;
    texopt_evaluate_options opt = {.resolution = 64, .lit = 1};
    texopt_evaluation ev;
    char err[256] = "";
    CHECK(texopt_evaluate(m, m, &opt, &ev, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    CHECK(strstr(err, "light") != NULL);
    texopt_model_destroy(m);
}

/* The light is fixed to the camera: towards it, above and to the right. */
TEST(light_comes_from_the_camera_side_upper_right)
{
    texopt_view view = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1};
    double l[3];
    texopt_lit_light(&view, l);
    CHECK_NEAR(l[0] * l[0] + l[1] * l[1] + l[2] * l[2], 1.0, 1e-12);
    CHECK(l[0] > 0 && l[1] > 0 && l[2] > l[0]);
    CHECK_NEAR(l[0], 0.5 / sqrt(0.99), 1e-12);
}

/* A 16 x 16 px view straight down onto the quad (right +x, up +y), its raster, the model's
 * tangent frames and the shading's scratch: the pixel-level tests below shade through it. */
#define HEAD_ON_SIDE 16
typedef struct head_on {
    texopt_view view;
    texopt_raster raster;
    texopt_lit_frames *frames;
    float *scratch;
} head_on;

static int head_on_init(head_on *h, const texopt_model *m)
{
    const texopt_view view = {{0.5, 0.5, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1};
    char err[256] = "";
    memset(h, 0, sizeof *h);
    h->view = view;
    if (texopt_meshrender_rasterize(m, &h->view, HEAD_ON_SIDE, &h->raster, err, sizeof err) != TEXOPT_OK ||
        texopt_lit_frames_create(m, &h->frames, err, sizeof err) != TEXOPT_OK) {
        printf("  head-on view: %s\n", err);
        return 0;
    }
    h->scratch = malloc(TEXOPT_LIT_SCRATCH_FLOATS * HEAD_ON_SIDE * HEAD_ON_SIDE * sizeof(float));
    return h->scratch != NULL;
}

static void head_on_free(head_on *h)
{
    free(h->scratch);
    texopt_lit_frames_destroy(h->frames);
    texopt_raster_destroy(&h->raster);
}

/* The lit luma of m through h into lit (HEAD_ON_SIDE^2 floats). */
static texopt_status head_on_shade(head_on *h, const texopt_model *m, float *lit, char *err, size_t err_len)
{
    return texopt_lit_shade(m, &h->raster, h->frames, NULL, NULL, h->scratch, lit, err, err_len);
}

/* The quad's u runs along world +x and v along +y, so glTF's normal-map X (+u) points to
 * +x and Y (up in the image, -v) to -y; the light comes from +x, +y: a map tilted to +X
 * lights the face more than a flat one, tilted to -X or +Y less. Checks the tangent frame's
 * T and B's sign (and that lighting reads the normal map at all). */
TEST(normal_map_tilted_towards_the_light_brightens_the_face)
{
    texopt_model *m = lit_quad(quad_uv);
    CHECK(m);
    head_on h;
    CHECK(head_on_init(&h, m));
    char err[256] = "";
    float lit[4][HEAD_ON_SIDE * HEAD_ON_SIDE];
    const float tilt[4][3] = {{0.5f, 0.5f, 1.0f}, {0.9f, 0.5f, 0.8f}, {0.1f, 0.5f, 0.8f}, {0.5f, 0.9f, 0.8f}};
    for (int k = 0; k < 4; k++) {
        texopt_image *n = &m->images[1];
        for (size_t i = 0; i < (size_t)n->width * (size_t)n->height; i++)
            memcpy(n->pixels + 3 * i, tilt[k], sizeof tilt[k]);
        CHECK_OK(head_on_shade(&h, m, lit[k], err, sizeof err), err);
    }
    size_t centre = 8 * HEAD_ON_SIDE + 8;
    printf("  flat %.4f, tilted to +X %.4f, to -X %.4f, to +Y %.4f\n", lit[0][centre], lit[1][centre], lit[2][centre],
           lit[3][centre]);
    CHECK(h.raster.triangle[centre] >= 0);
    CHECK(lit[1][centre] > lit[0][centre] && lit[0][centre] > lit[2][centre]);
    CHECK(lit[3][centre] < lit[0][centre]);
    head_on_free(&h);
    texopt_model_destroy(m);
}

/* Seen head-on, the half vector of the upper-right light lies between the face normal and the
 * light. A grey face whose normal map points at it shows a highlight when smooth and hardly
 * one when rough; with the face's own normal, 23 degrees off it, the smooth highlight has
 * fallen off and the rough lobe is the brighter; a metal is darker than a dielectric away from
 * its highlight (no diffuse, f0 its base colour). Checks roughness (G), metallic (B) and the
 * half vector. */
TEST(highlight_follows_roughness_and_metallic)
{
    texopt_model *m = lit_quad_with_material(quad_uv, 0.0f);
    CHECK(m);
    for (size_t i = 0; i < 3 * (size_t)TEX * TEX; i++)
        m->images[0].pixels[i] = 0.5f;
    head_on ho;
    CHECK(head_on_init(&ho, m));
    double l[3], h[3];
    texopt_lit_light(&ho.view, l);
    for (int k = 0; k < 3; k++)
        h[k] = l[k] + ho.view.direction[k];
    double hn = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    /* Tangent-space X is world +x, Y world -y (see the test above). */
    const float towards_h[3] = {(float)(0.5 + 0.5 * h[0] / hn), (float)(0.5 - 0.5 * h[1] / hn),
                                (float)(0.5 + 0.5 * h[2] / hn)};
    const float flat[3] = {0.5f, 0.5f, 1.0f};
    char err[256] = "";
    float lit[6][HEAD_ON_SIDE * HEAD_ON_SIDE];
    /* normal, roughness, metallic per case */
    const struct {
        const float *normal;
        float roughness, metallic;
    } cases[6] = {{towards_h, 0.2f, 0}, {towards_h, 1.0f, 0}, {flat, 0.2f, 0},
                  {flat, 1.0f, 0},      {flat, 1.0f, 1},      {flat, 0.2f, 1}};
    for (int k = 0; k < 6; k++) {
        for (size_t i = 0; i < (size_t)TEX * TEX; i++) {
            memcpy(m->images[1].pixels + 3 * i, cases[k].normal, 3 * sizeof(float));
            m->images[3].pixels[3 * i + 1] = cases[k].roughness;
            m->images[3].pixels[3 * i + 2] = cases[k].metallic;
        }
        CHECK_OK(head_on_shade(&ho, m, lit[k], err, sizeof err), err);
    }
    size_t c = 8 * HEAD_ON_SIDE + 8;
    printf("  towards h: smooth %.4f rough %.4f; face normal: smooth %.4f rough %.4f, rough metal %.4f, "
           "smooth metal %.4f\n",
           lit[0][c], lit[1][c], lit[2][c], lit[3][c], lit[4][c], lit[5][c]);
    CHECK(ho.raster.triangle[c] >= 0);
    CHECK_MSG(lit[0][c] > lit[1][c] + 0.2f, "smooth %.4f rough %.4f", lit[0][c], lit[1][c]);
    CHECK(lit[3][c] > lit[2][c]);
    CHECK(lit[4][c] < 0.75f * lit[3][c] && lit[5][c] < 0.75f * lit[2][c]); /* measured 0.54 and 0.38 */
    for (int k = 0; k < 6; k++)
        CHECK(lit[k][c] >= 0.0f && lit[k][c] <= 1.0f);
    head_on_free(&ho);
    texopt_model_destroy(m);
}

/* The shading normal is the vertex normals interpolated, as a viewer draws it: with the
 * quad's left corners' normals tilted to -x and its right corners' to +x, a grey quad with a
 * flat normal map is brighter on the right (the light comes from +x) and darker on the left
 * than flat shading; vertex normals equal to the face normal shade exactly as none. */
TEST(vertex_normals_are_interpolated_across_the_face)
{
    texopt_model *m = lit_quad(quad_uv);
    CHECK(m);
    for (size_t i = 0; i < 3 * (size_t)TEX * TEX; i++) {
        m->images[0].pixels[i] = 0.5f;
        m->images[2].pixels[i] = 1.0f;
    }
    fill_flat_normal(&m->images[1]);
    const size_t left = 8 * HEAD_ON_SIDE + 5, right = 8 * HEAD_ON_SIDE + 10;
    const float s = (float)(1.0 / sqrt(1.25));
    const float face[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float tilted[12] = {-0.5f * s, 0, s, 0.5f * s, 0, s, 0.5f * s, 0, s, -0.5f * s, 0, s};
    const float *cases[3] = {NULL, face, tilted};
    float lit[3][HEAD_ON_SIDE * HEAD_ON_SIDE];
    char err[256] = "";
    for (int k = 0; k < 3; k++) {
        float normals[12];
        if (cases[k])
            memcpy(normals, cases[k], sizeof normals);
        m->normals = cases[k] ? normals : NULL;
        head_on h;
        CHECK(head_on_init(&h, m));
        CHECK(h.raster.triangle[left] >= 0 && h.raster.triangle[right] >= 0);
        CHECK_OK(head_on_shade(&h, m, lit[k], err, sizeof err), err);
        head_on_free(&h);
        m->normals = NULL;
    }
    printf("  flat %.4f / %.4f, face normals %.4f / %.4f, tilted %.4f / %.4f (left / right)\n", lit[0][left],
           lit[0][right], lit[1][left], lit[1][right], lit[2][left], lit[2][right]);
    CHECK_NEAR(lit[0][left], lit[0][right], 1e-6);
    for (size_t i = 0; i < (size_t)HEAD_ON_SIDE * HEAD_ON_SIDE; i++)
        CHECK_NEAR(lit[1][i], lit[0][i], 1e-6);
    CHECK(lit[2][right] > lit[0][right] + 0.02f);
    CHECK(lit[2][left] < lit[0][left] - 0.02f);
    texopt_model_destroy(m);
}
