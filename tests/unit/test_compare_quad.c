/* test_compare_quad.c - what compare measures (engine/compare/compare.h), on generated quads.
 * Every texture (every_texture): on a quad whose base colour is detailed and whose normal map
 * is flat, a downscale loses base-colour detail and none of the normal map's, so the two q
 * must differ, and a texture the input does not use must not be measured; a material
 * extension's (sheen) is; lit (the input has a normal map) is, and may be q's own measure.
 * As re-baked: on a quad whose texture is a JPEG, the output a JPEG input gets is a JPEG
 * (texopt_params lossless_textures 0), which adds its own noise to q; compare's q must be that
 * of the lossless output, as the statistics' and the target_loss search's q are. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "gltf_builder.h"
#include "gltf_io.h"
#include "pipeline.h"
#include "test.h"

/* Writes doc (when ok) as dir/quad.glb, its name into path, and frees it. */
static int write_quad_doc(quad_doc *doc, int ok, const char *dir, char *path, size_t len)
{
    size_t glb_len = 0;
    unsigned char *glb = ok ? builder_glb(doc->json, doc->bin, doc->bin_len, &glb_len) : NULL;
    snprintf(path, len, "%s/quad.glb", dir);
    ok = glb && builder_write(path, glb, glb_len);
    free(glb);
    quad_doc_free(doc);
    return ok;
}

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
    snprintf(image, sizeof image,
             "{\"bufferView\":3,\"mimeType\":\"image/png\"},{\"bufferView\":%d,\"mimeType\":\"image/png\"}", view);
    ok = view > 0 && builder_replace(&doc.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", image) &&
         builder_replace(&doc.json, "\"textures\":[{\"source\":0,\"sampler\":0}]",
                         "\"textures\":[{\"source\":0,\"sampler\":0},{\"source\":1,\"sampler\":0}]") &&
         builder_replace(&doc.json, "\"baseColorTexture\":{\"index\":0}}",
                         "\"baseColorTexture\":{\"index\":0}},\"normalTexture\":{\"index\":1},"
                         "\"extensions\":{\"KHR_materials_sheen\":{\"sheenColorTexture\":{\"index\":0}}}") &&
         builder_replace(&doc.json, "\"asset\":{\"version\":\"2.0\"},",
                         "\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_materials_sheen\"],");
    return write_quad_doc(&doc, ok, dir, path, len);
}

/* The evaluation every test here measures with: a 128-pixel view of the 64-texel quad. */
static texopt_evaluate_options quad_evaluation(void)
{
    texopt_evaluate_options eo;
    memset(&eo, 0, sizeof eo);
    eo.resolution = 128;
    eo.threads = 2;
    return eo;
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
    opt.evaluate = quad_evaluation();
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

/* The builder's quad with its 64 x 64 texture (every texel differs) stored as a JPEG, written
 * as dir/quad.glb (its name into path). */
static int write_jpeg_quad(const char *dir, char *path, size_t len)
{
    quad_doc doc;
    if (!quad_doc_init(&doc, 64, 64))
        return 0;
    texopt_image tex;
    unsigned char *jpg = NULL;
    size_t jpg_len = 0;
    int ok = builder_texture(&tex, 64, 64);
    if (ok) {
        ok = texopt_image_encode_jpeg(&tex, 90, 1, &jpg, &jpg_len, NULL, 0) == TEXOPT_OK;
        texopt_image_destroy(&tex);
    }
    int view = ok ? quad_doc_add_view(&doc, jpg, jpg_len) : -1;
    free(jpg);
    char image[64];
    snprintf(image, sizeof image, "{\"bufferView\":%d,\"mimeType\":\"image/jpeg\"}", view);
    ok = view > 0 && builder_replace(&doc.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", image);
    return write_quad_doc(&doc, ok, dir, path, len);
}

/* Whether the file at path holds `needle` (it must be under 64 KiB). */
static int file_holds(const char *path, const char *needle)
{
    static unsigned char buf[65536];
    FILE *f = fopen(path, "rb");
    size_t len = f ? fread(buf, 1, sizeof buf, f) : 0;
    if (f)
        fclose(f);
    return len < sizeof buf && builder_contains(buf, len, needle, strlen(needle));
}

/* q of `in` resized by method input to c_r 0.25 and written with or without lossless_textures
 * (as dir/out.glb); *jpeg says whether the file holds a JPEG. NAN on failure. */
static double q_of_written_output(const char *in, const char *dir, int lossless, int *jpeg)
{
    char out[128], err[512] = "";
    snprintf(out, sizeof out, "%s/out.glb", dir);
    texopt_params p;
    memset(&p, 0, sizeof p);
    p.method = TEXOPT_METHOD_INPUT;
    p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    p.relative_cost = 0.25;
    p.threads = 2;
    p.lossless_textures = lossless;
    texopt_model *input = NULL, *output = NULL;
    texopt_evaluate_options eo = quad_evaluation();
    texopt_evaluation ev;
    double q = NAN;
    if (texopt_optimize_file(in, out, NULL, &p, NULL, err, sizeof err) == TEXOPT_OK &&
        texopt_model_load(&input, in, NULL, err, sizeof err) == TEXOPT_OK &&
        texopt_model_load(&output, out, NULL, err, sizeof err) == TEXOPT_OK &&
        texopt_evaluate(input, output, &eo, &ev, err, sizeof err) == TEXOPT_OK)
        q = ev.q;
    *jpeg = file_holds(out, "image/jpeg");
    texopt_model_destroy(input);
    texopt_model_destroy(output);
    if (isnan(q))
        fprintf(stderr, "  %s\n", err);
    return q;
}

TEST(a_jpeg_input_is_measured_as_re_baked_not_as_re_encoded)
{
    char dir[64], path[128], err[512] = "";
    CHECK(builder_tempdir(dir));
    CHECK(write_jpeg_quad(dir, path, sizeof path));
    int jpeg = -1;
    double q_jpeg = q_of_written_output(path, dir, 0, &jpeg);
    CHECK_MSG(jpeg == 1, "a JPEG input's output is a JPEG: %d", jpeg);
    double q_png = q_of_written_output(path, dir, 1, &jpeg);
    CHECK_MSG(jpeg == 0, "lossless: %d", jpeg);
    /* The encoding shows in q, so the check below can tell the two apart. */
    CHECK_MSG(fabs(q_jpeg - q_png) > 1e-4 * q_png, "q %.9f as JPEG, %.9f as PNG", q_jpeg, q_png);

    texopt_compare_result r;
    CHECK_OK(compare_input_method(path, 0, "baseColor", &r, err, sizeof err), err);
    const texopt_compare_point *pt = &r.curves[0].points[0];
    CHECK_MSG(pt->status == TEXOPT_OK, "%s", pt->message);
    CHECK_MSG(pt->q == q_png, "compare's q %.9f, the lossless output's %.9f, the JPEG's %.9f", pt->q, q_png, q_jpeg);
    texopt_compare_result_destroy(&r);
    builder_rmdir(dir);
}
