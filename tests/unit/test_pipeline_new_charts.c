/* test_pipeline_new_charts.c - `charts new` through the whole job (pipeline.c,
 * job/domain_rechart.h, model/model_split.h, the split vertices saved by io/gltf_save.cpp):
 *  - a grid folded once at a right angle, its input UVs one flat chart across the fold: new
 *    charts cut at the fold (two charts, the fold's vertices split); the re-bake reads the
 *    input texture through the input UVs, so the output looks like the input (q near the
 *    kept charts'), and the saved file holds the split vertices with the positions they
 *    copy and passes the Khronos validator; stage 2 solved each new chart in a scaffold;
 *  - a flat grid (one planar patch): re-charted, its q stays near the kept layout's;
 *  - a fragmented atlas whose islands overlap (grid_glb.h): the input layout fails the layout
 *    check (its islands share texels), the new charts pass it and show the input's look
 *    (they join islands, though not across the seams where the overlap makes the texture
 *    jump: rechart.h may_cross). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "layout_check.h"
#include "mesh.h"

#include "pipeline.h"
#include "pipeline_scratch.h"
#include "test.h"

#define N 8

/* The grid of grid_fill with x > 1/2 turned up: (x, y, 0) -> (1/2, y, x - 1/2). */
static int write_folded_grid(const char *path, const char *pattern)
{
    size_t nv = (size_t)(N + 1) * (N + 1), nt = 2 * (size_t)N * N;
    float pos[(N + 1) * (N + 1) * 3], uv[(N + 1) * (N + 1) * 2];
    uint32_t idx[2 * N * N * 3];
    grid_fill(N, pos, uv, idx);
    for (size_t v = 0; v < nv; v++)
        if (pos[3 * v] > 0.5f) {
            pos[3 * v + 2] = pos[3 * v] - 0.5f;
            pos[3 * v] = 0.5f;
        }
    const char *patterns[1] = {pattern};
    return write_mesh_glb_material(path, pos, uv, nv, idx, nt, 64, patterns, 1,
                                   "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}");
}

static int run_validator(const char *file, const char *baseline)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "node '%s/tools/validate-gltf.mjs' '%s' --baseline '%s' >/dev/null 2>&1",
             TEXOPT_SOURCE_DIR, file, baseline);
    int rc = system(cmd);
    return rc == -1 ? -1 : WEXITSTATUS(rc);
}

static cJSON *first_domain(cJSON *stats)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(stats, "domains"), 0);
}

/* The share of 4000 surface points (triangle t, fixed barycentrics) whose colour, the nearest
 * texel of base colour through the UVs, differs by more than 0.25 between the two files. */
static double colours_changed(const char *in_path, const char *out_path)
{
    texopt_model *a = load(in_path), *b = load(out_path);
    double changed = 1;
    if (a && b && a->triangle_count == b->triangle_count && a->image_count > 0 && b->image_count > 0) {
        size_t differ = 0, n = 4000;
        for (size_t i = 0; i < n; i++) {
            size_t t = (i * 7919) % a->triangle_count;
            double w[3] = {0.2 + 0.6 * (double)(i % 7) / 7, 0, 0};
            w[1] = (1 - w[0]) * (0.1 + 0.8 * (double)(i % 11) / 11);
            w[2] = 1 - w[0] - w[1];
            float c[2][3];
            const texopt_model *m[2] = {a, b};
            for (int k = 0; k < 2; k++) {
                double u = 0, v = 0;
                for (int j = 0; j < 3; j++) {
                    uint32_t vx = m[k]->triangles[3 * t + (size_t)j];
                    u += w[j] * m[k]->uvs[2 * vx];
                    v += w[j] * m[k]->uvs[2 * vx + 1];
                }
                const texopt_image *img = &m[k]->images[0];
                int x = (int)floor(u * img->width), y = (int)floor(v * img->height);
                x = x < 0 ? 0 : x >= img->width ? img->width - 1 : x;
                y = y < 0 ? 0 : y >= img->height ? img->height - 1 : y;
                memcpy(c[k], texopt_image_at(img, x, y), sizeof c[k]);
            }
            differ +=
                fabs(c[0][0] - c[1][0]) > 0.25 || fabs(c[0][1] - c[1][1]) > 0.25 || fabs(c[0][2] - c[1][2]) > 0.25;
        }
        changed = (double)differ / (double)n;
    }
    texopt_model_destroy(a);
    texopt_model_destroy(b);
    return changed;
}

static double run(const scratch *s, texopt_charts charts, double relative_cost, cJSON **stats)
{
    texopt_params p = {0};
    p.method = TEXOPT_METHOD_ARAP;
    p.relative_cost = relative_cost;
    p.evaluate = 1;
    p.charts = charts;
    char err[512] = "";
    *stats = NULL;
    texopt_status st = texopt_optimize_file(s->in, s->out, s->stats, &p, NULL, err, sizeof err);
    if (st != TEXOPT_OK) {
        test_fail(__FILE__, __LINE__, "charts %s: %s", texopt_charts_name(charts), err);
        return NAN;
    }
    *stats = read_json(s->stats);
    cJSON *ev = *stats ? cJSON_GetObjectItem(*stats, "evaluation") : NULL;
    return ev ? cJSON_GetObjectItem(ev, "q")->valuedouble : NAN;
}

TEST(new_charts_cut_the_fold_and_keep_the_look)
{
    scratch s;
    CHECK(scratch_init(&s, 0, 0, NULL) == 0);
    CHECK(write_folded_grid(s.in, "gradient") == 0);
    cJSON *keep = NULL, *fresh = NULL;
    double q_keep = run(&s, TEXOPT_CHARTS_KEEP, 1.0, &keep);
    double q_new = run(&s, TEXOPT_CHARTS_NEW, 1.0, &fresh);
    CHECK(keep && fresh);
    cJSON *d = cJSON_GetArrayItem(cJSON_GetObjectItem(fresh, "domains"), 0);
    cJSON *nc = cJSON_GetObjectItem(d, "new_charts");
    CHECK(nc != NULL);
    CHECK_EQ_INT(cJSON_GetObjectItem(nc, "charts")->valueint, 2);
    CHECK_EQ_INT(cJSON_GetObjectItem(fresh, "vertices_split")->valueint, N + 1);
    CHECK(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(keep, "domains"), 0), "new_charts") == NULL);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(d, "layout_check"), "passed")));
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(d, "repacked")));
    /* stage 2 boxed every new chart in scaffold triangles (params.h: new charts are bijective) */
    cJSON *scaffold = cJSON_GetObjectItem(cJSON_GetObjectItem(d, "stage2"), "scaffold");
    CHECK(scaffold != NULL);
    if (scaffold) {
        CHECK_EQ_INT(cJSON_GetObjectItem(scaffold, "charts")->valueint, 2);
        CHECK_EQ_INT(cJSON_GetObjectItem(scaffold, "skipped_charts")->valueint, 0);
    }
    CHECK_MSG(q_new < 2 * q_keep + 0.005, "q new charts %g, kept charts %g", q_new, q_keep);
    texopt_model *out = load(s.out);
    CHECK(out != NULL);
    if (out) {
        CHECK_EQ_INT(out->vertex_count, (N + 1) * (N + 1) + N + 1);
        /* the copies lie on the fold, x = 1/2, and every triangle keeps its 3D corners */
        for (size_t v = (N + 1) * (N + 1); v < out->vertex_count; v++)
            CHECK_NEAR(out->positions[3 * v], 0.5, 1e-6);
        double area = 0;
        for (size_t t = 0; t < out->triangle_count; t++) {
            const float *a = out->positions + 3 * out->triangles[3 * t],
                        *b = out->positions + 3 * out->triangles[3 * t + 1],
                        *c = out->positions + 3 * out->triangles[3 * t + 2];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        }
        CHECK_NEAR(area, 1.0, 1e-5);
        texopt_model_destroy(out);
    }
    CHECK_EQ_INT(run_validator(s.out, s.in), 0);
    CHECK(colours_changed(s.in, s.out) < 0.01);
    cJSON_Delete(keep);
    cJSON_Delete(fresh);
    scratch_free(&s);
}

TEST(a_planar_patch_re_charted_keeps_its_look)
{
    scratch s;
    CHECK(scratch_init(&s, N, 64, "checker") == 0);
    cJSON *keep = NULL, *fresh = NULL;
    double q_keep = run(&s, TEXOPT_CHARTS_KEEP, 1.0, &keep);
    double q_new = run(&s, TEXOPT_CHARTS_NEW, 1.0, &fresh);
    CHECK(keep && fresh);
    cJSON *nc = fresh ? cJSON_GetObjectItem(first_domain(fresh), "new_charts") : NULL;
    CHECK(nc && cJSON_GetObjectItem(nc, "charts")->valueint == 1);
    CHECK(fresh && cJSON_GetObjectItem(fresh, "vertices_split")->valueint == 0);
    CHECK_MSG(q_new < 1.5 * q_keep + 0.002, "q new charts %g, kept charts %g", q_new, q_keep);
    cJSON_Delete(keep);
    cJSON_Delete(fresh);
    scratch_free(&s);
}

/* Whether the input layout of the model at path fails the layout check (against itself). */
static int input_layout_fails_check(const char *path)
{
    texopt_model *m = load(path);
    texopt_mesh *mesh = NULL;
    char err[256];
    int fails = -1;
    if (m && texopt_mesh_create(&mesh, m, 0, err, sizeof err) == TEXOPT_OK) {
        texopt_layout_check c;
        if (texopt_layout_check_run(mesh, mesh->texel, mesh->width, mesh->height, NULL, NULL, &c, err, sizeof err) ==
            TEXOPT_OK)
            fails = c.failed != TEXOPT_LAYOUT_PASSED;
    }
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
    return fails;
}

/* Texel centres of the model's layout strictly inside two or more triangles (any charts). */
static size_t centres_covered_twice(const char *path)
{
    texopt_model *m = load(path);
    texopt_mesh *mesh = NULL;
    char err[256];
    size_t twice = (size_t)-1;
    if (m && texopt_mesh_create(&mesh, m, 0, err, sizeof err) == TEXOPT_OK) {
        int w = mesh->width, h = mesh->height;
        unsigned char *count = calloc((size_t)w * h, 1);
        twice = 0;
        for (size_t t = 0; count && t < mesh->triangle_count; t++) {
            const double *a = mesh->texel + 2 * mesh->triangle[3 * t], *b = mesh->texel + 2 * mesh->triangle[3 * t + 1],
                         *c = mesh->texel + 2 * mesh->triangle[3 * t + 2];
            double d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if (fabs(d) < 1e-12)
                continue;
            int x0 = (int)floor(fmin(a[0], fmin(b[0], c[0]))), x1 = (int)ceil(fmax(a[0], fmax(b[0], c[0])));
            int y0 = (int)floor(fmin(a[1], fmin(b[1], c[1]))), y1 = (int)ceil(fmax(a[1], fmax(b[1], c[1])));
            for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < h; y++)
                for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < w; x++) {
                    double px = x + 0.5, py = y + 0.5;
                    double l1 = ((px - a[0]) * (c[1] - a[1]) - (py - a[1]) * (c[0] - a[0])) / d;
                    double l2 = ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0])) / d;
                    if (l1 > 1e-6 && l2 > 1e-6 && 1 - l1 - l2 > 1e-6 && count[(size_t)y * w + x]++ == 1)
                        twice++;
                }
        }
        free(count);
    }
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
    return twice;
}

TEST(an_overlapping_input_layout_is_laid_out_anew)
{
    scratch s;
    CHECK(scratch_init(&s, 0, 0, NULL) == 0);
    CHECK(write_fragmented_grid_glb(s.in, N, 2, 1.5, 1.5707963267948966, 64, "gradient") == 0);
    CHECK_EQ_INT(input_layout_fails_check(s.in), 1);
    /* the islands cover their texels about twice: c_r 2 keeps the input's density */
    cJSON *fresh = NULL;
    double q_new = run(&s, TEXOPT_CHARTS_NEW, 2.0, &fresh);
    cJSON *d = fresh ? first_domain(fresh) : NULL;
    CHECK(d != NULL);
    if (d) {
        CHECK(cJSON_IsTrue(cJSON_GetObjectItem(d, "repacked")));
        CHECK(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(d, "layout_check"), "passed")));
        /* overlapping islands read other texels at their shared edges, so new charts stop at
           some of those seams (rechart.h may_cross), never cutting an island further */
        int charts = cJSON_GetObjectItem(cJSON_GetObjectItem(d, "new_charts"), "charts")->valueint;
        CHECK_MSG(charts >= 2 && charts <= (N / 2) * (N / 2), "%d new charts", charts);
    }
    CHECK_EQ_INT(input_layout_fails_check(s.out), 0);
    CHECK(centres_covered_twice(s.in) > 0);
    CHECK_EQ_INT(centres_covered_twice(s.out), 0);
    /* the look is the input's: the islands' sharp seams blur over a texel, nothing else */
    double changed = colours_changed(s.in, s.out);
    CHECK_MSG(changed < 0.03, "%.1f%% of the surface changed colour (q %g)", 100 * changed, q_new);
    cJSON_Delete(fresh);
    scratch_free(&s);
}
