/* test_compare_slots.c - compare's q of every texture (engine/compare.h every_texture), on a
 * generated quad whose base colour is detailed and whose normal map is flat: a downscale
 * loses base-colour detail and none of the normal map's, so the two q must differ, and a
 * texture the input does not use must not be measured; a material extension's (sheen) is;
 * lit (the input has a normal map) is, and may be q's own measure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "gltf_builder.h"
#include "test.h"

/* The builder's quad (a 64 x 64 texture where every texel differs, also its sheen colour map)
 * plus a flat 64 x 64 normal map, written as a .glb into dir; path receives its name. */
static int write_quad_with_flat_normal_map(const char *dir, char *path, size_t len)
{
    quad_doc doc;
    if (!quad_doc_init(&doc, 64, 64))
        return 0;
    texopt_image flat;
    unsigned char *png = NULL;
    size_t png_len = 0;
    int ok = texopt_image_create(&flat, 64, 64, 3, NULL, 0) == TEXOPT_OK;
    if (ok) {
        for (int y = 0; y < 64; y++)
            for (int x = 0; x < 64; x++) {
                float *p = texopt_image_at(&flat, x, y);
                p[0] = p[1] = 0.5f;
                p[2] = 1.0f;
            }
        ok = texopt_image_encode_png(&flat, &png, &png_len, NULL, 0) == TEXOPT_OK;
        texopt_image_destroy(&flat);
    }
    int view = ok ? quad_doc_add_view(&doc, png, png_len) : -1;
    free(png);
    char image[96];
    snprintf(image, sizeof image, "{\"bufferView\":3,\"mimeType\":\"image/png\"},{\"bufferView\":%d,\"mimeType\":\"image/png\"}", view);
    ok = view > 0 &&
         builder_replace(&doc.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", image) &&
         builder_replace(&doc.json, "\"textures\":[{\"source\":0,\"sampler\":0}]",
                         "\"textures\":[{\"source\":0,\"sampler\":0},{\"source\":1,\"sampler\":0}]") &&
         builder_replace(&doc.json, "\"baseColorTexture\":{\"index\":0}}",
                         "\"baseColorTexture\":{\"index\":0}},\"normalTexture\":{\"index\":1},"
                         "\"extensions\":{\"KHR_materials_sheen\":{\"sheenColorTexture\":{\"index\":0}}}") &&
         builder_replace(&doc.json, "\"asset\":{\"version\":\"2.0\"},",
                         "\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_materials_sheen\"],");
    size_t glb_len = 0;
    unsigned char *glb = ok ? builder_glb(doc.json, doc.bin, doc.bin_len, &glb_len) : NULL;
    snprintf(path, len, "%s/quad.glb", dir);
    ok = glb && builder_write(path, glb, glb_len);
    free(glb);
    quad_doc_free(&doc);
    return ok;
}

static texopt_status compare_input_method(const char *path, int every_texture, const char *measure,
                                          texopt_compare_result *r, char *err, size_t err_len)
{
    static const texopt_method methods[] = {TEXOPT_METHOD_INPUT};
    static const double costs[] = {0.25};
    texopt_compare_options opt;
    memset(&opt, 0, sizeof opt);
    opt.methods = methods;
    opt.method_count = 1;
    opt.costs = costs;
    opt.cost_count = 1;
    opt.evaluate.resolution = 128;
    opt.evaluate.threads = 2;
    opt.every_texture = every_texture;
    if (texopt_evaluate_select_measure(&opt.evaluate, measure) != 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "unknown measure %s", measure);
    return texopt_compare(path, &opt, r, err, err_len);
}

/* r as compare's JSON (written to dir/curves.json) read back into text, its length into *len. */
static void compare_json_text(const texopt_compare_result *r, const char *dir, char *text, size_t cap, size_t *len)
{
    char json[160], err[512] = "";
    text[0] = 0;
    *len = 0;
    snprintf(json, sizeof json, "%s/curves.json", dir);
    CHECK_OK(texopt_compare_write_json(r, json, err, sizeof err), err);
    FILE *f = fopen(json, "rb");
    CHECK(f != NULL);
    size_t n = f ? fread(text, 1, cap - 1, f) : 0;
    if (f)
        fclose(f);
    text[n] = 0;
    *len = n;
}

TEST(every_texture_is_measured_that_the_input_has)
{
    char dir[64], path[128], err[512] = "";
    CHECK(builder_tempdir(dir));
    CHECK(write_quad_with_flat_normal_map(dir, path, sizeof path));
    texopt_compare_result r;
    CHECK_OK(compare_input_method(path, 1, "baseColor", &r, err, sizeof err), err);
    const texopt_compare_point *p = &r.curves[0].points[0];
    CHECK_MSG(p->status == TEXOPT_OK, "%s", p->message);
    CHECK(r.texture_measured[TEXOPT_SLOT_BASE_COLOR] && r.texture_measured[TEXOPT_SLOT_NORMAL]);
    CHECK(!r.texture_measured[TEXOPT_SLOT_METALLIC_ROUGHNESS] && !r.texture_measured[TEXOPT_SLOT_EMISSIVE]);
    /* The headline q is base colour's; the detailed texture loses a lot at a quarter of its
     * texels, the flat normal map nothing. */
    CHECK(p->q_by_texture[TEXOPT_SLOT_BASE_COLOR] == p->q);
    CHECK_MSG(p->q > 0.01, "base colour q %.5f", p->q);
    CHECK_MSG(p->q_by_texture[TEXOPT_SLOT_NORMAL] < 1e-4, "normal q %.6f", p->q_by_texture[TEXOPT_SLOT_NORMAL]);
    CHECK(isnan(p->q_by_texture[TEXOPT_SLOT_METALLIC_ROUGHNESS]));
    /* With a normal map lit is measured too: it sees the lost base-colour detail, shaded. */
    CHECK(r.texture_measured[TEXOPT_COMPARE_LIT]);
    CHECK_MSG(p->q_by_texture[TEXOPT_COMPARE_LIT] > 0.01, "lit q %.5f", p->q_by_texture[TEXOPT_COMPARE_LIT]);
    /* The sheen map, a material extension's texture, is measured under its key: the same image
     * as base colour, resized the same way. */
    int sheen = texopt_texture_key_from_name("sheenColorTexture");
    CHECK(r.texture_measured[sheen] && !r.texture_measured[texopt_texture_key_from_name("clearcoatTexture")]);
    CHECK_MSG(p->q_by_texture[sheen] == p->q, "sheen q %.6f, base colour q %.6f", p->q_by_texture[sheen], p->q);
    char text[4096];
    size_t n;
    compare_json_text(&r, dir, text, sizeof text, &n);
    CHECK(strstr(text, "\"q_by_texture\"") != NULL && strstr(text, "\"normal\"") != NULL);
    CHECK(strstr(text, "\"sheenColorTexture\"") != NULL);
    CHECK(strstr(text, "\"lit\"") != NULL);
    CHECK(strstr(text, "metallicRoughness") == NULL);
    texopt_compare_result_destroy(&r);

    /* Without the option only the headline slot is measured, and the JSON stays as it was. */
    CHECK_OK(compare_input_method(path, 0, "baseColor", &r, err, sizeof err), err);
    p = &r.curves[0].points[0];
    CHECK(r.texture_measured[TEXOPT_SLOT_BASE_COLOR] && !r.texture_measured[TEXOPT_SLOT_NORMAL]);
    CHECK(p->q_by_texture[TEXOPT_SLOT_BASE_COLOR] == p->q && isnan(p->q_by_texture[TEXOPT_SLOT_NORMAL]));
    CHECK(!r.texture_measured[TEXOPT_COMPARE_LIT] && isnan(p->q_by_texture[TEXOPT_COMPARE_LIT]));
    compare_json_text(&r, dir, text, sizeof text, &n);
    CHECK(n > 0 && strstr(text, "q_by_texture") == NULL);
    texopt_compare_result_destroy(&r);
    builder_rmdir(dir);
}

/* q may measure lit itself (compare --texture lit): the headline is lit's q, nothing else is
 * measured without every_texture, and the JSON names it. */
TEST(lit_can_be_the_headline_measure)
{
    char dir[64], path[128], err[512] = "";
    CHECK(builder_tempdir(dir));
    CHECK(write_quad_with_flat_normal_map(dir, path, sizeof path));
    texopt_compare_result r;
    CHECK_OK(compare_input_method(path, 0, "LIT", &r, err, sizeof err), err);
    const texopt_compare_point *p = &r.curves[0].points[0];
    CHECK_MSG(p->status == TEXOPT_OK, "%s", p->message);
    CHECK(r.measure == TEXOPT_COMPARE_LIT && r.texture_measured[TEXOPT_COMPARE_LIT]);
    CHECK(!r.texture_measured[TEXOPT_SLOT_BASE_COLOR] && isnan(p->q_by_texture[TEXOPT_SLOT_BASE_COLOR]));
    CHECK(p->q == p->q_by_texture[TEXOPT_COMPARE_LIT]);
    CHECK_MSG(p->q > 0.01, "lit q %.5f", p->q);
    char text[4096];
    size_t n;
    compare_json_text(&r, dir, text, sizeof text, &n);
    CHECK(strstr(text, "\"lit\"") != NULL && strstr(text, "baseColor") == NULL);
    texopt_compare_result_destroy(&r);
    CHECK(compare_input_method(path, 0, "shininess", &r, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    builder_rmdir(dir);
}
