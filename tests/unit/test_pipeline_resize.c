/* test_pipeline_resize.c - never worse than a resize (resize_check.c): a
 * perceptual domain whose new layout's q, on the choice's views, is not below its input layout
 * resized with Lanczos-3 to the same pixels keeps its input layout, its images re-baked by the
 * fit where that beats the resize in every map (the statistics give all three q), else
 * resized exactly as method "input" writes them; a layout that beats the resize is kept; a
 * layout that loses on an emissive map is not, named as the map that decided. Generated grids
 * (grid_glb.h). */
#include <math.h>
#include <string.h>

#include "pipeline.h"
#include "pipeline_scratch.h"
#include "test.h"

/* One job at a texture size; its statistics (NULL on failure). */
static cJSON *run_job(const scratch *s, const char *out, texopt_method method, int side, int resize_check)
{
    texopt_params p = {0};
    p.method = method;
    p.threads = 1;
    p.iterations = 5;
    p.eval_resolution = 96;
    p.evaluate = 1;
    p.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    p.texture_width = p.texture_height = side;
    p.resize_check = resize_check;
    char err[512] = "";
    if (texopt_optimize_file(s->in, out, s->stats, &p, NULL, err, sizeof err) != TEXOPT_OK) {
        printf("  %s\n", err);
        return NULL;
    }
    return read_json(s->stats);
}

static cJSON *domain0(cJSON *st)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(st, "domains"), 0);
}

static double number(cJSON *o, const char *key)
{
    cJSON *v = cJSON_GetObjectItem(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* Whether two images have the same size and pixels. */
static int same_image(const texopt_image *a, const texopt_image *b)
{
    if (a->width != b->width || a->height != b->height || a->channels != b->channels)
        return 0;
    size_t n = (size_t)a->width * a->height * a->channels;
    return n == 0 || memcmp(a->pixels, b->pixels, n * sizeof *a->pixels) == 0;
}

/* Whether two files have the same UVs and, with pixels, the same pixels in every image. */
static int same_model_of(const char *a_path, const char *b_path, int pixels)
{
    texopt_model *a = load(a_path), *b = load(b_path);
    int same = a && b && a->vertex_count == b->vertex_count && a->image_count == b->image_count;
    for (size_t i = 0; same && i < 2 * a->vertex_count; i++)
        same = a->uvs[i] == b->uvs[i];
    for (int i = 0; same && pixels && i < a->image_count; i++)
        same = same_image(&a->images[i], &b->images[i]);
    texopt_model_destroy(a);
    texopt_model_destroy(b);
    return same;
}

static int same_model(const char *a_path, const char *b_path)
{
    return same_model_of(a_path, b_path, 1);
}

/* The check's verdict in the statistics, with both q, printed. */
static const char *verdict(cJSON *st, double *q_layout, double *q_resize)
{
    cJSON *r = cJSON_GetObjectItem(domain0(st), "resize_check");
    *q_layout = number(r, "q_layout");
    *q_resize = number(r, "q_resize");
    cJSON *kept = cJSON_GetObjectItem(r, "kept");
    printf("  q %.5f layout, %.5f resize on the choice's views: %s kept; reported q %.5f\n", *q_layout, *q_resize,
           cJSON_IsString(kept) ? kept->valuestring : "?", number(cJSON_GetObjectItem(st, "evaluation"), "q"));
    return cJSON_IsString(kept) ? kept->valuestring : "";
}

/* At the input's own size the resize is the input itself (q 0): the domain keeps its input
 * layout and image to the pixel, and says so; with resize_check -1 the new layout is kept. */
TEST(at_the_input_s_size_the_input_is_kept)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "half") == 0);
    cJSON *st = run_job(&s, s.out, TEXOPT_METHOD_PERCEPTUAL, 64, 0);
    CHECK(st != NULL);
    double q_layout, q_resize;
    CHECK(strcmp(verdict(st, &q_layout, &q_resize), "resize") == 0);
    CHECK(q_resize == 0 && q_layout > 0);
    CHECK(!cJSON_IsTrue(cJSON_GetObjectItem(domain0(st), "repacked")));
    cJSON *why = cJSON_GetObjectItem(domain0(st), "input_layout_kept");
    CHECK(cJSON_IsString(why) && strstr(why->valuestring, "Lanczos-3") != NULL);
    CHECK(number(cJSON_GetObjectItem(st, "evaluation"), "q") == 0);
    CHECK(same_model(s.in, s.out));
    cJSON_Delete(st);
    st = run_job(&s, s.out, TEXOPT_METHOD_PERCEPTUAL, 64, -1);
    CHECK(st != NULL);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(domain0(st), "repacked")));
    CHECK(cJSON_GetObjectItem(domain0(st), "resize_check") == NULL);
    CHECK(!same_model(s.in, s.out));
    cJSON_Delete(st);
    scratch_free(&s);
}

/* A gradient at a quarter of the pixels, where the new layout is measured below the resize
 * on the choice's views (0.0045 against 0.0101), is kept. (On these flat grids the resize
 * mostly wins: "half" at a quarter, 0.112 against 0.088.) */
TEST(a_layout_below_the_resize_is_kept)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "gradient") == 0);
    cJSON *st = run_job(&s, s.out, TEXOPT_METHOD_PERCEPTUAL, 32, 0);
    CHECK(st != NULL);
    double q_layout, q_resize;
    CHECK(strcmp(verdict(st, &q_layout, &q_resize), "layout") == 0);
    CHECK(q_layout < q_resize);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(domain0(st), "repacked")));
    CHECK(cJSON_GetObjectItem(domain0(st), "input_layout_kept") == NULL);
    cJSON_Delete(st);
    scratch_free(&s);
}

/* The check's q of one map (resize_check.maps): layout's, resize's or the fit's. */
static double map_q(cJSON *st, const char *map, const char *which)
{
    cJSON *maps = cJSON_GetObjectItem(cJSON_GetObjectItem(domain0(st), "resize_check"), "maps");
    return number(cJSON_GetObjectItem(maps, map), which);
}

/* Uniform detail over a texture its one chart fills: no layout spends the pixels better than
 * the input's, and the input layout re-baked by the fit beats its Lanczos-3 resize. That is
 * written: the input's UVs, other pixels than method "input"'s and a lower reported q. */
TEST(a_losing_layout_falls_back_to_the_input_layout_refitted_when_that_beats_the_resize)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "checker") == 0);
    cJSON *st = run_job(&s, s.out, TEXOPT_METHOD_PERCEPTUAL, 32, 0);
    CHECK(st != NULL);
    double q_layout, q_resize;
    CHECK(strcmp(verdict(st, &q_layout, &q_resize), "input_fit") == 0);
    CHECK(q_resize <= q_layout);
    CHECK(map_q(st, "baseColor", "q_input_fit") < map_q(st, "baseColor", "q_resize"));
    CHECK(number(cJSON_GetObjectItem(domain0(st), "resize_check"), "input_fit_images") == 1);
    cJSON *why = cJSON_GetObjectItem(domain0(st), "input_layout_kept");
    CHECK(cJSON_IsString(why) && strstr(why->valuestring, "its images re-baked by the fit") != NULL &&
          strstr(why->valuestring, "the others resized") == NULL);
    double q = number(cJSON_GetObjectItem(st, "evaluation"), "q");
    cJSON_Delete(st);
    st = run_job(&s, s.again, TEXOPT_METHOD_INPUT, 32, 0);
    CHECK(st != NULL);
    double q_input = number(cJSON_GetObjectItem(st, "evaluation"), "q");
    printf("  reported q %.5f refitted, %.5f resized\n", q, q_input);
    CHECK(q < q_input);
    CHECK(same_model_of(s.out, s.again, 0) && !same_model(s.out, s.again));
    cJSON_Delete(st);
    scratch_free(&s);
}

/* A grid whose material binds a base colour of `base` and an emissive map of `emissive`, at a
 * quarter of its pixels: the statistics (NULL on failure), the check's verdict and the map
 * that decided it, printed with base colour's, emissive's and lit's q. */
static cJSON *run_emissive_job(scratch *s, const char *base, const char *emissive, const char **kept,
                               const char **decided_by)
{
    const char *patterns[2] = {base, emissive};
    if (scratch_init(s, 4, 64, NULL) != 0 ||
        write_grid_glb_material(s->in, 4, 64, patterns, 2,
                                "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
                                "\"emissiveTexture\":{\"index\":1},\"emissiveFactor\":[1,1,1]}") != 0)
        return NULL;
    cJSON *st = run_job(s, s->out, TEXOPT_METHOD_PERCEPTUAL, 32, 0);
    double q_layout, q_resize;
    *kept = st ? verdict(st, &q_layout, &q_resize) : "";
    cJSON *by = cJSON_GetObjectItem(cJSON_GetObjectItem(domain0(st), "resize_check"), "decided_by");
    *decided_by = cJSON_IsString(by) ? by->valuestring : "";
    printf("  decided by %s; layout / resize / fit: base colour %.5f / %.5f / %.5f, emissive %.5f / %.5f / %.5f, "
           "lit %.5f / %.5f / %.5f; %g images fitted\n",
           *decided_by, map_q(st, "baseColor", "q_layout"), map_q(st, "baseColor", "q_resize"),
           map_q(st, "baseColor", "q_input_fit"), map_q(st, "emissive", "q_layout"), map_q(st, "emissive", "q_resize"),
           map_q(st, "emissive", "q_input_fit"), map_q(st, "lit", "q_layout"), map_q(st, "lit", "q_resize"),
           map_q(st, "lit", "q_input_fit"),
           number(cJSON_GetObjectItem(domain0(st), "resize_check"), "input_fit_images"));
    return st;
}

/* Every map counts (map_check.h): base colour where the layout wins (the gradient above) and
 * an emissive checker where it loses. The input layout is kept, its emissive map re-baked by
 * the fit (below the resize there) and its base colour resized (the fit is not below there),
 * and the statistics name emissive as the map that decided, with every map's q and lit's;
 * the reported q per map covers the same maps. */
TEST(a_layout_that_loses_on_the_emissive_map_keeps_the_input_layout)
{
    scratch s;
    const char *kept, *by;
    cJSON *st = run_emissive_job(&s, "gradient", "checker", &kept, &by);
    CHECK(st != NULL);
    CHECK(map_q(st, "baseColor", "q_layout") < map_q(st, "baseColor", "q_resize"));
    CHECK(map_q(st, "emissive", "q_layout") > map_q(st, "emissive", "q_resize"));
    CHECK(strcmp(kept, "input_fit") == 0);
    CHECK(strcmp(by, "emissive") == 0);
    CHECK(map_q(st, "emissive", "q_input_fit") < map_q(st, "emissive", "q_resize"));
    CHECK(map_q(st, "baseColor", "q_input_fit") == map_q(st, "baseColor", "q_resize"));
    CHECK(map_q(st, "lit", "q_input_fit") < map_q(st, "lit", "q_resize"));
    CHECK(same_model_of(s.in, s.out, 0));
    cJSON *check = cJSON_GetObjectItem(domain0(st), "resize_check");
    CHECK(number(check, "q_layout") == map_q(st, "emissive", "q_layout"));
    CHECK(number(check, "q_resize") == map_q(st, "emissive", "q_resize"));
    CHECK(map_q(st, "lit", "q_resize") > 0 && isnan(map_q(st, "normal", "q_layout")));
    cJSON *q_maps = cJSON_GetObjectItem(cJSON_GetObjectItem(st, "evaluation"), "q_maps");
    CHECK(number(q_maps, "baseColor") == number(cJSON_GetObjectItem(st, "evaluation"), "q"));
    CHECK(number(q_maps, "emissive") > 0 && number(q_maps, "lit") > 0 && cJSON_GetArraySize(q_maps) == 3);
    cJSON_Delete(st);
    scratch_free(&s);
}

/* Flat base colour, a sharp emissive shape (text-like strokes on half the map): base colour
 * is the same under any layout, so only the emissive map (and lit) can decide; a check on
 * base colour alone would keep the resize on a tie. Where the fit is not below the resize
 * either, the file is method "input"'s, to the pixel. */
TEST(over_a_flat_base_colour_the_emissive_map_decides)
{
    scratch s;
    const char *kept, *by;
    cJSON *st = run_emissive_job(&s, "flat", "half", &kept, &by);
    CHECK(st != NULL);
    double el = map_q(st, "emissive", "q_layout"), er = map_q(st, "emissive", "q_resize");
    CHECK(map_q(st, "baseColor", "q_layout") == map_q(st, "baseColor", "q_resize"));
    CHECK(strcmp(by, "emissive") == 0 && el != er);
    CHECK(strcmp(kept, el < er && map_q(st, "lit", "q_layout") <= map_q(st, "lit", "q_resize") ? "layout" : "resize") ==
          0);
    CHECK(map_q(st, "emissive", "q_input_fit") >= er);
    int resize_kept = strcmp(kept, "resize") == 0; /* kept lives in st */
    cJSON_Delete(st);
    if (resize_kept) {
        st = run_job(&s, s.again, TEXOPT_METHOD_INPUT, 32, 0);
        CHECK(st != NULL && same_model(s.out, s.again));
        cJSON_Delete(st);
    }
    scratch_free(&s);
}
