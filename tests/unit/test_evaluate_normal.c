/* test_evaluate_normal.c - normal-slot q compares the two normal maps in the reference's
 * tangent frame (engine/evaluate/evaluate.h): a layout that turns the triangles, re-baked with the
 * normal map turned as a renderer needs it (engine/bake/rebake.h), scores near 0; the same map
 * read unturned (as base colour, which is never turned) or baked without the turn scores
 * far worse; a material extension's normal map (clearcoatNormalTexture) the same. Models are
 * generated in code; the stored-tangent case writes a small .gltf. The report's renders
 * (texopt_evaluate_render) show a turned map turned back alike. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "evaluate.h"
#include "fixtures.h"
#include "gltf_io.h"
#include "image_io.h"
#include "test.h"

#define TEX 64
#define PI 3.14159265358979323846

static const float quad_pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float quad_uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
static const uint32_t quad_tris[6] = {0, 1, 2, 0, 2, 3};

/* The quad with UVs `uv` whose one image (side x side) is its base colour, its normal map
 * and its clearcoat normal map, so the base-colour q of a candidate is its normal map read
 * unturned. */
static texopt_model *quad_with_normal_map(const float *uv, int side)
{
    texopt_model *m = fixture_model_from_arrays(quad_pos, uv, 4, quad_tris, 2, side, side, "flat");
    if (m) {
        texopt_material *mat = &m->materials[0];
        mat->slot[TEXOPT_SLOT_NORMAL] = mat->slot[TEXOPT_SLOT_BASE_COLOR];
        mat->extra[0] = (texopt_extra_texture){mat->slot[TEXOPT_SLOT_BASE_COLOR], TEXOPT_TEXTURE_NORMAL,
                                               TEXOPT_CHANNELS_RGB, "clearcoatNormalTexture"};
        mat->extra_count = 1;
    }
    return m;
}

/* The reference's UVs turned by `degrees` about (0.5, 0.5) and scaled to stay in [0, 1]. */
static void turned_uvs(double degrees, float *uv)
{
    double t = degrees * PI / 180.0, c = cos(t), s = sin(t), k = 1.0 / (fabs(c) + fabs(s));
    for (int v = 0; v < 4; v++) {
        double x = quad_uv[2 * v] - 0.5, y = quad_uv[2 * v + 1] - 0.5;
        uv[2 * v] = (float)(0.5 + k * (c * x - s * y));
        uv[2 * v + 1] = (float)(0.5 + k * (s * x + c * y));
    }
}

/* A candidate over `uv` whose image is the reference's re-baked into it (normal_map: turn). */
static texopt_model *rebaked_candidate(const texopt_model *ref, const float *uv, int side, int normal_map)
{
    texopt_model *cand = quad_with_normal_map(uv, side);
    if (cand && fixture_rebake(ref, cand, 0, normal_map) != 0) {
        texopt_model_destroy(cand);
        return NULL;
    }
    return cand;
}

static double slot_q(const texopt_model *ref, const texopt_model *cand, int texture)
{
    texopt_evaluate_options opt = {.resolution = 128, .threads = 2, .texture = texture};
    texopt_evaluation ev;
    char err[256] = "";
    if (texopt_evaluate(ref, cand, &opt, &ev, err, sizeof err) != TEXOPT_OK)
        return NAN;
    return ev.q;
}

static texopt_model *reference_quad(void)
{
    texopt_model *ref = quad_with_normal_map(quad_uv, TEX);
    if (ref)
        fixture_fill_normal_map(&ref->images[0]);
    return ref;
}

/* Normal-slot q of the turned bake, of the same image unturned (its base-colour q) and of a
 * bake that did not turn the map, for a layout turned by `degrees`. */
static void check_turned_layout(double degrees, int side)
{
    texopt_model *ref = reference_quad();
    float uv[8];
    turned_uvs(degrees, uv);
    texopt_model *turned = rebaked_candidate(ref, uv, side, 1), *unturned = rebaked_candidate(ref, uv, side, 0);
    CHECK(ref && turned && unturned);
    double fixed = slot_q(ref, turned, TEXOPT_SLOT_NORMAL), as_image = slot_q(ref, turned, TEXOPT_SLOT_BASE_COLOR);
    double wrong_bake = slot_q(ref, unturned, TEXOPT_SLOT_NORMAL);
    printf("  %.0f degrees: normal q %.5f, read unturned %.5f, bake without the turn %.5f\n", degrees, fixed, as_image,
           wrong_bake);
    /* Measured: 0 / 0.054 / 0.054 at 90 degrees, 0.0007 / 0.074 / 0.049 at 37. */
    CHECK_MSG(fixed < 0.005, "%.0f degrees: normal q %.5f", degrees, fixed);
    CHECK_MSG(as_image > 10 * fixed && as_image > 0.03, "%.0f degrees: unturned %.5f", degrees, as_image);
    CHECK_MSG(wrong_bake > 10 * fixed && wrong_bake > 0.03, "%.0f degrees: wrong bake %.5f", degrees, wrong_bake);
    /* Base colour is never turned: the bake without the turn is the plain image there. */
    CHECK(slot_q(ref, unturned, TEXOPT_SLOT_BASE_COLOR) < 0.01);
    /* A material extension's normal map is turned back like the core one, by its own
     * bindings: the core normal map unbound. */
    ref->materials[0].slot[TEXOPT_SLOT_NORMAL].image = -1;
    turned->materials[0].slot[TEXOPT_SLOT_NORMAL].image = -1;
    unturned->materials[0].slot[TEXOPT_SLOT_NORMAL].image = -1;
    int clearcoat_normal = texopt_texture_key_from_name("clearcoatNormalTexture");
    double coat = slot_q(ref, turned, clearcoat_normal), coat_wrong = slot_q(ref, unturned, clearcoat_normal);
    CHECK_MSG(coat == fixed, "%.0f degrees: clearcoat normal q %.5f, normal q %.5f", degrees, coat, fixed);
    CHECK_MSG(coat_wrong == wrong_bake, "%.0f degrees: clearcoat wrong bake %.5f", degrees, coat_wrong);
    texopt_model_destroy(ref);
    texopt_model_destroy(turned);
    texopt_model_destroy(unturned);
}

TEST(quarter_turned_layout_scores_its_turned_normal_map_near_zero)
{
    check_turned_layout(90, TEX);
}

TEST(layout_turned_by_any_angle_scores_its_turned_normal_map_near_zero)
{
    check_turned_layout(37, 96);
}

/* Writes quad.bin (positions, UVs, optionally TANGENT, u32 indices) and normal.png (the
 * reference's map) into dir; returns the .gltf JSON naming them, or NULL. */
static char *write_quad_gltf(const char *dir, const texopt_image *normal, int tangents)
{
    static const float tangent[16] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    char path[512], err[256];
    snprintf(path, sizeof path, "%s/normal.png", dir);
    if (texopt_image_write_png(normal, path, err, sizeof err) != TEXOPT_OK)
        return NULL;
    snprintf(path, sizeof path, "%s/quad.bin", dir);
    FILE *f = fopen(path, "wb");
    if (!f)
        return NULL;
    fwrite(quad_pos, sizeof quad_pos, 1, f);
    fwrite(quad_uv, sizeof quad_uv, 1, f);
    fwrite(quad_tris, sizeof quad_tris, 1, f);
    fwrite(tangent, sizeof tangent, 1, f);
    if (fclose(f) != 0)
        return NULL;
    char *json = malloc(4096);
    if (json)
        snprintf(
            json, 4096,
            "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
            "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1%s},"
            "\"indices\":2,\"material\":0}]}],"
            "\"materials\":[{\"normalTexture\":{\"index\":0}}],"
            "\"textures\":[{\"source\":0}],\"images\":[{\"uri\":\"normal.png\"}],"
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
            "\"min\":[0,0,0],\"max\":[1,1,0]},"
            "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
            "{\"bufferView\":2,\"componentType\":5125,\"count\":6,\"type\":\"SCALAR\"},"
            "{\"bufferView\":3,\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"}],"
            "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
            "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32},{\"buffer\":0,\"byteOffset\":80,\"byteLength\":24},"
            "{\"buffer\":0,\"byteOffset\":104,\"byteLength\":64}],"
            "\"buffers\":[{\"uri\":\"quad.bin\",\"byteLength\":168}]}",
            tangents ? ",\"TANGENT\":3" : "");
    return json;
}

/* The loaded quad (with or without TANGENT) and a candidate loaded from the same file whose
 * UVs are turned by 90 degrees and whose map is re-baked WITHOUT the turn, as the pipeline
 * bakes a model with stored tangents: normal-slot q of that candidate. */
static double stored_tangent_case(const char *dir, int tangents, int drop_candidate_file)
{
    texopt_image normal;
    char err[256] = "";
    double q = NAN;
    if (texopt_image_create(&normal, TEX, TEX, 3, NULL, 0) != TEXOPT_OK)
        return q;
    fixture_fill_normal_map(&normal);
    char *json = write_quad_gltf(dir, &normal, tangents);
    texopt_image_destroy(&normal);
    texopt_model *ref = NULL, *cand = NULL;
    if (json && texopt_model_load_memory(&ref, json, strlen(json), dir, NULL, err, sizeof err) == TEXOPT_OK &&
        texopt_model_load_memory(&cand, json, strlen(json), dir, NULL, err, sizeof err) == TEXOPT_OK) {
        float uv[8];
        turned_uvs(90, uv);
        texopt_model *baked = rebaked_candidate(ref, uv, TEX, 0);
        if (baked) {
            memcpy(cand->uvs, uv, sizeof uv);
            texopt_image swap = cand->images[0];
            cand->images[0] = baked->images[0];
            baked->images[0] = swap;
            if (drop_candidate_file && cand->destroy_document) {
                cand->destroy_document(cand->document);
                cand->document = NULL;
            }
            q = slot_q(ref, cand, TEXOPT_SLOT_NORMAL);
        }
        texopt_model_destroy(baked);
    }
    free(json);
    texopt_model_destroy(ref);
    texopt_model_destroy(cand);
    return q;
}

/* With stored tangents the re-bake does not turn the map and neither does the evaluation,
 * also for a candidate in memory (no file: it has the reference's attributes); without
 * them the same unturned bake is wrong for lighting and scores far worse. */
TEST(stored_tangents_turn_nothing)
{
    char dir[] = "/tmp/texopt_normal_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    double with = stored_tangent_case(dir, 1, 0), in_memory = stored_tangent_case(dir, 1, 1);
    double without = stored_tangent_case(dir, 0, 0);
    printf("  stored tangents %.5f, in memory %.5f, no tangents %.5f\n", with, in_memory, without);
    CHECK_MSG(with < 0.005, "stored tangents: %.5f", with);
    CHECK_MSG(in_memory < 0.005, "in memory: %.5f", in_memory);
    CHECK_MSG(without > 0.03, "no tangents: %.5f", without);
    char path[512];
    snprintf(path, sizeof path, "%s/normal.png", dir);
    remove(path);
    snprintf(path, sizeof path, "%s/quad.bin", dir);
    remove(path);
    rmdir(dir);
}

/* Mean absolute RGB difference of two renders over the raster's covered pixels. */
static double render_difference(const texopt_image *a, const texopt_image *b, const texopt_raster *raster)
{
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)raster->side * (size_t)raster->side; i++)
        if (raster->triangle[i] >= 0) {
            for (int k = 0; k < 3; k++)
                sum += fabs(a->pixels[3 * i + k] - b->pixels[3 * i + k]);
            n += 3;
        }
    return n ? sum / (double)n : NAN;
}

/* texopt_evaluate_render of `model` in `measure` (a texture key, or -1: lit) into *img. */
static texopt_status render_as(const texopt_model *ref, const texopt_model *model, int measure,
                               const texopt_raster *raster, texopt_image *img)
{
    texopt_evaluate_options opt = {.texture = measure < 0 ? TEXOPT_SLOT_BASE_COLOR : measure, .lit = measure < 0};
    char err[256] = "";
    texopt_status st = texopt_evaluate_render(ref, model, &opt, raster, img, err, sizeof err);
    if (st != TEXOPT_OK)
        printf("  render: %s\n", err);
    return st;
}

/* The report's renders (texopt_evaluate_render) show a re-baked normal map as q compares it,
 * turned back to the reference's frame: the quarter-turned bake looks like the reference
 * there, and unlike it read as base colour (never turned); base colour is what
 * texopt_meshrender_shade draws; the lit render is grey. */
TEST(renders_show_a_turned_normal_map_as_q_compares_it)
{
    texopt_model *ref = reference_quad();
    float uv[8];
    turned_uvs(90, uv);
    texopt_model *turned = rebaked_candidate(ref, uv, TEX, 1);
    CHECK(ref && turned);
    texopt_view views[TEXOPT_VIEW_COUNT];
    texopt_raster raster;
    char err[256] = "";
    CHECK_OK(texopt_meshrender_views(ref, views, err, sizeof err), err);
    CHECK_OK(texopt_meshrender_rasterize(ref, &views[0], 64, &raster, err, sizeof err), err);
    CHECK(raster.covered > 100);
    texopt_image ref_normal, turned_normal, turned_colour, ref_colour, shaded, lit;
    CHECK(render_as(ref, ref, TEXOPT_SLOT_NORMAL, &raster, &ref_normal) == TEXOPT_OK);
    CHECK(render_as(ref, turned, TEXOPT_SLOT_NORMAL, &raster, &turned_normal) == TEXOPT_OK);
    CHECK(render_as(ref, turned, TEXOPT_SLOT_BASE_COLOR, &raster, &turned_colour) == TEXOPT_OK);
    CHECK(render_as(ref, ref, TEXOPT_SLOT_BASE_COLOR, &raster, &ref_colour) == TEXOPT_OK);
    CHECK(render_as(ref, turned, -1, &raster, &lit) == TEXOPT_OK);
    CHECK_OK(texopt_meshrender_shade(ref, &raster, &shaded, err, sizeof err), err);
    double same = render_difference(&ref_normal, &turned_normal, &raster);
    double unturned = render_difference(&ref_normal, &turned_colour, &raster);
    printf("  normal render differs by %.4f turned back, %.4f read as base colour\n", same, unturned);
    CHECK_MSG(same < 0.01 && unturned > 10 * same && unturned > 0.02, "%.4f, %.4f", same, unturned);
    CHECK(memcmp(ref_colour.pixels, shaded.pixels, sizeof(float) * 3 * 64 * 64) == 0);
    size_t grey = 0;
    for (size_t i = 0; i < 64 * 64; i++)
        grey += lit.pixels[3 * i] == lit.pixels[3 * i + 1] && lit.pixels[3 * i] == lit.pixels[3 * i + 2];
    CHECK_EQ_INT((int)grey, 64 * 64);
    texopt_image *all[] = {&ref_normal, &turned_normal, &turned_colour, &ref_colour, &shaded, &lit};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        texopt_image_destroy(all[i]);
    texopt_raster_destroy(&raster);
    texopt_model_destroy(ref);
    texopt_model_destroy(turned);
}
