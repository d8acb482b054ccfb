/* test_triopt.c - the triangle-wise stage on generated strips of quads. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "lit_weight.h"
#include "mesh.h"
#include "test.h"
#include "triopt.h"

#define PI 3.14159265358979323846

/* One row of `cols` quads across the texture at v in [0.375, 0.4375] (one quad tall),
 * positions = UVs (z = 0). Quad i owns triangles 2i and 2i + 1. With transpose the image is
 * mirrored across its diagonal, so vertical stripes become horizontal ones. */
static texopt_model *strip_model(int cols, int tex, const char *pattern, int transpose)
{
    size_t nv = 2 * (size_t)(cols + 1);
    float *pos = malloc(sizeof(float) * 3 * nv), *uv = malloc(sizeof(float) * 2 * nv);
    uint32_t *tri = malloc(sizeof(uint32_t) * 6 * (size_t)cols);
    texopt_model *m = NULL;
    if (pos && uv && tri) {
        for (int r = 0; r < 2; r++)
            for (int i = 0; i <= cols; i++) {
                size_t v = (size_t)r * (size_t)(cols + 1) + (size_t)i;
                pos[3 * v] = uv[2 * v] = (float)i / (float)cols;
                pos[3 * v + 1] = uv[2 * v + 1] = 0.375f + (float)r / (float)cols;
                pos[3 * v + 2] = 0.0f;
            }
        for (int i = 0; i < cols; i++) {
            uint32_t a = (uint32_t)i, b = a + 1, c = b + (uint32_t)(cols + 1), d = a + (uint32_t)(cols + 1);
            uint32_t *t = tri + 6 * (size_t)i;
            t[0] = a, t[1] = b, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
        }
        m = fixture_model_from_arrays(pos, uv, nv, tri, 2 * (size_t)cols, tex, tex, pattern);
    }
    free(pos);
    free(uv);
    free(tri);
    if (m && transpose) {
        texopt_image *img = &m->images[0];
        for (int y = 0; y < img->height; y++)
            for (int x = 0; x < y; x++)
                for (int c = 0; c < img->channels; c++) {
                    float t = texopt_image_at(img, x, y)[c];
                    texopt_image_at(img, x, y)[c] = texopt_image_at(img, y, x)[c];
                    texopt_image_at(img, y, x)[c] = t;
                }
    }
    return m;
}

typedef struct stage_run {
    texopt_model *model;
    texopt_mesh *mesh;
    texopt_triangle_target *out;
    texopt_triopt_report report;
    texopt_status status;
    char err[256];
} stage_run;

static int run_stage(stage_run *r, texopt_model *model, const texopt_triopt_options *opt, const texopt_monitor *monitor)
{
    memset(r, 0, sizeof *r);
    r->model = model;
    if (!model || texopt_mesh_create(&r->mesh, model, 0, r->err, sizeof r->err) != TEXOPT_OK)
        return 0;
    r->out = calloc(r->mesh->triangle_count, sizeof *r->out);
    if (!r->out)
        return 0;
    r->status = texopt_triopt_run(model, r->mesh, opt, r->out, &r->report, monitor, r->err, sizeof r->err);
    return 1;
}

static void close_stage(stage_run *r)
{
    free(r->out);
    texopt_mesh_destroy(r->mesh);
    texopt_model_destroy(r->model);
}

/* Angle in [0, 180) degrees of the input direction J squeezes most. */
static double squeeze_direction_degrees(const texopt_triangle_target *o)
{
    double b = o->lambda1 < o->lambda2 ? o->beta : o->beta + PI / 2;
    double deg = fmod(b * 180.0 / PI, 180.0);
    return deg < 0 ? deg + 180.0 : deg;
}

TEST(flat_half_gets_far_fewer_texels_than_detail)
{
    /* "half" on 256 texels, 16-texel quads: quads 2..5 see only the flat colour (their
     * one-rings span x in [16, 96]), quads 10..13 only text-like strokes. */
    texopt_triopt_options opt = {.iterations = 10, .threads = 2, .seed = 7};
    stage_run r;
    CHECK(run_stage(&r, strip_model(16, 256, "half", 0), &opt, NULL));
    CHECK_OK(r.status, r.err);
    double flat = 0, detail = 0;
    for (int i = 0; i < 16; i++)
        for (int k = 0; k < 2; k++) {
            const texopt_triangle_target *o = &r.out[2 * i + k];
            CHECK_MSG(o->loss >= 0 && o->loss < 0.01, "triangle %d: E = %g", 2 * i + k, o->loss);
            CHECK(o->lambda1 >= 0.1 - 1e-12 && o->lambda1 <= 1 + 1e-12);
            CHECK(o->lambda2 >= 0.1 - 1e-12 && o->lambda2 <= 1 + 1e-12);
            CHECK(o->alpha >= 0 && o->alpha < PI / 2 && o->beta >= 0 && o->beta < PI / 2);
            if (i >= 2 && i <= 5) {
                flat += o->lambda1 * o->lambda2 / 8;
                /* E = 0 at the smallest area is the objective's lower bound: one
                 * evaluation, and the weights of a loss that is 0 everywhere are 0. */
                CHECK_NEAR(o->lambda1 * o->lambda2, 0.01, 1e-12);
                CHECK_EQ_INT(o->evaluations, 1);
                CHECK(o->w_rotation == 0.0 && o->w_stretch == 0.0);
            }
            if (i >= 10 && i <= 13)
                detail += o->lambda1 * o->lambda2 / 8;
        }
    CHECK_MSG(flat < 0.5 * detail, "flat %g vs detail %g", flat, detail);
    CHECK_MSG(detail > 0.2, "detail %g", detail);
    CHECK_EQ_INT(r.report.optimised, 32);
    CHECK(r.report.evaluations > 8 * 20);
    /* 16-texel quads fit one window at the zoom limit many times over. */
    CHECK_EQ_INT(r.report.close_up_triangles, 0);
    close_stage(&r);
}

TEST(text_in_triangles_larger_than_the_window_keeps_its_texels)
{
    /* "half" on 512 texels, 2 x 2 quads of 256 texels: the one-ring's window shows each
     * triangle at 4 or more texels a pixel, where the 1-texel strokes of the right half blur
     * to grey; the close-ups (triloss.h) see them at the zoom limit. */
    texopt_triopt_options opt = {.iterations = 10, .threads = 2, .seed = 7};
    stage_run r;
    CHECK(run_stage(&r, fixture_grid(2, 512, "half"), &opt, NULL));
    CHECK_OK(r.status, r.err);
    /* Quads 1 and 3 lie in the strokes: without close-ups they shrank to area 0.03 (73a56a1),
     * with them they keep 0.53-0.57. The triangles of quads 0 and 2 away from the strokes
     * (the second of each) stay at the smallest area. */
    for (int q = 0; q < 4; q++)
        for (int k = 0; k < 2; k++) {
            const texopt_triangle_target *o = &r.out[2 * q + k];
            double area = o->lambda1 * o->lambda2;
            CHECK_MSG(o->loss >= 0 && o->loss <= 0.03, "triangle %d: E = %g", 2 * q + k, o->loss);
            if (q % 2 == 1)
                CHECK_MSG(area > 0.3, "stroke triangle %d: area %g", 2 * q + k, area);
            else if (k == 1)
                CHECK_MSG(area < 0.0101, "flat triangle %d: area %g", 2 * q + k, area);
        }
    /* Every triangle's legs span 256 texels, over three windows at the limit (80 texels); a
     * window of the flat ones near their edge shows the strokes next door, so each keeps
     * close-ups. */
    CHECK_EQ_INT(r.report.close_up_triangles, 8);
    close_stage(&r);
}

/* strip_model(16, 256, "flat") with a metallic-roughness image whose channel `channel` holds
 * "half"'s strokes and whose other channels are 0.5 (G roughness, B metallic; R is read by
 * no lit term). */
static texopt_model *strip_with_mr_detail(int channel)
{
    char err[256] = "";
    texopt_model *m = strip_model(16, 256, "flat", 0);
    texopt_image *mr = m ? fixture_add_slot_image(m, TEXOPT_SLOT_METALLIC_ROUGHNESS, 256) : NULL;
    texopt_image half = {0};
    int ok = mr && texopt_image_create(&half, 256, 256, 3, err, sizeof err) == TEXOPT_OK &&
             fixture_fill_pattern(&half, "half") == 0;
    for (size_t i = 0; ok && i < 256 * 256; i++)
        for (int c = 0; c < 3; c++)
            mr->pixels[3 * i + c] = c == channel ? half.pixels[3 * i] : 0.5f;
    texopt_image_destroy(&half);
    if (!ok || texopt_model_build_domains(m, err, sizeof err) != TEXOPT_OK) {
        texopt_model_destroy(m);
        return NULL;
    }
    return m;
}

/* Mean target area of the detailed quads 10..13 of a strip_with_mr_detail(channel), stage 1's
 * signals weighed by the light (lit_weight.h) or not. */
static double mr_detail_area(int channel, int weighed)
{
    texopt_model *m = strip_with_mr_detail(channel);
    double *w = m ? malloc((size_t)m->image_count * TEXOPT_LIT_WEIGHT_STRIDE * sizeof *w) : NULL;
    char err[256] = "";
    if (!w || texopt_lit_signal_weights(m, w, err, sizeof err) != TEXOPT_OK) {
        free(w);
        texopt_model_destroy(m);
        return NAN;
    }
    texopt_triopt_options opt = {.iterations = 10, .threads = 2, .seed = 7, .signal_weights = weighed ? w : NULL};
    stage_run r;
    double area = NAN;
    if (run_stage(&r, m, &opt, NULL) && r.status == TEXOPT_OK) {
        area = 0;
        for (int t = 20; t < 28; t++)
            area += r.out[t].lambda1 * r.out[t].lambda2 / 8;
    }
    close_stage(&r);
    free(w);
    return area;
}

TEST(detail_the_light_does_not_show_gets_no_texels)
{
    /* Strokes in the metallic-roughness map's B (metallic) under a metallic factor of 0, which
     * hides them from every lit term: compared as they are they hold the quads near input
     * density; weighed (0) they are flat colour. */
    double hidden = mr_detail_area(2, 0), hidden_weighed = mr_detail_area(2, 1);
    /* The same strokes as roughness: the light shows them, weighed they still count. */
    double rough_weighed = mr_detail_area(1, 1);
    /* In R, which the glTF specification gives metallic-roughness no use for: never compared. */
    double unread = mr_detail_area(0, 0);
    printf("  detailed quads' area: B %.3f, B weighed %.3f, G weighed %.3f, R %.3f\n", hidden, hidden_weighed,
           rough_weighed, unread);
    CHECK(hidden > 0.2);
    CHECK_NEAR(hidden_weighed, 0.01, 1e-12);
    CHECK_MSG(rough_weighed > 0.05, "roughness strokes weighed: %g", rough_weighed); /* measured 0.122 */
    CHECK_NEAR(unread, 0.01, 1e-12);
}

/* Mean target area of quads 10..13 (strokes) and 2..5 (flat) of a strip whose base colour is
 * flat with the "half" pattern in its alpha, shown by the material or not. */
static void alpha_detail_areas(int shown, double *detail, double *flat)
{
    texopt_model *m = strip_model(16, 256, "flat", 0);
    *detail = *flat = NAN;
    if (!m || fixture_add_alpha(&m->images[0], "half") != 0) {
        texopt_model_destroy(m);
        return;
    }
    m->materials[0].alpha_mode = shown ? TEXOPT_ALPHA_MASK : TEXOPT_ALPHA_OPAQUE;
    m->materials[0].alpha_cutoff = 0.5;
    texopt_triopt_options opt = {.iterations = 10, .threads = 2, .seed = 7};
    stage_run r;
    if (run_stage(&r, m, &opt, NULL) && r.status == TEXOPT_OK) {
        *detail = *flat = 0;
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 2; k++) {
                *flat += r.out[2 * (2 + i) + k].lambda1 * r.out[2 * (2 + i) + k].lambda2 / 8;
                *detail += r.out[2 * (10 + i) + k].lambda1 * r.out[2 * (10 + i) + k].lambda2 / 8;
            }
    }
    close_stage(&r);
}

TEST(a_cut_out_keeps_the_texels_of_its_edges)
{
    /* alphaMode MASK or BLEND: the strokes in alpha are what the surface shows, so their quads
     * keep texels as colour strokes would (flat_half_gets_far_fewer_texels_than_detail);
     * OPAQUE: alpha is not rendered and every quad is flat colour. */
    double detail, flat, detail_hidden, flat_hidden;
    alpha_detail_areas(1, &detail, &flat);
    alpha_detail_areas(0, &detail_hidden, &flat_hidden);
    printf("  alpha shown: detail %.3f flat %.3f; hidden: detail %.3f flat %.3f\n", detail, flat, detail_hidden,
           flat_hidden);
    CHECK_MSG(detail > 0.2, "detail %g", detail);
    CHECK_NEAR(flat, 0.01, 1e-12);
    CHECK_NEAR(detail_hidden, 0.01, 1e-12);
    CHECK_NEAR(flat_hidden, 0.01, 1e-12);
}

TEST(sampled_weights_of_a_flat_texture_are_zero)
{
    /* What the flat shortcut assumes: with a loss that is 0 at lambda_min I, the sampled
     * eq. 17 variances (the plain plan samples them) are 0 too. A linear gradient is smooth
     * everywhere but at the texture's wrap (x = 0): quads 2..5 keep their one-rings off it. */
    texopt_triopt_options opt = {.iterations = 2, .threads = 2, .plain = 1};
    stage_run r;
    CHECK(run_stage(&r, strip_model(8, 64, "gradient", 0), &opt, NULL));
    CHECK_OK(r.status, r.err);
    for (size_t t = 4; t < 12; t++) {
        CHECK(r.out[t].evaluations > 16);
        CHECK_MSG(r.out[t].w_rotation < 1e-12 && r.out[t].w_stretch < 1e-12, "triangle %zu: wR %g wS %g", t,
                  r.out[t].w_rotation, r.out[t].w_stretch);
    }
    close_stage(&r);
    /* and the shortcut takes it after one evaluation */
    texopt_triopt_options fast = {.iterations = 2, .threads = 2};
    CHECK(run_stage(&r, strip_model(8, 64, "gradient", 0), &fast, NULL));
    CHECK_OK(r.status, r.err);
    for (size_t t = 4; t < 12; t++) {
        CHECK_EQ_INT(r.out[t].evaluations, 1);
        CHECK(r.out[t].w_rotation == 0.0 && r.out[t].w_stretch == 0.0);
    }
    /* next to the wrap, the discontinuity is detail: searched and weighted */
    CHECK(r.out[0].evaluations > 1);
    close_stage(&r);
}

/* Share of triangles whose squeeze direction lies within 15 degrees of `target` degrees
 * among those with a clear anisotropy (ratio >= 2), and their mean area. */
static void stripe_summary(const stage_run *r, double target, double *aligned, double *area)
{
    int n = 0, ok = 0;
    *area = 0;
    for (size_t t = 0; t < r->mesh->triangle_count; t++) {
        const texopt_triangle_target *o = &r->out[t];
        *area += o->lambda1 * o->lambda2 / (double)r->mesh->triangle_count;
        double lo = fmin(o->lambda1, o->lambda2), hi = fmax(o->lambda1, o->lambda2);
        if (hi < 2 * lo)
            continue;
        n++;
        double d = fabs(squeeze_direction_degrees(o) - target);
        ok += fmin(d, 180 - d) < 15;
    }
    *aligned = n ? (double)ok / n : 0;
}

TEST(stripes_squeeze_along_the_grid_with_the_quarter_turn_symmetry)
{
    /* Paper Fig. 7: detail aligned with the texel grid compresses along itself; turned by a
     * quarter it compresses along the other axis; at 45 degrees (a staircase on the grid)
     * it barely compresses at all. */
    texopt_triopt_options opt = {.iterations = 10, .threads = 2, .seed = 3, .weight_samples = -1};
    stage_run vertical, horizontal, diagonal;
    CHECK(run_stage(&vertical, strip_model(8, 64, "stripes0", 0), &opt, NULL));
    CHECK(run_stage(&horizontal, strip_model(8, 64, "stripes0", 1), &opt, NULL));
    CHECK(run_stage(&diagonal, strip_model(8, 64, "stripes45", 0), &opt, NULL));
    CHECK_OK(vertical.status, vertical.err);
    CHECK_OK(horizontal.status, horizontal.err);
    CHECK_OK(diagonal.status, diagonal.err);
    double va, varea, ha, harea, da, darea;
    stripe_summary(&vertical, 90, &va, &varea);
    stripe_summary(&horizontal, 0, &ha, &harea);
    stripe_summary(&diagonal, 0, &da, &darea);
    CHECK_MSG(va >= 0.75, "vertical stripes: %.2f squeezed along y", va);
    CHECK_MSG(ha >= 0.75, "horizontal stripes: %.2f squeezed along x", ha);
    CHECK_MSG(varea < 0.3 && harea < 0.3, "areas %g %g", varea, harea);
    CHECK_MSG(fabs(varea - harea) < 0.05, "quarter turn changes the area: %g vs %g", varea, harea);
    CHECK_MSG(darea > 1.5 * varea && darea > 1.5 * harea, "diagonal %g vs %g, %g", darea, varea, harea);
    close_stage(&vertical);
    close_stage(&horizontal);
    close_stage(&diagonal);
}

TEST(structured_search_alone_finds_the_stripe_squeeze)
{
    /* Without any BO iteration: flat test, isotropic and grid-aligned anisotropic golden
     * sections must still find the squeeze along vertical stripes (J = diag(1, lambda_min)). */
    texopt_triopt_options opt = {.iterations = -1, .threads = 2, .weight_samples = 4};
    stage_run r;
    CHECK(run_stage(&r, strip_model(8, 64, "stripes0", 0), &opt, NULL));
    CHECK_OK(r.status, r.err);
    double aligned, area;
    stripe_summary(&r, 90, &aligned, &area);
    CHECK_MSG(aligned >= 0.75 && area < 0.3, "aligned %.2f, area %.3f", aligned, area);
    for (size_t t = 0; t < r.mesh->triangle_count; t++) {
        CHECK(r.out[t].loss < 0.01);
        CHECK(r.out[t].evaluations <= 1 + 8 + 1 + 3 * (16 + 8) + 8);
    }
    close_stage(&r);
}

/* Sum of one weight over the triangles of a run. */
static double weight_sum(const stage_run *r, int stretch)
{
    double sum = 0.0;
    for (size_t t = 0; t < r->mesh->triangle_count; t++)
        sum += stretch ? r->out[t].w_stretch : r->out[t].w_rotation;
    return sum;
}

TEST(few_weight_samples_agree_with_dense_sampling)
{
    /* Eq. 17 from the default 4 samples per weight must estimate the same variances as 32
     * samples: over the stripe strip their sums agree within a factor 1.6 (measured 0.83 for
     * the rotation, 1.22 for the stretch; samples missing part of the range move them
     * further), and both are positive (turning or stretching stripes off their squeeze
     * changes the loss). */
    texopt_triopt_options few = {.iterations = -1, .threads = 2, .seed = 5, .weight_samples = 4};
    texopt_triopt_options dense = few;
    dense.weight_samples = 32;
    stage_run a, b;
    CHECK(run_stage(&a, strip_model(8, 64, "stripes0", 0), &few, NULL));
    CHECK(run_stage(&b, strip_model(8, 64, "stripes0", 0), &dense, NULL));
    CHECK_OK(a.status, a.err);
    CHECK_OK(b.status, b.err);
    for (int stretch = 0; stretch < 2; stretch++) {
        double ratio = weight_sum(&a, stretch) / weight_sum(&b, stretch);
        printf("%s weight, 4 vs 32 samples: sum ratio %.3f\n", stretch ? "stretch" : "rotation", ratio);
        CHECK_MSG(weight_sum(&b, stretch) > 0.0 && ratio > 1.0 / 1.6 && ratio < 1.6, "%s: sums %g vs %g",
                  stretch ? "stretch" : "rotation", weight_sum(&a, stretch), weight_sum(&b, stretch));
    }
    close_stage(&a);
    close_stage(&b);
}

TEST(output_does_not_depend_on_the_thread_count)
{
    texopt_triopt_options opt = {.iterations = 8, .threads = 1, .seed = 11};
    stage_run one, two;
    CHECK(run_stage(&one, strip_model(8, 64, "checker", 0), &opt, NULL));
    opt.threads = 2;
    CHECK(run_stage(&two, strip_model(8, 64, "checker", 0), &opt, NULL));
    CHECK_OK(one.status, one.err);
    CHECK_OK(two.status, two.err);
    CHECK(memcmp(one.out, two.out, sizeof *one.out * one.mesh->triangle_count) == 0);
    CHECK(one.report.mean_objective == two.report.mean_objective);
    /* A different seed gives a different search. */
    stage_run other;
    opt.seed = 12;
    CHECK(run_stage(&other, strip_model(8, 64, "checker", 0), &opt, NULL));
    CHECK(memcmp(one.out, other.out, sizeof *one.out * one.mesh->triangle_count) != 0);
    close_stage(&one);
    close_stage(&two);
    close_stage(&other);
}

typedef struct progress_log {
    atomic_int cancel;
    atomic_int inside;
    int calls, overlapped, cancel_after;
    double last_fraction, last_mean_loss, last_mean_area;
} progress_log;

static void on_progress(void *user, const texopt_progress *p)
{
    progress_log *log = user;
    if (atomic_fetch_add(&log->inside, 1) != 0)
        log->overlapped++;
    log->calls++;
    log->last_fraction = p->stage_fraction;
    log->last_mean_loss = p->mean_loss;
    log->last_mean_area = p->mean_area_scale;
    if (log->cancel_after > 0 && log->calls >= log->cancel_after)
        atomic_store(&log->cancel, 1);
    atomic_fetch_sub(&log->inside, 1);
}

TEST(progress_reaches_one_and_cancel_stops)
{
    progress_log log = {.cancel_after = 0};
    atomic_init(&log.cancel, 0);
    atomic_init(&log.inside, 0);
    texopt_monitor mon = {.on_progress = on_progress, .user = &log, .cancel = &log.cancel};
    texopt_triopt_options opt = {.iterations = 4, .threads = 2, .weight_samples = -1};
    stage_run r;
    CHECK(run_stage(&r, strip_model(8, 64, "half", 0), &opt, &mon));
    CHECK_OK(r.status, r.err);
    CHECK_EQ_INT(log.calls, 16);
    CHECK_EQ_INT(log.overlapped, 0);
    CHECK_NEAR(log.last_fraction, 1.0, 1e-12);
    CHECK_NEAR(log.last_mean_loss, r.report.mean_loss, 1e-9);
    CHECK_NEAR(log.last_mean_area, r.report.mean_area_scale, 1e-9);
    close_stage(&r);

    progress_log stop = {.cancel_after = 2};
    atomic_init(&stop.cancel, 0);
    atomic_init(&stop.inside, 0);
    texopt_monitor mon2 = {.on_progress = on_progress, .user = &stop, .cancel = &stop.cancel};
    CHECK(run_stage(&r, strip_model(8, 64, "half", 0), &opt, &mon2));
    CHECK_EQ_INT(r.status, TEXOPT_E_CANCELED);
    CHECK(strstr(r.err, "cancel") != NULL);
    CHECK(stop.calls < 16);
    close_stage(&r);
}

TEST(degenerate_triangles_keep_the_identity)
{
    /* Triangle 1 is a sliver with three collinear corners. */
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2f, 0.2f, 0, 0.4f, 0.4f, 0, 0.6f, 0.6f, 0};
    const float uv[] = {0.1f, 0.1f, 0.6f, 0.1f, 0.1f, 0.6f, 0.2f, 0.2f, 0.3f, 0.3f, 0.4f, 0.4f};
    const uint32_t tris[] = {0, 1, 2, 3, 4, 5};
    texopt_triopt_options opt = {.iterations = 4, .threads = 1};
    stage_run r;
    CHECK(run_stage(&r, fixture_model_from_arrays(pos, uv, 6, tris, 2, 32, 32, "checker"), &opt, NULL));
    CHECK_OK(r.status, r.err);
    CHECK(r.mesh->flags[1] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV));
    CHECK_EQ_INT(r.out[1].evaluations, 0);
    CHECK(r.out[1].lambda1 == 1.0 && r.out[1].lambda2 == 1.0 && r.out[1].alpha == 0.0);
    CHECK(r.out[0].evaluations > 0);
    CHECK_EQ_INT(r.report.optimised, 1);
    CHECK_EQ_INT(r.report.skipped, 1);
    close_stage(&r);
}

TEST(triopt_rejects_bad_options)
{
    texopt_triopt_options bad[] = {{.epsilon = -0.5},  {.lambda_min = 1.5},
                                   {.iterations = -3}, {.iterations = -1, .plain = 1},
                                   {.viewport = 4},    {.weight_samples = 1000}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        stage_run r;
        CHECK(run_stage(&r, fixture_textured_quad(16, "flat"), &bad[i], NULL));
        CHECK_EQ_INT(r.status, TEXOPT_E_INVALID_ARGUMENT);
        CHECK(r.err[0] != '\0');
        close_stage(&r);
    }
    char err[64];
    CHECK(texopt_triopt_run(NULL, NULL, NULL, NULL, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
}

/* The paper's plan with its window (job method "paper") searches the rotation: on 45-degree
 * stripes some triangle ends rotated (alpha != 0), which the default plan's searches never
 * try. */
TEST(the_paper_plan_searches_the_rotation)
{
    texopt_triopt_options opt = {.iterations = 20, .threads = 2, .plain = 1, .paper_window = 1, .weight_samples = -1};
    stage_run r;
    CHECK(run_stage(&r, strip_model(8, 64, "stripes45", 0), &opt, NULL));
    CHECK_OK(r.status, r.err);
    int rotated = 0;
    for (size_t t = 0; t < r.mesh->triangle_count; t++) {
        CHECK(r.out[t].evaluations > 20);
        CHECK(r.out[t].alpha >= 0 && r.out[t].alpha < PI / 2);
        rotated += r.out[t].alpha > 1e-3;
    }
    printf("  paper plan: %d of %zu triangles rotated\n", rotated, r.mesh->triangle_count);
    CHECK(rotated > 0);
    close_stage(&r);
}
