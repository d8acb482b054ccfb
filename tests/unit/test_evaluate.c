/* test_evaluate.c - whole-mesh loss q (engine/evaluate/evaluate.h) and the renderer under it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "evaluate.h"
#include "fixtures.h"
#include "gltf_io.h"
#include "gmsd.h"
#include "meshrender.h"
#include "resize.h"
#include "sample.h"
#include "test.h"

/* A sphere whose texture is the "half" pattern: flat on one side, text-like detail on the
 * other, so downscaling has something to destroy. */
static texopt_model *detailed_sphere(void)
{
    texopt_model *m = fixture_uv_sphere(48, 24, 256);
    if (m && fixture_fill_pattern(&m->images[0], "half") != 0) {
        texopt_model_destroy(m);
        return NULL;
    }
    return m;
}

/* Replaces image 0 of m by its resize to side x side. */
static int shrink_texture(texopt_model *m, int image, int side)
{
    texopt_image small;
    char err[256];
    if (texopt_image_resize(&m->images[image], side, side, &small, err, sizeof err) != TEXOPT_OK)
        return -1;
    texopt_image_destroy(&m->images[image]);
    m->images[image] = small;
    return 0;
}

TEST(identical_models_have_zero_loss)
{
    texopt_model *a = detailed_sphere(), *b = detailed_sphere();
    CHECK(a && b);
    char err[256] = "";
    texopt_evaluate_options opt = {.resolution = 256, .threads = 2};
    texopt_evaluation ev;
    CHECK_OK(texopt_evaluate(a, b, &opt, &ev, err, sizeof err), err);
    CHECK(ev.q == 0.0);
    CHECK_EQ_INT(ev.resolution, 256);
    CHECK_EQ_INT(ev.view_count, TEXOPT_VIEW_COUNT);
    for (int v = 0; v < TEXOPT_VIEW_COUNT; v++) {
        CHECK(ev.view_gmsd[v] == 0.0);
        /* The unit sphere fills pi/4 of a window 2.02 wide: 0.77 of the pixels. */
        CHECK_NEAR((double)ev.view_pixels[v] / (256.0 * 256.0), 3.14159265358979 / 4 / (1.01 * 1.01), 0.01);
    }
    texopt_model_destroy(a);
    texopt_model_destroy(b);
}

TEST(loss_grows_as_the_texture_is_downscaled)
{
    texopt_model *ref = detailed_sphere();
    CHECK(ref);
    char err[256] = "";
    const int sides[] = {192, 128, 64, 32};
    double last = 0;
    for (size_t i = 0; i < sizeof sides / sizeof sides[0]; i++) {
        texopt_model *cand = detailed_sphere();
        CHECK(cand);
        CHECK(shrink_texture(cand, 0, sides[i]) == 0);
        texopt_evaluate_options opt = {.resolution = 200, .threads = 2};
        texopt_evaluation ev;
        texopt_status st = texopt_evaluate(ref, cand, &opt, &ev, err, sizeof err);
        texopt_model_destroy(cand);
        CHECK_OK(st, err);
        CHECK_MSG(ev.q > last + 0.005, "side %d: q %.4f not above %.4f", sides[i], ev.q, last);
        last = ev.q;
    }
    CHECK(last > 0.1); /* 1/8 of the texels is far from invisible */
    texopt_model_destroy(ref);
}

/* The icosahedron's 12 cameras (for tuning on other views than q's): q is the mean of 12
 * views, close to but not the dodecahedron's, and 0 for the model itself. */
TEST(icosahedron_cameras_give_a_twelve_view_loss)
{
    texopt_model *ref = detailed_sphere(), *cand = detailed_sphere();
    CHECK(ref && cand);
    CHECK(shrink_texture(cand, 0, 64) == 0);
    char err[256] = "";
    texopt_evaluate_options dod = {.resolution = 160, .threads = 2}, ico = dod;
    ico.cameras = TEXOPT_CAMERAS_ICOSAHEDRON;
    texopt_evaluation a, b, self;
    CHECK_OK(texopt_evaluate(ref, cand, &dod, &a, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, cand, &ico, &b, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, ref, &ico, &self, err, sizeof err), err);
    CHECK_EQ_INT(b.view_count, 12);
    double sum = 0;
    for (int v = 0; v < 12; v++) {
        CHECK(b.view_pixels[v] > 0);
        sum += b.view_gmsd[v];
    }
    CHECK_NEAR(b.q, sum / 12, 1e-15);
    CHECK(b.q != a.q);
    CHECK_NEAR(b.q, a.q, 0.3 * a.q);
    CHECK(self.q == 0.0);
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
}

TEST(flat_texture_survives_any_downscale)
{
    texopt_model *ref = fixture_uv_sphere(24, 12, 128), *cand = fixture_uv_sphere(24, 12, 128);
    CHECK(ref && cand);
    CHECK(fixture_fill_pattern(&ref->images[0], "flat") == 0);
    CHECK(fixture_fill_pattern(&cand->images[0], "flat") == 0);
    CHECK(shrink_texture(cand, 0, 8) == 0);
    char err[256] = "";
    texopt_evaluate_options opt = {.resolution = 128};
    texopt_evaluation ev;
    CHECK_OK(texopt_evaluate(ref, cand, &opt, &ev, err, sizeof err), err);
    CHECK(ev.q < 1e-4);
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
}

/* A sphere of flat colour whose base colour's alpha cuts out a checkerboard of 16-texel
 * blocks, shown as alphaMode `mode`; its texture resized to `side` when side > 0. */
static texopt_model *perforated_sphere(texopt_alpha_mode mode, int side)
{
    texopt_model *m = fixture_uv_sphere(24, 12, 128);
    if (!m || fixture_fill_pattern(&m->images[0], "flat") != 0 || fixture_add_alpha(&m->images[0], "checker") != 0)
        return texopt_model_destroy(m), NULL;
    m->materials[0].alpha_mode = mode;
    m->materials[0].alpha_cutoff = 0.5;
    if (side > 0 && shrink_texture(m, 0, side) != 0)
        return texopt_model_destroy(m), NULL;
    return m;
}

TEST(a_cut_out_blurred_away_counts_where_the_material_shows_alpha)
{
    /* The flat colour survives the downscale (flat_texture_survives_any_downscale); the
     * cut-out's edges do not, which only a material showing its alpha makes visible. */
    const texopt_alpha_mode modes[3] = {TEXOPT_ALPHA_OPAQUE, TEXOPT_ALPHA_MASK, TEXOPT_ALPHA_BLEND};
    double q[3];
    for (int k = 0; k < 3; k++) {
        texopt_model *ref = perforated_sphere(modes[k], 0), *cand = perforated_sphere(modes[k], 8);
        CHECK(ref && cand);
        char err[256] = "";
        texopt_evaluate_options opt = {.resolution = 128};
        texopt_evaluation ev;
        CHECK_OK(texopt_evaluate(ref, cand, &opt, &ev, err, sizeof err), err);
        q[k] = ev.q;
        texopt_model_destroy(ref);
        texopt_model_destroy(cand);
    }
    printf("  q opaque %.5f, mask %.5f, blend %.5f\n", q[0], q[1], q[2]);
    CHECK(q[0] < 1e-4);
    CHECK_MSG(q[1] > 0.01 && q[2] > 0.01, "mask %g, blend %g", q[1], q[2]);
}

TEST(thread_count_does_not_change_the_result)
{
    texopt_model *ref = detailed_sphere(), *cand = detailed_sphere();
    CHECK(ref && cand);
    CHECK(shrink_texture(cand, 0, 64) == 0);
    char err[256] = "";
    texopt_evaluation one, two;
    double *tri_err = calloc(ref->triangle_count, sizeof(double));
    double *tri_err_one = calloc(ref->triangle_count, sizeof(double));
    CHECK(tri_err && tri_err_one);
    texopt_evaluate_options o1 = {.resolution = 200, .threads = 1, .triangle_error = tri_err_one};
    texopt_evaluate_options o2 = {.resolution = 200, .threads = 3, .triangle_error = tri_err};
    CHECK_OK(texopt_evaluate(ref, cand, &o1, &one, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, cand, &o2, &two, err, sizeof err), err);
    CHECK(one.q == two.q);
    /* To the last bit, also for the edge measure's irrational terms: the refinement steers by
     * these, and a job must not depend on which thread drew which view. */
    int same_bits = memcmp(tri_err, tri_err_one, ref->triangle_count * sizeof(double)) == 0;
    o1.triangle_error_edges = o2.triangle_error_edges = 1;
    o1.triangle_error = tri_err_one;
    double *edges_three = calloc(ref->triangle_count, sizeof(double));
    o2.triangle_error = edges_three;
    CHECK_OK(texopt_evaluate(ref, cand, &o1, &one, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, cand, &o2, &two, err, sizeof err), err);
    same_bits = same_bits && edges_three && memcmp(edges_three, tri_err_one, ref->triangle_count * sizeof(double)) == 0;
    free(edges_three);
    free(tri_err_one);
    CHECK(same_bits);
    /* Triangles on the flat half (u < 0.5, the texture's left half, away from the u = 0 seam where REPEAT wraps onto the detail) lose nothing; those on
     * the detailed half do. */
    double flat = 0, detail = 0;
    for (size_t t = 0; t < ref->triangle_count; t++) {
        const uint32_t *c = ref->triangles + 3 * t;
        double u = (ref->uvs[2 * c[0]] + ref->uvs[2 * c[1]] + ref->uvs[2 * c[2]]) / 3;
        if (u > 0.05 && u < 0.45)
            flat = fmax(flat, tri_err[t]);
        else if (u > 0.55)
            detail += tri_err[t];
    }
    free(tri_err);
    CHECK_MSG(flat < 0.02, "flat %g", flat);
    CHECK_MSG(detail > 1.0, "detail %g", detail);
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
}

/* Mean per-triangle error over the triangles whose centroid's u lies in [lo, hi). */
static double mean_error_between(const texopt_model *m, const double *tri_err, double lo, double hi)
{
    double sum = 0;
    size_t n = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *c = m->triangles + 3 * t;
        double u = (m->uvs[2 * c[0]] + m->uvs[2 * c[1]] + m->uvs[2 * c[2]]) / 3;
        if (u >= lo && u < hi) {
            sum += tri_err[t];
            n++;
        }
    }
    return n ? sum / (double)n : NAN;
}

/* The edge measure (triangle_error_edges) sees blurred detail and not a brightness shift of
 * a flat region, which the absolute difference sees as well. */
TEST(edge_error_weighs_blurred_detail_and_not_a_flat_shift)
{
    texopt_model *ref = detailed_sphere(), *cand = detailed_sphere();
    CHECK(ref && cand);
    CHECK(shrink_texture(cand, 0, 64) == 0);
    texopt_image *img = &cand->images[0];
    for (int y = 0; y < img->height; y++)
        for (int x = 1; x < img->width / 2 - 1; x++) /* the flat half, brighter */
            for (int k = 0; k < 3 && k < img->channels; k++)
                img->pixels[((size_t)y * img->width + x) * img->channels + k] += 0.15f;
    double *absolute = calloc(ref->triangle_count, sizeof(double));
    double *edges = calloc(ref->triangle_count, sizeof(double));
    CHECK(absolute && edges);
    char err[256] = "";
    texopt_evaluate_options opt = {.resolution = 200, .threads = 2, .triangle_error = absolute};
    texopt_evaluation a, b;
    CHECK_OK(texopt_evaluate(ref, cand, &opt, &a, err, sizeof err), err);
    opt.triangle_error = edges;
    opt.triangle_error_edges = 1;
    CHECK_OK(texopt_evaluate(ref, cand, &opt, &b, err, sizeof err), err);
    CHECK(a.q == b.q); /* the measure of the triangles does not change q */
    double flat_abs = mean_error_between(ref, absolute, 0.1, 0.4);
    double flat_edge = mean_error_between(ref, edges, 0.1, 0.4);
    double detail_abs = mean_error_between(ref, absolute, 0.6, 0.9);
    double detail_edge = mean_error_between(ref, edges, 0.6, 0.9);
    CHECK_MSG(flat_abs > 0.05, "flat, absolute %g", flat_abs);
    CHECK_MSG(flat_edge < 0.01, "flat, edges %g", flat_edge);
    CHECK_MSG(detail_edge > 5 * flat_edge && detail_edge > 0.05, "detail, edges %g", detail_edge);
    CHECK_MSG(detail_abs > 0.02, "detail, absolute %g", detail_abs);
    for (size_t t = 0; t < ref->triangle_count; t++)
        CHECK(edges[t] >= 0 && isfinite(edges[t]));
    free(absolute);
    free(edges);
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
}

/* GMSD of one view computed here from the renderer's pieces with the plain (unprepared)
 * GMSD, as an independent check of the evaluation's per-view value. */
static double direct_view_gmsd(const texopt_model *ref, const texopt_model *cand, int view, int side)
{
    texopt_view views[TEXOPT_VIEW_COUNT];
    texopt_raster r;
    texopt_image a = {0}, b = {0};
    char err[256];
    if (texopt_meshrender_views(ref, views, err, sizeof err) != TEXOPT_OK ||
        texopt_meshrender_rasterize(ref, &views[view], side, &r, err, sizeof err) != TEXOPT_OK)
        return NAN;
    size_t n = (size_t)side * side;
    float *la = malloc(n * sizeof(float)), *lb = malloc(n * sizeof(float));
    unsigned char *mask = malloc(n);
    double g = NAN;
    if (la && lb && mask && texopt_meshrender_shade(ref, &r, &a, err, sizeof err) == TEXOPT_OK &&
        texopt_meshrender_shade(cand, &r, &b, err, sizeof err) == TEXOPT_OK) {
        for (size_t i = 0; i < n; i++) {
            la[i] = texopt_luma(a.pixels + 3 * i, 3);
            lb[i] = texopt_luma(b.pixels + 3 * i, 3);
            mask[i] = r.triangle[i] >= 0;
        }
        g = texopt_gmsd(la, lb, mask, side, side);
    }
    free(la);
    free(lb);
    free(mask);
    texopt_image_destroy(&a);
    texopt_image_destroy(&b);
    texopt_raster_destroy(&r);
    return g;
}

static int same_evaluation(const texopt_evaluation *a, const texopt_evaluation *b)
{
    int same = a->q == b->q && a->resolution == b->resolution;
    for (int v = 0; v < TEXOPT_VIEW_COUNT; v++)
        same = same && a->view_gmsd[v] == b->view_gmsd[v] && a->view_pixels[v] == b->view_pixels[v];
    return same;
}

TEST(several_candidates_score_exactly_as_each_alone)
{
    texopt_model *ref = detailed_sphere(), *c1 = detailed_sphere(), *c2 = detailed_sphere();
    CHECK(ref && c1 && c2);
    CHECK(shrink_texture(c1, 0, 96) == 0);
    CHECK(shrink_texture(c2, 0, 32) == 0);
    const texopt_model *cands[3] = {c1, c2, ref};
    char err[256] = "";
    for (int mip = 0; mip < 2; mip++) {
        texopt_evaluate_options many = {.resolution = 160, .threads = 2, .mipmapped = mip};
        texopt_evaluate_options alone = {.resolution = 160, .threads = 1, .mipmapped = mip};
        texopt_evaluation all[3], one;
        CHECK_OK(texopt_evaluate_many(ref, cands, 3, &many, all, err, sizeof err), err);
        for (int c = 0; c < 3; c++) {
            CHECK_OK(texopt_evaluate(ref, cands[c], &alone, &one, err, sizeof err), err);
            CHECK_MSG(same_evaluation(&all[c], &one), "mipmapped %d candidate %d: q %.6g alone %.6g", mip, c, all[c].q,
                      one.q);
        }
        CHECK(all[0].q > 0.01 && all[1].q > all[0].q && all[2].q == 0.0);
    }
    texopt_evaluate_options plain = {.resolution = 160, .threads = 2};
    texopt_evaluation all[2];
    CHECK_OK(texopt_evaluate_many(ref, cands, 2, &plain, all, err, sizeof err), err);
    for (int v = 0; v < TEXOPT_VIEW_COUNT; v += 7)
        CHECK(all[1].view_gmsd[v] == direct_view_gmsd(ref, c2, v, 160));
    /* Per-triangle errors belong to one candidate. */
    double *tri_err = calloc(ref->triangle_count, sizeof(double));
    plain.triangle_error = tri_err;
    CHECK(texopt_evaluate_many(ref, cands, 2, &plain, all, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    free(tri_err);
    /* Every candidate must have the reference's triangles. */
    texopt_model *other = fixture_uv_sphere(24, 12, 64);
    const texopt_model *mixed[2] = {c1, other};
    plain.triangle_error = NULL;
    CHECK(other && texopt_evaluate_many(ref, mixed, 2, &plain, all, err, sizeof err) != TEXOPT_OK);
    CHECK(texopt_evaluate_many(ref, cands, 0, &plain, all, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_model_destroy(other);
    texopt_model_destroy(ref);
    texopt_model_destroy(c1);
    texopt_model_destroy(c2);
}

TEST(mipmapped_lookups_are_reported_separately)
{
    texopt_model *ref = detailed_sphere(), *cand = detailed_sphere();
    CHECK(ref && cand);
    char err[256] = "";
    texopt_evaluate_options mip = {.resolution = 160, .threads = 2, .mipmapped = 1};
    texopt_evaluate_options lin = {.resolution = 160, .threads = 2};
    texopt_evaluation same, a, b;
    CHECK_OK(texopt_evaluate(ref, cand, &mip, &same, err, sizeof err), err);
    CHECK(same.q == 0.0);
    CHECK(shrink_texture(cand, 0, 48) == 0);
    CHECK_OK(texopt_evaluate(ref, cand, &mip, &a, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, cand, &lin, &b, err, sizeof err), err);
    CHECK(a.q > 0.02 && b.q > 0.02);
    /* Prefiltering blurs the reference too, so the two figures are not the same. */
    CHECK(fabs(a.q - b.q) > 1e-4);
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
}

/* Adds a 256 x 256 normal map of `pattern` (image 1) to a detailed sphere's material. */
static texopt_model *sphere_with_normal_map(const char *pattern)
{
    texopt_model *m = detailed_sphere();
    char err[256];
    texopt_image *images = m ? realloc(m->images, 2 * sizeof *images) : NULL;
    if (images)
        m->images = images;
    char **names = images ? realloc(m->image_names, 2 * sizeof *names) : NULL;
    if (!names) {
        texopt_model_destroy(m);
        return NULL;
    }
    m->image_names = names;
    names[1] = NULL;
    if (texopt_image_create(&m->images[1], 256, 256, 3, err, sizeof err) != TEXOPT_OK) {
        texopt_model_destroy(m);
        return NULL;
    }
    m->image_count = 2;
    if (fixture_fill_pattern(&m->images[1], pattern) != 0) {
        texopt_model_destroy(m);
        return NULL;
    }
    m->materials[0].slot[TEXOPT_SLOT_NORMAL] = m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR];
    m->materials[0].slot[TEXOPT_SLOT_NORMAL].image = 1;
    return m;
}

/* The slot option really reads the normal map: a downscaled normal map is seen by the
 * normal slot (bilinear and mip-mapped) and not by base colour, a downscaled base colour the
 * other way round, and a model against itself is 0 in every slot. */
TEST(normal_slot_sees_the_normal_map_and_only_it)
{
    texopt_model *ref = sphere_with_normal_map("stripes45"), *coarse_normal = sphere_with_normal_map("stripes45"),
                 *coarse_base = sphere_with_normal_map("stripes45");
    CHECK(ref && coarse_normal && coarse_base);
    CHECK(shrink_texture(coarse_normal, 1, 32) == 0);
    CHECK(shrink_texture(coarse_base, 0, 32) == 0);
    char err[256] = "";
    for (int mip = 0; mip <= 1; mip++) {
        texopt_evaluate_options base = {.resolution = 200, .threads = 2, .mipmapped = mip}, normal = base;
        normal.texture = TEXOPT_SLOT_NORMAL;
        texopt_evaluation self, n_of_n, b_of_n, n_of_b, b_of_b;
        CHECK_OK(texopt_evaluate(ref, ref, &normal, &self, err, sizeof err), err);
        CHECK_OK(texopt_evaluate(ref, coarse_normal, &normal, &n_of_n, err, sizeof err), err);
        CHECK_OK(texopt_evaluate(ref, coarse_normal, &base, &b_of_n, err, sizeof err), err);
        CHECK_OK(texopt_evaluate(ref, coarse_base, &normal, &n_of_b, err, sizeof err), err);
        CHECK_OK(texopt_evaluate(ref, coarse_base, &base, &b_of_b, err, sizeof err), err);
        CHECK(self.q == 0.0);
        CHECK_MSG(n_of_n.q > 0.05, "mip %d: normal map at 1/8: normal q %.4f", mip, n_of_n.q);
        CHECK(b_of_n.q == 0.0);
        CHECK(n_of_b.q == 0.0);
        CHECK(b_of_b.q > 0.05);
    }
    texopt_model_destroy(ref);
    texopt_model_destroy(coarse_normal);
    texopt_model_destroy(coarse_base);
}

/* sphere_with_normal_map's second image bound as a sheen colour map instead. */
static texopt_model *sphere_with_sheen_map(void)
{
    texopt_model *m = sphere_with_normal_map("checker");
    if (m) {
        texopt_material *mat = &m->materials[0];
        mat->extra[0] = (texopt_extra_texture){mat->slot[TEXOPT_SLOT_NORMAL], TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB,
                                               "sheenColorTexture"};
        mat->extra_count = 1;
        mat->slot[TEXOPT_SLOT_NORMAL].image = -1;
    }
    return m;
}

/* A material extension's texture is measured by its key: a downscaled sheen map is seen
 * there and not by base colour, a downscaled base colour the other way round. */
TEST(an_extension_texture_is_measured_by_its_key)
{
    texopt_model *ref = sphere_with_sheen_map(), *coarse_sheen = sphere_with_sheen_map();
    texopt_model *coarse_base = sphere_with_sheen_map();
    CHECK(ref && coarse_sheen && coarse_base);
    CHECK(shrink_texture(coarse_sheen, 1, 32) == 0);
    CHECK(shrink_texture(coarse_base, 0, 32) == 0);
    char err[256] = "";
    texopt_evaluate_options base = {.resolution = 200, .threads = 2}, sheen = base;
    CHECK(texopt_evaluate_select_measure(&sheen, "sheenColorTexture") == 0);
    CHECK(strcmp(texopt_evaluate_measure_name(&sheen), "sheenColorTexture") == 0);
    texopt_evaluation self, s_of_s, b_of_s, s_of_b;
    CHECK_OK(texopt_evaluate(ref, ref, &sheen, &self, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, coarse_sheen, &sheen, &s_of_s, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, coarse_sheen, &base, &b_of_s, err, sizeof err), err);
    CHECK_OK(texopt_evaluate(ref, coarse_base, &sheen, &s_of_b, err, sizeof err), err);
    CHECK(self.q == 0.0);
    CHECK_MSG(s_of_s.q > 0.05, "sheen map at 1/8: sheen q %.4f", s_of_s.q);
    CHECK(b_of_s.q == 0.0);
    CHECK(s_of_b.q == 0.0);
    texopt_model_destroy(ref);
    texopt_model_destroy(coarse_sheen);
    texopt_model_destroy(coarse_base);
}

/* A reference without the texture is refused (its q would be a meaningless 0); a candidate
 * that lost it is measured as mid grey against the map. */
TEST(a_texture_the_reference_lacks_is_refused)
{
    texopt_model *plain = detailed_sphere(), *mapped = sphere_with_normal_map("checker");
    CHECK(plain && mapped);
    char err[256] = "";
    texopt_evaluate_options opt = {.resolution = 96, .texture = TEXOPT_SLOT_NORMAL};
    texopt_evaluation ev;
    CHECK(texopt_evaluate(plain, plain, &opt, &ev, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    CHECK(strstr(err, "normal") != NULL);
    CHECK_OK(texopt_evaluate(mapped, plain, &opt, &ev, err, sizeof err), err);
    CHECK(ev.q > 0.05);
    opt.texture = TEXOPT_SLOT_EMISSIVE;
    CHECK(texopt_evaluate(mapped, mapped, &opt, &ev, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    opt.texture = texopt_texture_key_from_name("clearcoatTexture");
    CHECK(texopt_evaluate(mapped, mapped, &opt, &ev, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    CHECK(strstr(err, "clearcoatTexture") != NULL);
    opt.texture = TEXOPT_TEXTURE_KEY_COUNT;
    CHECK(texopt_evaluate(mapped, mapped, &opt, &ev, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    opt.texture = -1;
    CHECK(texopt_evaluate(mapped, mapped, &opt, &ev, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_model_destroy(plain);
    texopt_model_destroy(mapped);
}

TEST(texture_names_are_the_gltf_fields_and_short_forms)
{
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("baseColor"), TEXOPT_SLOT_BASE_COLOR);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("base"), TEXOPT_SLOT_BASE_COLOR);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("Normal"), TEXOPT_SLOT_NORMAL);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("metallicroughness"), TEXOPT_SLOT_METALLIC_ROUGHNESS);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("mr"), TEXOPT_SLOT_METALLIC_ROUGHNESS);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("occlusion"), TEXOPT_SLOT_OCCLUSION);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("ao"), TEXOPT_SLOT_OCCLUSION);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("emissive"), TEXOPT_SLOT_EMISSIVE);
    int sheen = texopt_evaluate_texture_from_name("SheenColorTexture");
    CHECK(sheen >= TEXOPT_SLOT_COUNT && sheen < TEXOPT_TEXTURE_KEY_COUNT);
    CHECK(strcmp(texopt_texture_key_name(sheen), "sheenColorTexture") == 0);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("sheenColor"), -1);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name("normals"), -1);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name(""), -1);
    CHECK_EQ_INT(texopt_evaluate_texture_from_name(NULL), -1);
}

TEST(different_geometry_is_refused)
{
    texopt_model *a = fixture_uv_sphere(24, 12, 64), *b = fixture_uv_sphere(24, 12, 64);
    texopt_model *c = fixture_uv_sphere(20, 12, 64);
    CHECK(a && b && c);
    b->positions[3 * b->triangles[3 * 7 + 1]] += 0.1f;
    char err[256] = "";
    texopt_evaluation ev;
    CHECK(texopt_evaluate(a, b, NULL, &ev, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle") != NULL);
    CHECK(texopt_evaluate(a, c, NULL, &ev, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_evaluate_options bad = {.resolution = 3};
    CHECK(texopt_evaluate(a, a, &bad, &ev, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_model_destroy(a);
    texopt_model_destroy(b);
    texopt_model_destroy(c);
}

TEST(default_resolution_shows_a_texel_per_pixel)
{
    /* The quad covers its whole 200^2 texture: 1.25 * 200 = 250. */
    texopt_model *quad = fixture_textured_quad(200, "checker");
    CHECK(quad);
    int side = 0;
    char err[256] = "";
    CHECK_OK(texopt_evaluate_default_resolution(quad, &side, err, sizeof err), err);
    CHECK_EQ_INT(side, 250);
    texopt_model_destroy(quad);
}
TEST(spot_loss_grows_with_downscale)
{
    char path[1024], err[256] = "";
    snprintf(path, sizeof path, "%s/spot/spot.glb", TEXOPT_TEST_DATA_DIR);
    texopt_model *ref = NULL, *cand = NULL;
    CHECK_OK(texopt_model_load(&ref, path, NULL, err, sizeof err), err);
    CHECK_OK(texopt_model_load(&cand, path, NULL, err, sizeof err), err);
    int side = 0;
    CHECK_OK(texopt_evaluate_default_resolution(ref, &side, err, sizeof err), err);
    /* 515805 covered texels (of 1024^2): 1.25 * 718.2 = 898. */
    CHECK_EQ_INT(side, 898);
    int image = ref->materials[ref->primitives[0].material].slot[TEXOPT_SLOT_BASE_COLOR].image;
    CHECK(image >= 0);
    double last = 0;
    int bad_size = 0; /* the first size whose loss did not grow */
    const int sizes[] = {512, 256, 128};
    texopt_status st = TEXOPT_OK;
    for (size_t i = 0; i < 3 && st == TEXOPT_OK; i++) {
        texopt_image small;
        st = texopt_image_resize(&ref->images[image], sizes[i], sizes[i], &small, err, sizeof err);
        if (st != TEXOPT_OK)
            break;
        texopt_image_destroy(&cand->images[image]);
        cand->images[image] = small;
        texopt_evaluate_options opt = {.resolution = 384, .threads = 2};
        texopt_evaluation ev;
        st = texopt_evaluate(ref, cand, &opt, &ev, err, sizeof err);
        if (st == TEXOPT_OK && !(ev.q > last) && !bad_size)
            bad_size = sizes[i];
        last = ev.q;
    }
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
    CHECK_OK(st, err);
    CHECK_MSG(bad_size == 0, "texture %d: loss did not grow", bad_size);
    CHECK(last > 0.02); /* an eighth of the texture per side is plainly visible */
}
