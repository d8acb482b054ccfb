/* Tests of coverage.c: unique covered texels, the half-open fill rule on shared edges,
 * mirrored overlaps counted once, wrap modes, custom frames and refusals. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "coverage.h"
#include "fixtures.h"
#include "mesh.h"
#include "test.h"

/* Builds the mesh of domain 0 and measures its own layout, marking mesh->flags. */
static texopt_status measure_model(texopt_model *model, texopt_mesh **mesh, texopt_coverage *cov, char *err,
                                   size_t err_len)
{
    texopt_status st = texopt_mesh_create(mesh, model, 0, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_coverage_options opt = {.triangle_flags = (*mesh)->flags};
    return texopt_coverage_measure(*mesh, &opt, cov, err, err_len);
}

static size_t count_flag(const texopt_mesh *m, unsigned flag)
{
    size_t n = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        n += (m->flags[t] & flag) != 0;
    return n;
}

TEST(quad_covers_every_texel_once)
{
    /* The quad's diagonal runs through texel centres (k + 0.5, k + 0.5): the half-open rule
     * must give each to exactly one triangle. */
    texopt_model *model = fixture_textured_quad(64, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.width, 64);
    CHECK_EQ_INT(cov.covered_texels, 64 * 64);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    CHECK_EQ_INT(cov.overlapping_triangles, 0);
    CHECK_NEAR(cov.packing_efficiency, 1.0, 0);
    CHECK_NEAR(cov.texel_area, 64.0 * 64.0, 1e-9);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(shared_edges_never_double_count)
{
    /* 7 x 7 grid on 100 texels: edges cross texel rows at arbitrary fractions. */
    const int sizes[][2] = {{7, 100}, {8, 64}, {13, 97}};
    for (size_t i = 0; i < 3; i++) {
        texopt_model *model = fixture_grid(sizes[i][0], sizes[i][1], "flat");
        CHECK(model != NULL);
        texopt_mesh *m = NULL;
        texopt_coverage cov;
        char err[256] = "";
        CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
        CHECK_EQ_INT(cov.covered_texels, sizes[i][1] * sizes[i][1]);
        CHECK_MSG(cov.overlap_texels == 0, "grid %d on %d: %llu overlap texels", sizes[i][0], sizes[i][1],
                  (unsigned long long)cov.overlap_texels);
        CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_OVERLAPS), 0);
        texopt_mesh_destroy(m);
        texopt_model_destroy(model);
    }
}

TEST(cube_covers_its_six_squares)
{
    texopt_model *model = fixture_cube_with_seams(64);
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 6 * 16 * 16);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    CHECK_NEAR(cov.packing_efficiency, 0.375, 0);
    uint64_t total = 0;
    CHECK_OK(texopt_coverage_model_texels(model, &total, err, sizeof err), err);
    CHECK_EQ_INT(total, 6 * 16 * 16);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(sphere_coverage_tracks_texel_area)
{
    texopt_model *model = fixture_uv_sphere(24, 12, 256);
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    /* area = 256^2 (1 - 1/12): the pole bands are half covered by their fans */
    CHECK_NEAR(cov.texel_area, 256.0 * 256.0 * (1.0 - 1.0 / 12.0), 0.01);
    /* centre sampling errs only along the fans' zig-zag boundary: ~ half a texel per
     * boundary texel, 2 * 2 * 256 boundary texels at most */
    CHECK(fabs((double)cov.covered_texels - cov.texel_area) < 512.0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

/* Two quads in 3D, x in [0,1] and [x0, x0 + 1]; the first maps to the UV square, the second
 * mirrored onto [0, w] x [0, 1] (w = 1: the same texels; w = 0.5: the left half). With
 * x0 = 1 and w = 1 the halves meet at the mirror line with equal UVs there, so they weld. */
static texopt_model *mirrored_pair(float w, float x0, int tex)
{
    const float x1 = x0 + 1;
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, x0, 0, 0, x1, 0, 0, x1, 1, 0, x0, 1, 0};
    const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1, w, 0, 0, 0, 0, 1, w, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    return fixture_model_from_arrays(pos, uv, 8, tri, 4, tex, tex, "flat");
}

TEST(mirrored_halves_count_once_and_are_flagged)
{
    texopt_model *model = mirrored_pair(1.0f, 2.0f, 32);
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK_EQ_INT(m->chart_count, 2);
    CHECK_EQ_INT(m->chart_sign[1], -1);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_FLIPPED), 0);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlapping_triangles, 4);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_OVERLAPS), 4);
    CHECK_NEAR(cov.texel_area, 2 * 32.0 * 32.0, 1e-9);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);

    /* The mirrored copy squeezed onto the left half: half the texels are shared. */
    model = mirrored_pair(0.5f, 2.0f, 32);
    CHECK(model != NULL);
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 16 * 32);
    /* Every triangle of the first quad reaches the left half, so all four are flagged. */
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_OVERLAPS), 4);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(mirrored_halves_joined_at_the_mirror_line_are_one_chart_and_not_flipped)
{
    /* One chart, two halves of opposite orientation, each half the chart's area: a mirror,
     * not a fold-over, so nothing is FLIPPED; the shared texels are overlaps. */
    texopt_model *model = mirrored_pair(1.0f, 1.0f, 32);
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK_EQ_INT(m->chart_count, 1);
    CHECK_EQ_INT(m->point_count, 6);
    CHECK_EQ_INT(m->vertex_count, 6);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_FLIPPED), 0);
    CHECK(m->area_texel[0] * m->area_texel[2] < 0);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 32 * 32);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_OVERLAPS), 4);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(fold_over_overlaps_its_neighbours)
{
    texopt_model *model = fixture_grid(2, 64, "flat");
    CHECK(model != NULL);
    model->uvs[2 * 4] = 1.25f; /* folds triangles 3 and 6 (see test_mesh.c) */
    texopt_mesh *m = NULL;
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_model(model, &m, &cov, err, sizeof err), err);
    CHECK(cov.overlap_texels > 0);
    CHECK(m->flags[3] & TEXOPT_TRI_OVERLAPS);
    CHECK(m->flags[6] & TEXOPT_TRI_OVERLAPS);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

/* Shifts every UV of the model by (du, dv) and measures with the given wraps. */
static texopt_status measure_shifted(int tex, float du, float dv, float su, texopt_wrap wrap, texopt_coverage *cov,
                                     char *err, size_t err_len)
{
    texopt_model *model = fixture_textured_quad(tex, "flat");
    if (!model)
        return TEXOPT_E_NOMEM;
    for (size_t v = 0; v < model->vertex_count; v++) {
        model->uvs[2 * v] = model->uvs[2 * v] * su + du;
        model->uvs[2 * v + 1] += dv;
    }
    texopt_mesh *m = NULL;
    texopt_status st = texopt_mesh_create(&m, model, 0, err, err_len);
    texopt_coverage_options opt = {.use_wraps = 1, .wrap_s = wrap, .wrap_t = wrap};
    if (st == TEXOPT_OK)
        st = texopt_coverage_measure(m, &opt, cov, err, err_len);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
    return st;
}

TEST(repeat_copies_cover_the_same_texels)
{
    texopt_coverage cov;
    char err[256] = "";
    CHECK_OK(measure_shifted(32, 1.0f, 0.0f, 1.0f, TEXOPT_WRAP_REPEAT, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    CHECK_OK(measure_shifted(32, -3.0f, 2.0f, 1.0f, TEXOPT_WRAP_REPEAT, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    /* Quarter shift: the quad straddles u = 1 and still covers each texel once. */
    CHECK_OK(measure_shifted(32, 0.25f, 0.0f, 1.0f, TEXOPT_WRAP_REPEAT, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    /* u in [0, 2]: the texture is tiled twice across the quad: every texel read twice. */
    CHECK_OK(measure_shifted(32, 0.0f, 0.0f, 2.0f, TEXOPT_WRAP_REPEAT, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 32 * 32);
    CHECK_NEAR(cov.texel_area, 2 * 32.0 * 32.0, 1e-9);
}

TEST(mirror_and_clamp_wraps)
{
    texopt_coverage cov;
    char err[256] = "";
    /* u in [1, 2] mirrored reads the whole texture once */
    CHECK_OK(measure_shifted(32, 1.0f, 0.0f, 1.0f, TEXOPT_WRAP_MIRROR, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    /* u in [0, 2] under MIRROR: [0, 1] then [1, 2] reflected back over it: each texel twice. */
    CHECK_OK(measure_shifted(32, 0.0f, 0.0f, 2.0f, TEXOPT_WRAP_MIRROR, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 32 * 32);
    /* u in [0.5, 1.5] clamped: the right half of the texture; the clamped part reads the
     * last column, which the quad covers anyway, and is no overlap. */
    CHECK_OK(measure_shifted(32, 0.5f, 0.0f, 1.0f, TEXOPT_WRAP_CLAMP, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 16 * 32);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    /* the same quad under REPEAT covers everything */
    CHECK_OK(measure_shifted(32, 0.5f, 0.0f, 1.0f, TEXOPT_WRAP_REPEAT, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 32 * 32);
}

/* Independent reference: every texel centre of each triangle's unwrapped bounding box tested
 * with edge functions, mapped through the wrap mode by plain arithmetic. Random coordinates
 * put no centre exactly on an edge, so the half-open rule does not matter here. */
static int64_t wrap_index(int64_t x, int64_t n, texopt_wrap wrap, int *clamped)
{
    *clamped = 0;
    if (wrap == TEXOPT_WRAP_CLAMP) {
        *clamped = x < 0 || x >= n;
        return x < 0 ? 0 : x >= n ? n - 1 : x;
    }
    int64_t period = wrap == TEXOPT_WRAP_MIRROR ? 2 * n : n;
    int64_t r = ((x % period) + period) % period;
    return r < n ? r : 2 * n - 1 - r;
}

static void brute_force(const double *t, size_t count, int w, int h, texopt_wrap wrap, uint8_t *hits,
                        uint8_t *clamped_hits)
{
    for (size_t k = 0; k < count; k++) {
        const double *a = t + 6 * k, *b = a + 2, *c = a + 4;
        double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        double xmin = fmin(a[0], fmin(b[0], c[0])), xmax = fmax(a[0], fmax(b[0], c[0]));
        double ymin = fmin(a[1], fmin(b[1], c[1])), ymax = fmax(a[1], fmax(b[1], c[1]));
        for (int64_t y = (int64_t)floor(ymin) - 1; y <= (int64_t)ceil(ymax); y++)
            for (int64_t x = (int64_t)floor(xmin) - 1; x <= (int64_t)ceil(xmax); x++) {
                double px = (double)x + 0.5, py = (double)y + 0.5;
                double e0 = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
                double e1 = (c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]);
                double e2 = (a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]);
                if (!(area > 0 ? (e0 > 0 && e1 > 0 && e2 > 0) : (e0 < 0 && e1 < 0 && e2 < 0)))
                    continue;
                int cx, cy;
                int64_t wx = wrap_index(x, w, wrap, &cx), wy = wrap_index(y, h, wrap, &cy);
                size_t i = (size_t)wy * (size_t)w + (size_t)wx;
                if (cx || cy)
                    clamped_hits[i] = 1;
                else if (hits[i] < 2)
                    hits[i]++;
            }
    }
}

TEST(random_triangles_match_a_brute_force_count)
{
    enum { W = 37, H = 23, TRIS = 8 };
    const texopt_wrap wraps[3] = {TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_MIRROR, TEXOPT_WRAP_CLAMP};
    uint64_t state = 12345;
    for (int trial = 0; trial < 30; trial++) {
        /* disjoint triangles (no shared vertices): vertex 3k + i is corner i of triangle k,
         * within 0.3 of a centre anywhere in [-1, 2]^2: they overlap sometimes, never all */
        float pos[TRIS * 9], uv[TRIS * 6];
        uint32_t tri[TRIS * 3];
        double centre[2] = {0, 0};
        for (int i = 0; i < TRIS * 3; i++) {
            double r[2];
            for (int c = 0; c < 2; c++) {
                state = state * 6364136223846793005ull + 1442695040888963407ull;
                r[c] = (double)(state >> 11) / 9007199254740992.0;
            }
            if (i % 3 == 0) {
                centre[0] = -1.0 + 3.0 * r[0];
                centre[1] = -1.0 + 3.0 * r[1];
            }
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            double r1 = (double)(state >> 11) / 9007199254740992.0 - 0.5;
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            double r2 = (double)(state >> 11) / 9007199254740992.0 - 0.5;
            uv[2 * i] = (float)(centre[0] + 0.6 * r1);
            uv[2 * i + 1] = (float)(centre[1] + 0.6 * r2);
            pos[3 * i] = (float)i, pos[3 * i + 1] = (float)(i * i % 7), pos[3 * i + 2] = (float)(i % 3);
            tri[i] = (uint32_t)i;
        }
        texopt_model *model = fixture_model_from_arrays(pos, uv, TRIS * 3, tri, TRIS, W, H, "flat");
        CHECK(model != NULL);
        texopt_mesh *m = NULL;
        char err[256] = "";
        CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
        double t[TRIS * 6];
        for (size_t k = 0; k < TRIS * 3; k++) {
            t[2 * k] = m->texel[2 * m->triangle[k]];
            t[2 * k + 1] = m->texel[2 * m->triangle[k] + 1];
        }
        texopt_wrap wrap = wraps[trial % 3];
        uint8_t hits[W * H] = {0}, clamped[W * H] = {0};
        brute_force(t, TRIS, W, H, wrap, hits, clamped);
        uint64_t covered = 0, multi = 0;
        for (int i = 0; i < W * H; i++) {
            covered += hits[i] > 0 || clamped[i];
            multi += hits[i] > 1;
        }
        CHECK(covered > 0 && covered < (uint64_t)W * H);
        texopt_coverage_options opt = {.use_wraps = 1, .wrap_s = wrap, .wrap_t = wrap};
        texopt_coverage cov;
        CHECK_OK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err), err);
        CHECK_MSG(cov.covered_texels == covered && cov.overlap_texels == multi,
                  "trial %d wrap %d: covered %llu vs %llu, overlap %llu vs %llu", trial, (int)wrap,
                  (unsigned long long)cov.covered_texels, (unsigned long long)covered,
                  (unsigned long long)cov.overlap_texels, (unsigned long long)multi);
        texopt_mesh_destroy(m);
        texopt_model_destroy(model);
    }
}

TEST(custom_layout_and_frame)
{
    texopt_model *model = fixture_textured_quad(32, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    /* The layout halved, measured in a 64 x 64 frame: a 16 x 16 block. */
    double texel[8];
    for (size_t i = 0; i < 8; i++)
        texel[i] = 0.5 * m->texel[i];
    uint8_t flags[2] = {TEXOPT_TRI_OVERLAPS | TEXOPT_TRI_WRAPPED, 0};
    texopt_coverage_options opt = {.texel = texel, .width = 64, .height = 64, .triangle_flags = flags};
    texopt_coverage cov;
    CHECK_OK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.width, 64);
    CHECK_EQ_INT(cov.covered_texels, 16 * 16);
    CHECK_NEAR(cov.packing_efficiency, 256.0 / 4096.0, 1e-15);
    CHECK_NEAR(cov.texel_area, 256.0, 1e-12);
    /* the stale OVERLAPS bit is cleared, other bits kept */
    CHECK_EQ_INT(flags[0], TEXOPT_TRI_WRAPPED);
    CHECK_EQ_INT(flags[1], 0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(bad_layouts_are_refused)
{
    texopt_model *model = fixture_textured_quad(32, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    double texel[8];
    memcpy(texel, m->texel, sizeof texel);
    texel[3] = NAN;
    texopt_coverage cov = {.covered_texels = 12345};
    texopt_coverage_options opt = {.texel = texel};
    CHECK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle 0") != NULL);
    CHECK_EQ_INT(cov.covered_texels, 12345);
    texel[3] = 32.0 * 5000;
    CHECK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err) == TEXOPT_E_LIMIT);
    CHECK(strstr(err, "repeats") != NULL);
    texopt_coverage_options big = {.width = 1 << 15, .height = 1 << 15};
    CHECK(texopt_coverage_measure(m, &big, &cov, err, sizeof err) == TEXOPT_E_LIMIT);
    texopt_coverage_options neg = {.width = -1};
    CHECK(texopt_coverage_measure(m, &neg, &cov, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

/* A layout whose triangles each span a few hundred repeats, within the per-triangle limit,
 * but together cover 2^38 texels (minutes to fill) is refused before filling, saying how
 * often it repeats the texture; the same grid at a sixteenth of the scale is filled. */
TEST(a_layout_repeating_its_texture_past_the_total_limit_is_refused)
{
    texopt_model *model = fixture_grid(16, 64, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    size_t n = 2 * m->vertex_count;
    double *texel = malloc(n * sizeof *texel);
    CHECK(texel != NULL);
    texopt_coverage cov;
    texopt_coverage_options opt = {.texel = texel};
    for (size_t k = 0; k < n; k++)
        texel[k] = m->texel[k] * 8192; /* each triangle 512 repeats wide, 2^38 texels in all */
    CHECK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err) == TEXOPT_E_LIMIT);
    CHECK_MSG(strstr(err, "times the 64x64 texture") != NULL, "%s", err);
    for (size_t k = 0; k < n; k++)
        texel[k] = m->texel[k] * 512;
    CHECK_OK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err), err);
    CHECK_EQ_INT(cov.covered_texels, 64 * 64);
    free(texel);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(large_frame_is_fast)
{
    /* 131072 triangles over a 4096^2 frame (16.7 M texels). */
    texopt_model *model = fixture_grid(256, 8, "flat");
    CHECK(model != NULL);
    model->images[0].width = model->images[0].height = 4096; /* frame only; pixels unused */
    char err[256] = "";
    CHECK_OK(texopt_model_build_domains(model, err, sizeof err), err);
    model->images[0].width = model->images[0].height = 8;
    texopt_mesh *m = NULL;
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->width, 4096);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    texopt_coverage cov;
    CHECK_OK(texopt_coverage_measure(m, NULL, &cov, err, sizeof err), err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    printf("  coverage: %zu triangles on 4096^2 in %.3f s\n", m->triangle_count, seconds);
    CHECK_EQ_INT(cov.covered_texels, 4096ull * 4096ull);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    CHECK(seconds < 3.0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}
