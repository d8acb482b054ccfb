/* test_compare_encoding.c - compare measures a layout as re-baked, not as re-encoded: on a
 * quad whose texture is a JPEG, the output a JPEG input would get is a JPEG (texopt_params
 * lossless_textures 0), which adds its own noise to q; compare's q must be that of the
 * lossless output, as the statistics' and the target_loss search's q are. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "gltf_builder.h"
#include "gltf_io.h"
#include "pipeline.h"
#include "test.h"

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
        ok = texopt_image_encode_jpeg(&tex, 90, &jpg, &jpg_len, NULL, 0) == TEXOPT_OK;
        texopt_image_destroy(&tex);
    }
    int view = ok ? quad_doc_add_view(&doc, jpg, jpg_len) : -1;
    free(jpg);
    char image[64];
    snprintf(image, sizeof image, "{\"bufferView\":%d,\"mimeType\":\"image/jpeg\"}", view);
    ok = view > 0 && builder_replace(&doc.json, "{\"bufferView\":3,\"mimeType\":\"image/png\"}", image);
    size_t glb_len = 0;
    unsigned char *glb = ok ? builder_glb(doc.json, doc.bin, doc.bin_len, &glb_len) : NULL;
    snprintf(path, len, "%s/quad.glb", dir);
    ok = glb && builder_write(path, glb, glb_len);
    free(glb);
    quad_doc_free(&doc);
    return ok;
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

static texopt_evaluate_options evaluate_options(void)
{
    texopt_evaluate_options eo;
    memset(&eo, 0, sizeof eo);
    eo.resolution = 128;
    eo.threads = 2;
    return eo;
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
    texopt_evaluate_options eo = evaluate_options();
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

    static const texopt_method methods[] = {TEXOPT_METHOD_INPUT};
    static const double costs[] = {0.25};
    texopt_compare_options opt;
    memset(&opt, 0, sizeof opt);
    opt.methods = methods;
    opt.method_count = 1;
    opt.costs = costs;
    opt.cost_count = 1;
    opt.params.threads = 2;
    opt.evaluate = evaluate_options();
    texopt_compare_result r;
    CHECK_OK(texopt_compare(path, &opt, &r, err, sizeof err), err);
    const texopt_compare_point *pt = &r.curves[0].points[0];
    CHECK_MSG(pt->status == TEXOPT_OK, "%s", pt->message);
    CHECK_MSG(pt->q == q_png, "compare's q %.9f, the lossless output's %.9f, the JPEG's %.9f", pt->q, q_png,
              q_jpeg);
    texopt_compare_result_destroy(&r);
    builder_rmdir(dir);
}
