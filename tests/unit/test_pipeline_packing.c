/* test_pipeline_packing.c - `packing refine` through the whole job (budget_layout.c,
 * layout/atlas_refine.h): an L-shaped flat chart with a jittered outline, laid out by arap
 * (isometric, so stage 2 keeps the jitter), is refined, the statistics report it, the
 * tighter packing is the one kept, and without the option nothing is refined. The refined
 * L is cut once into two pieces (chart_cut.h), measured in the statistics: more boundary,
 * the vertices along the cut split, and the written layout still passes the check. */
#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

#include "pipeline.h"
#include "pipeline_scratch.h"
#include "rng.h"
#include "test.h"

#define N 12

static int in_l(int i, int j)
{
    return !(i >= N / 2 && j >= N / 2);
}

/* The L of N x N cells without its upper right quadrant, every vertex jittered in the
 * plane, UV = position. */
static int write_l_glb(const char *path)
{
    float pos[3 * (N + 1) * (N + 1)], uv[2 * (N + 1) * (N + 1)];
    uint32_t idx[6 * N * N];
    texopt_rng rng;
    texopt_rng_seed(&rng, 3);
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            int v = j * (N + 1) + i;
            double x = (i + 0.3 * (texopt_rng_uniform(&rng) - 0.5)) / (N + 1) + 0.02;
            double y = (j + 0.3 * (texopt_rng_uniform(&rng) - 0.5)) / (N + 1) + 0.02;
            pos[3 * v] = uv[2 * v] = (float)x;
            pos[3 * v + 1] = uv[2 * v + 1] = (float)y;
            pos[3 * v + 2] = 0;
        }
    size_t nt = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            if (!in_l(i, j))
                continue;
            uint32_t a = (uint32_t)(j * (N + 1) + i), t[6] = {a, a + 1, a + N + 2, a, a + N + 2, a + N + 1};
            memcpy(idx + 3 * nt, t, sizeof t);
            nt += 2;
        }
    /* vertices of the removed quadrant's interior are unused; the mesh keeps them */
    return write_mesh_glb(path, pos, uv, (N + 1) * (N + 1), idx, nt, 128, "checker", NULL);
}

static void run_arap(int refine, cJSON **stats)
{
    scratch s;
    *stats = NULL;
    CHECK(scratch_init(&s, 0, 0, NULL) == 0);
    CHECK(write_l_glb(s.in) == 0);
    texopt_params p = {0};
    p.method = TEXOPT_METHOD_ARAP;
    p.relative_cost = 1.0;
    p.packing_refine = refine;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    *stats = read_json(s.stats);
    scratch_free(&s);
}

/* The number at key, NaN when there is none (every comparison with it fails). */
static double number(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItem(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

TEST(the_refined_packing_is_reported_and_kept_only_when_tighter)
{
    cJSON *on, *off;
    run_arap(1, &on);
    run_arap(0, &off);
    CHECK(on != NULL && off != NULL);
    cJSON *d_on = cJSON_GetArrayItem(cJSON_GetObjectItem(on, "domains"), 0);
    cJSON *d_off = cJSON_GetArrayItem(cJSON_GetObjectItem(off, "domains"), 0);
    cJSON *a = cJSON_GetObjectItem(d_on, "atlas_refine");
    CHECK(a != NULL);
    CHECK(cJSON_GetObjectItem(d_off, "atlas_refine") == NULL);
    CHECK(strcmp(cJSON_GetObjectItem(cJSON_GetObjectItem(on, "params"), "packing")->valuestring, "refine") == 0);
    CHECK(strcmp(cJSON_GetObjectItem(cJSON_GetObjectItem(off, "params"), "packing")->valuestring, "plain") == 0);
    CHECK(number(a, "charts") == 1 && number(a, "skipped_charts") == 0);
    double before = number(a, "packing_efficiency_before"), after = number(a, "packing_efficiency_after");
    const char *kept = cJSON_GetObjectItem(a, "kept")->valuestring;
    CHECK_MSG(strcmp(kept, after > before ? "refined" : "plain") == 0, "kept %s with %.4f -> %.4f", kept, before,
              after);
    CHECK(number(a, "distortion") > 1.0 && number(a, "distortion") <= 1.1);
    CHECK(number(a, "boundary_length_before") > 0 && number(a, "boundary_length_after") > 0);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(d_on, "layout_check"), "passed")));
    CHECK(number(a, "charts_cut") == 1 && number(a, "pieces") == 2 && number(a, "cuts") == 1);
    /* a cut across the L's 6 cells, along mesh edges: about 7 vertices */
    CHECK_MSG(number(a, "vertices_split") >= 6 && number(a, "vertices_split") <= 12, "%g vertices split",
              number(a, "vertices_split"));
    CHECK(number(a, "boundary_length_cut") > number(a, "boundary_length_after"));
    /* two rectangles pack tighter than the refined L (0.82 against 0.69 when written) */
    CHECK_MSG(number(a, "packing_efficiency_cut") > after + 0.05 && number(a, "packing_efficiency_cut") <= 1,
              "cut %.3f", number(a, "packing_efficiency_cut"));
    cJSON_Delete(on);
    cJSON_Delete(off);
}
