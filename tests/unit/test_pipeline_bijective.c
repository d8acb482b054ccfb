/* test_pipeline_bijective.c - `bijective` through the whole job (pipeline.c, layout/scaffold.h):
 * the statistics report the scaffold, and a layout that needs no motion is not moved by it. */
#include <cjson/cJSON.h>
#include <string.h>

#include "grid_glb.h"
#include "mesh.h"
#include "pipeline.h"
#include "pipeline_scratch.h"
#include "scaffold.h"
#include "test.h"

static cJSON *first_domain(cJSON *root)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(root, "domains"), 0);
}

/* arap on a flat grid: isometric targets, so the charts keep their shape (output symmetric
 * Dirichlet 4, as without scaffold) while every chart is solved inside its scaffold. */
static void run_arap(int bijective, cJSON **stats)
{
    scratch s;
    *stats = NULL;
    CHECK(scratch_init(&s, 3, 128, "flat") == 0);
    texopt_params p = {0};
    p.method = TEXOPT_METHOD_ARAP;
    p.relative_cost = 0.5;
    p.bijective = bijective;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    *stats = read_json(s.stats);
    scratch_free(&s);
}

TEST(the_statistics_report_the_scaffold_and_it_leaves_an_isometry_alone)
{
    cJSON *on, *off;
    run_arap(1, &on);
    CHECK(on != NULL);
    run_arap(0, &off);
    CHECK(off != NULL);
    cJSON *d_on = first_domain(on), *d_off = first_domain(off);
    cJSON *sc = cJSON_GetObjectItem(cJSON_GetObjectItem(d_on, "stage2"), "scaffold");
    CHECK(sc != NULL);
    CHECK_EQ_INT(cJSON_GetObjectItem(sc, "charts")->valuedouble, cJSON_GetObjectItem(d_on, "charts")->valuedouble);
    CHECK_EQ_INT(cJSON_GetObjectItem(sc, "skipped_charts")->valuedouble, 0);
    CHECK(cJSON_GetObjectItem(sc, "rounds")->valuedouble >= 1);
    CHECK(cJSON_GetObjectItem(sc, "triangles")->valuedouble > 0);
    CHECK(cJSON_GetObjectItem(cJSON_GetObjectItem(d_off, "stage2"), "scaffold") == NULL);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(on, "params"), "bijective")));
    double sd_on =
        cJSON_GetObjectItem(cJSON_GetObjectItem(d_on, "distortion"), "symmetric_dirichlet_output")->valuedouble;
    CHECK_NEAR(sd_on, 4.0, 1e-3);
    cJSON_Delete(on);
    cJSON_Delete(off);
}

#define N 8

/* The grid of grid_fill with a Z fold in u: column 5 runs back (FLIPPED) and columns 6-7
 * forward again over columns 4-5, so one chart covers texels twice with one orientation. */
static int write_z_folded_grid(const char *path)
{
    size_t nv = (size_t)(N + 1) * (N + 1), nt = 2 * (size_t)N * N;
    float pos[(N + 1) * (N + 1) * 3], uv[(N + 1) * (N + 1) * 2];
    uint32_t idx[2 * N * N * 3];
    grid_fill(N, pos, uv, idx);
    for (size_t v = 0; v < nv; v++)
        if (v % (N + 1) >= 6)
            uv[2 * v] = (float)((double)(v % (N + 1) - 2) / N);
    const char *patterns[1] = {"gradient"};
    return write_mesh_glb_material(path, pos, uv, nv, idx, nt, 64, patterns, 1,
                                   "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}");
}

/* Texel centres covered twice within a chart (one orientation) in the written file. */
static size_t written_within(const char *path)
{
    texopt_model *m = load(path);
    texopt_mesh *mesh = NULL;
    size_t within = (size_t)-1, between;
    char err[256];
    if (m && texopt_mesh_create(&mesh, m, 0, err, sizeof err) == TEXOPT_OK &&
        texopt_count_overlap(mesh, mesh->texel, &within, &between, err, sizeof err) != TEXOPT_OK)
        within = (size_t)-1;
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
    return within;
}

TEST(a_chart_folded_in_the_input_is_unfolded_and_written_without_overlap)
{
    scratch s;
    CHECK(scratch_init(&s, 0, 0, NULL) == 0);
    CHECK(write_z_folded_grid(s.in) == 0);
    CHECK_MSG(written_within(s.in) > 10, "the input covers %zu centres twice", written_within(s.in));
    texopt_params p = {0};
    p.method = TEXOPT_METHOD_TEWARI;
    p.relative_cost = 0.5;
    p.bijective = 1;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    CHECK_EQ_INT(written_within(s.out), 0);
    cJSON *stats = read_json(s.stats), *d = first_domain(stats);
    cJSON *sc = cJSON_GetObjectItem(cJSON_GetObjectItem(d, "stage2"), "scaffold");
    CHECK(sc != NULL);
    if (sc) {
        CHECK_EQ_INT(cJSON_GetObjectItem(sc, "overlapping_input_charts")->valuedouble, 1);
        CHECK_EQ_INT(cJSON_GetObjectItem(sc, "unfolded_charts")->valuedouble, 1);
        CHECK_EQ_INT(cJSON_GetObjectItem(sc, "skipped_charts")->valuedouble, 0);
    }
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(d, "repacked")));
    texopt_model *in = load(s.in), *out = load(s.out);
    CHECK(in && out && in->vertex_count == out->vertex_count); /* no vertex split */
    texopt_model_destroy(in);
    texopt_model_destroy(out);
    cJSON_Delete(stats);
    scratch_free(&s);
}
