/* Tests of info.c: the `texopt info` document on fixtures with known answers, on a loaded
 * sample model, and its refusals. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "gltf_io.h"
#include "info.h"
#include "sliver_grids.h"
#include "test.h"

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static const char *str(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : "";
}

static const cJSON *domain(const cJSON *doc, int i)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(doc, "domains"), i);
}

TEST(cube_document_has_the_constructed_numbers)
{
    texopt_model *model = fixture_cube_with_seams(64);
    CHECK(model != NULL);
    cJSON *doc = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    CHECK_NEAR(num(doc, "vertices"), 24, 0);
    CHECK_NEAR(num(doc, "triangles"), 12, 0);
    CHECK_NEAR(num(doc, "primitives"), 1, 0);
    CHECK_NEAR(num(doc, "untextured_primitives"), 0, 0);
    CHECK_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(doc, "images")), 1);
    CHECK_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(doc, "domains")), 1);
    const cJSON *d = domain(doc, 0);
    CHECK_NEAR(num(d, "triangles"), 12, 0);
    CHECK_NEAR(num(d, "model_vertices"), 24, 0);
    CHECK_NEAR(num(d, "uv_vertices"), 18, 0);
    CHECK_NEAR(num(d, "points"), 8, 0);
    CHECK_NEAR(num(d, "charts"), 3, 0);
    CHECK_NEAR(num(d, "mirrored_charts"), 0, 0);
    CHECK_NEAR(num(d, "folded_charts"), 0, 0);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(d, "frame"), "width"), 64, 0);
    CHECK(strcmp(str(cJSON_GetObjectItemCaseSensitive(d, "wrap"), "s"), "repeat") == 0);
    const cJSON *tex = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(d, "textures"), 0);
    CHECK(strcmp(str(tex, "slot"), "baseColor") == 0);
    CHECK(strcmp(str(tex, "name"), "fixture_checker") == 0);
    CHECK_NEAR(num(tex, "channels"), 3, 0);
    CHECK(strcmp(str(tex, "reads"), "RGB") == 0);
    CHECK(cJSON_GetObjectItemCaseSensitive(tex, "magnify") == NULL);
    CHECK_NEAR(num(d, "covered_texels"), 6 * 16 * 16, 0);
    CHECK_NEAR(num(d, "overlap_texels"), 0, 0);
    CHECK_NEAR(num(d, "packing_efficiency"), 0.375, 0);
    CHECK_NEAR(num(d, "texel_area"), 1536, 1e-9);
    CHECK_NEAR(num(d, "area_3d"), 6, 1e-12);
    CHECK_NEAR(num(d, "flipped") + num(d, "overlapping") + num(d, "degenerate") + num(d, "wrapped"), 0, 0);
    /* Each face is a 16 x 16 texel square: an isometry up to scale, every metric minimal. */
    const cJSON *dist = cJSON_GetObjectItemCaseSensitive(d, "distortion");
    CHECK_NEAR(num(dist, "counted"), 12, 0);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(dist, "symmetric_dirichlet"), "max"), 4.0, 1e-12);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(dist, "mips"), "mean"), 2.0, 1e-12);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(dist, "isometric"), "mean"), sqrt(2.0), 1e-12);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(dist, "l2_stretch"), "max"), 1.0, 1e-12);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(dist, "area"), "max"), 1.0, 1e-12);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

TEST(extension_textures_are_listed_under_their_key)
{
    texopt_model *model = fixture_cube_with_seams(64);
    CHECK(model != NULL);
    texopt_material *mat = &model->materials[0];
    mat->extra[0].ref = mat->slot[TEXOPT_SLOT_BASE_COLOR];
    mat->extra[0].ref.wrap_s = TEXOPT_WRAP_CLAMP;
    mat->extra[0].kind = TEXOPT_TEXTURE_DATA;
    mat->extra[0].channels = TEXOPT_CHANNEL_A;
    mat->extra[0].name = "specularTexture";
    mat->extra_count = 1;
    mat->alpha_mode = TEXOPT_ALPHA_MASK;
    cJSON *doc = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    const cJSON *textures = cJSON_GetObjectItemCaseSensitive(domain(doc, 0), "textures");
    CHECK_EQ_INT(cJSON_GetArraySize(textures), 2);
    const cJSON *tex = cJSON_GetArrayItem(textures, 1);
    CHECK(strcmp(str(tex, "slot"), "specularTexture") == 0);
    CHECK_NEAR(num(tex, "image"), 0, 0);
    CHECK(strcmp(str(tex, "wrap_s"), "clamp") == 0);
    CHECK(strcmp(str(tex, "reads"), "A") == 0);
    /* A MASK material's base colour is read with its alpha. */
    CHECK(strcmp(str(cJSON_GetArrayItem(textures, 0), "reads"), "RGBA") == 0);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

/* A texture its sampler magnifies NEAREST (pixel art, which the layout methods keep as it is)
 * says so. */
TEST(a_texture_magnified_nearest_says_so)
{
    texopt_model *model = fixture_textured_quad(16, "gradient");
    CHECK(model != NULL);
    model->materials[0].slot[TEXOPT_SLOT_BASE_COLOR].magnify_nearest = 1;
    cJSON *doc = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    const cJSON *tex = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(domain(doc, 0), "textures"), 0);
    CHECK(strcmp(str(tex, "magnify"), "nearest") == 0);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

/* The reads of the quad's one texture when its two triangles' materials have these modes. */
static void check_shared_reads(texopt_alpha_mode first, texopt_alpha_mode second, const char *want)
{
    texopt_model *model = fixture_textured_quad(16, "gradient");
    CHECK(model != NULL && fixture_split_primitive(model, 1) == 0);
    model->materials[0].alpha_mode = first;
    model->materials[1].alpha_mode = second;
    cJSON *doc = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    CHECK_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(doc, "domains")), 1);
    const cJSON *textures = cJSON_GetObjectItemCaseSensitive(domain(doc, 0), "textures");
    CHECK_EQ_INT(cJSON_GetArraySize(textures), 1);
    const char *reads = str(cJSON_GetArrayItem(textures, 0), "reads");
    CHECK_MSG(strcmp(reads, want) == 0, "modes %d, %d: reads %s, not %s", (int)first, (int)second, reads, want);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

/* Whichever material comes first, a base colour that one material cuts out by its alpha
 * is read in RGBA. */
TEST(a_texture_two_materials_share_reads_what_either_reads)
{
    check_shared_reads(TEXOPT_ALPHA_OPAQUE, TEXOPT_ALPHA_BLEND, "RGBA");
    check_shared_reads(TEXOPT_ALPHA_MASK, TEXOPT_ALPHA_OPAQUE, "RGBA");
    check_shared_reads(TEXOPT_ALPHA_OPAQUE, TEXOPT_ALPHA_OPAQUE, "RGB");
}

/* A variant material (KHR_materials_variants) reading its own image through TEXCOORD_0 puts
 * that image in the primitive's domain, and info lists it there. */
TEST(a_variant_material_s_texture_belongs_to_the_domain)
{
    texopt_model *model = fixture_textured_quad(16, "gradient");
    CHECK(model != NULL);
    texopt_image *images = realloc(model->images, 2 * sizeof *images);
    char **names = realloc(model->image_names, 2 * sizeof *names);
    texopt_material *mats = realloc(model->materials, 2 * sizeof *mats);
    if (images)
        model->images = images;
    if (names)
        model->image_names = names;
    if (mats)
        model->materials = mats;
    CHECK(images && names && mats && (model->variant_materials = malloc(sizeof(int))) != NULL);
    CHECK(texopt_image_create(&images[1], 8, 8, 3, NULL, 0) == TEXOPT_OK &&
          fixture_fill_pattern(&images[1], "flat") == 0);
    names[1] = NULL;
    model->image_count = 2;
    mats[1] = mats[0];
    mats[1].slot[TEXOPT_SLOT_BASE_COLOR].image = 1;
    model->material_count = 2;
    model->variant_materials[0] = 1;
    model->primitives[0].first_variant = 0;
    model->primitives[0].variant_count = 1;
    char err[256] = "";
    CHECK_OK(texopt_model_build_domains(model, err, sizeof err), err);
    CHECK_EQ_INT(model->domain_count, 1);
    CHECK_EQ_INT(model->domains[0].image_count, 2);
    cJSON *doc = NULL;
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    const cJSON *textures = cJSON_GetObjectItemCaseSensitive(domain(doc, 0), "textures");
    CHECK_EQ_INT(cJSON_GetArraySize(textures), 2);
    CHECK_EQ_INT(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(textures, 1), "image")->valueint, 1);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

TEST(mirrored_and_wrapped_layout_is_reported)
{
    /* Quad A on the UV square; quad B elsewhere in 3D, mirrored onto the same square and
     * shifted by one period (u in [1, 2]): REPEAT reads the same texels. */
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 3, 0, 0, 4, 0, 0, 4, 1, 0, 3, 1, 0};
    const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1, 2, 0, 1, 0, 1, 1, 2, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    texopt_model *model = fixture_model_from_arrays(pos, uv, 8, tri, 4, 16, 16, "half");
    CHECK(model != NULL);
    char *text = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_string(model, 0, &text, err, sizeof err), err);
    CHECK(strchr(text, '\n') == NULL); /* unformatted: one line */
    cJSON *doc = cJSON_Parse(text);
    free(text);
    CHECK(doc != NULL);
    const cJSON *d = domain(doc, 0);
    CHECK_NEAR(num(d, "charts"), 2, 0);
    /* equal areas: the tie makes the positive chart the majority, the other mirrored */
    CHECK_NEAR(num(d, "mirrored_charts"), 1, 0);
    CHECK_NEAR(num(d, "covered_texels"), 256, 0);
    CHECK_NEAR(num(d, "overlap_texels"), 256, 0);
    CHECK_NEAR(num(d, "overlapping"), 4, 0);
    CHECK_NEAR(num(d, "wrapped"), 2, 0);
    CHECK_NEAR(num(d, "flipped"), 0, 0);
    CHECK_NEAR(num(d, "packing_efficiency"), 1.0, 0);
    CHECK_NEAR(num(d, "texel_area"), 512, 1e-9);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

TEST(pretty_text_parses_to_the_same_document)
{
    texopt_model *model = fixture_uv_sphere(8, 5, 64);
    CHECK(model != NULL);
    char *pretty = NULL, *flat = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_string(model, 1, &pretty, err, sizeof err), err);
    CHECK_OK(texopt_info_string(model, 0, &flat, err, sizeof err), err);
    CHECK(strchr(pretty, '\n') != NULL);
    cJSON *a = cJSON_Parse(pretty), *b = cJSON_Parse(flat);
    free(pretty);
    free(flat);
    CHECK(a && b);
    CHECK(cJSON_Compare(a, b, 1));
    CHECK_NEAR(num(domain(a, 0), "points"), 8 * 4 + 2, 0);
    cJSON_Delete(a);
    cJSON_Delete(b);
    texopt_model_destroy(model);
}

TEST(layout_too_large_to_rasterise_still_gets_a_document)
{
    texopt_model *model = fixture_textured_quad(8, "flat");
    CHECK(model != NULL);
    model->uvs[2 * 2] = 6000.0f; /* vertex (1,1) -> u = 6000: thousands of repeats */
    cJSON *doc = NULL;
    char err[256] = "";
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    const cJSON *d = domain(doc, 0);
    CHECK(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(d, "covered_texels")));
    CHECK(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(d, "packing_efficiency")));
    CHECK(strstr(str(d, "coverage_error"), "repeats") != NULL);
    CHECK_NEAR(num(d, "triangles"), 2, 0);
    CHECK_NEAR(num(d, "wrapped"), 2, 0);
    CHECK(num(d, "texel_area") > 8 * 8 * 1000);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

TEST(failures_name_the_domain)
{
    texopt_model *model = fixture_textured_quad(8, "flat");
    CHECK(model != NULL);
    model->uvs[2] = INFINITY;
    cJSON *doc = (cJSON *)1;
    char err[256] = "";
    CHECK(texopt_info_json(model, &doc, err, sizeof err) == TEXOPT_E_MALFORMED);
    CHECK(doc == NULL);
    CHECK(strstr(err, "texture domain 0") != NULL);
    CHECK(strstr(err, "non-finite UV") != NULL);
    CHECK(texopt_info_json(NULL, &doc, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strcmp(texopt_wrap_name(TEXOPT_WRAP_MIRROR), "mirror") == 0);
    CHECK(strcmp(texopt_slot_name(TEXOPT_SLOT_METALLIC_ROUGHNESS), "metallicRoughness") == 0);
    texopt_model_destroy(model);
}

TEST(spot_document_matches_its_file)
{
    /* spot.glb: one primitive, 5856 triangles, one 1024^2 base colour texture; the counts of
     * UV vertices and points were checked independently (numpy over the accessors, see
     * tests/integration/info_models.sh). */
    texopt_model *model = NULL;
    char err[512] = "";
    texopt_load_options opt = {.skip_images = 1};
    CHECK_OK(texopt_model_load(&model, TEXOPT_TEST_DATA_DIR "/spot/spot.glb", &opt, err, sizeof err), err);
    cJSON *doc = NULL;
    CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
    const cJSON *d = domain(doc, 0);
    CHECK_NEAR(num(d, "triangles"), 5856, 0);
    CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(d, "frame"), "width"), 1024, 0);
    CHECK(num(d, "points") < num(d, "uv_vertices")); /* seams split UV vertices */
    CHECK_NEAR(num(d, "overlap_texels"), 0, 0);
    /* no overlap: unique texels agree with the texel area up to the chart boundaries */
    CHECK(fabs(num(d, "covered_texels") - num(d, "texel_area")) < 0.01 * num(d, "texel_area"));
    CHECK_NEAR(num(d, "packing_efficiency"), num(d, "covered_texels") / (1024.0 * 1024.0), 1e-12);
    cJSON_Delete(doc);
    texopt_model_destroy(model);
}

/* The layout check of info on the model's own layout (layout_check.h): mirrored twins laid
 * on one region are one sharing group and pass; the twin shifted a quarter of the frame off
 * (half its texels on the other's, under texel_share.h's 90%) is another group and fails
 * "overlap"; the texture pixels are the image's. */
TEST(the_layout_check_tells_shared_twins_from_overlapping_charts)
{
    sliver_grid g;
    CHECK(sliver_grid_make(&g, 8, 0.5, 1) == 0);
    for (int shifted = 0; shifted < 2; shifted++) {
        for (size_t v = g.vertex_count / 2; shifted && v < g.vertex_count; v++)
            g.uvs[2 * v] += 0.45f;
        texopt_model *model = fixture_model_from_arrays(g.positions, g.uvs, g.vertex_count, g.triangles,
                                                        g.triangle_count, 64, 64, "checker");
        CHECK(model != NULL);
        cJSON *doc = NULL;
        char err[256] = "";
        CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
        const cJSON *check = cJSON_GetObjectItemCaseSensitive(domain(doc, 0), "layout_check");
        CHECK_NEAR(num(cJSON_GetObjectItemCaseSensitive(doc, "file_cost"), "texture_pixels"), 64 * 64, 0);
        CHECK(cJSON_IsBool(cJSON_GetObjectItemCaseSensitive(check, "passed")));
        CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(check, "passed")) == !shifted);
        CHECK(strcmp(str(check, "failed"), shifted ? "overlap" : "") == 0);
        CHECK((num(check, "overlapping_triangles") > 0) == shifted);
        cJSON_Delete(doc);
        texopt_model_destroy(model);
    }
    sliver_grid_free(&g);
}

/* A fan of right triangles (legs of 20 texels on integer corners, 190 texel centres strictly
 * inside each) around one vertex: past a full turn its fifth triangle lies on its first, one
 * chart over itself with one orientation, which info's layout check counts (and passes);
 * three quarters of a turn lie over nothing. */
TEST(the_layout_check_counts_a_chart_over_itself)
{
    for (int turns = 3; turns <= 5; turns += 2) {
        float positions[3 * 7] = {0, 0, 0}, uvs[2 * 7] = {0.5f, 0.5f};
        uint32_t triangles[3 * 5];
        for (int k = 0; k <= turns; k++) {
            const float cos_k[4] = {1, 0, -1, 0}, sin_k[4] = {0, 1, 0, -1};
            float *p = positions + 3 * (k + 1), *uv = uvs + 2 * (k + 1);
            p[0] = cos_k[k % 4];
            p[1] = sin_k[k % 4];
            p[2] = 0.1f * (float)k; /* a helix: the ring's repeated corners are new points */
            uv[0] = (32 + 20 * cos_k[k % 4]) / 64;
            uv[1] = (32 + 20 * sin_k[k % 4]) / 64;
        }
        for (int k = 0; k < turns; k++) {
            triangles[3 * k] = 0;
            triangles[3 * k + 1] = (uint32_t)k + 1;
            triangles[3 * k + 2] = (uint32_t)k + 2;
        }
        texopt_model *model =
            fixture_model_from_arrays(positions, uvs, (size_t)turns + 2, triangles, (size_t)turns, 64, 64, "checker");
        CHECK(model != NULL);
        cJSON *doc = NULL;
        char err[256] = "";
        CHECK_OK(texopt_info_json(model, &doc, err, sizeof err), err);
        const cJSON *d = domain(doc, 0), *check = cJSON_GetObjectItemCaseSensitive(d, "layout_check");
        CHECK_NEAR(num(d, "charts"), 1, 0);
        CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(check, "passed")));
        double triangles_over = num(check, "overlapping_within_chart_triangles");
        double texels_over = num(check, "overlap_within_chart_texels");
        CHECK_MSG(triangles_over == (turns == 5 ? 1 : 0) && texels_over == (turns == 5 ? 190 : 0),
                  "%d quarter turns: %g triangles, %g texels over their chart", turns, triangles_over, texels_over);
        CHECK_NEAR(num(d, "overlap_texels"), texels_over, 0);
        cJSON_Delete(doc);
        texopt_model_destroy(model);
    }
}
