/* test_pipeline_packing.c - `packing refine` through the whole job (budget_layout.c,
 * layout/atlas_refine.h): an L-shaped flat chart with a jittered outline, laid out by arap
 * (isometric, so stage 2 keeps the jitter), is refined, the statistics report it, the
 * tighter packing is the one kept, and without the option nothing is refined. The refined
 * L is cut once into two pieces (chart_cut.h), which pack tighter: the cut is written, the
 * file's vertices along it split (two charts in the file, as many vertices more as the
 * statistics say), and the written file's layout has no overlap. The reduction (section 3.3)
 * runs on the cut pieces, lowers their distortion relative to stage 2's L and is kept only
 * when it packs tightest. */
#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

#include "layout_check.h"
#include "mesh.h"
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

typedef struct written {
    size_t vertices, charts, overlapping, folded;
} written;

/* The written file's used vertices (the L's grid vertices and their copies), charts and
 * overlap (layout_check.h on its own layout). */
static void read_written(const char *path, written *w)
{
    texopt_model *m = load(path);
    CHECK(m != NULL);
    texopt_mesh *mesh = NULL;
    char err[256];
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    uint8_t *used = calloc(m->vertex_count, 1);
    for (size_t c = 0; c < 3 * m->triangle_count; c++)
        used[m->triangles[c]] = 1;
    w->vertices = 0;
    for (size_t v = 0; v < m->vertex_count; v++)
        w->vertices += used[v];
    w->charts = mesh->chart_count;
    texopt_layout_check check;
    CHECK_OK(texopt_layout_check_own(mesh, &check, err, sizeof err), err);
    w->overlapping = check.overlapping + check.overlapping_within;
    w->folded = check.folded;
    free(used);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

static void run_arap(int refine, cJSON **stats, written *w)
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
    read_written(s.out, w);
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
    written w_on, w_off;
    run_arap(1, &on, &w_on);
    run_arap(0, &off, &w_off);
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
    double cut = number(a, "packing_efficiency_cut");
    cJSON *r = cJSON_GetObjectItem(a, "reduction");
    CHECK(r != NULL && cJSON_IsFalse(cJSON_GetObjectItem(r, "refused")));
    double reduced = number(r, "packing_efficiency_after"), direct = number(r, "packing_efficiency_direct");
    /* the box layout as it is, when its pieces keep the packer's gutter (4) apart */
    int writable = number(r, "direct_gap") >= 4 && number(r, "unboxed_charts") == 0 && direct > reduced;
    reduced = writable ? direct : reduced;
    const char *kept = cJSON_GetObjectItem(a, "kept")->valuestring;
    const char *tightest = reduced > fmax(cut, fmax(before, after)) ? (writable ? "direct" : "reduced")
                           : cut > fmax(before, after)              ? "cut"
                           : after > before                         ? "refined"
                                                                    : "plain";
    CHECK_MSG(strcmp(kept, tightest) == 0, "kept %s with %.4f -> %.4f, cut %.4f, reduced %.4f", kept, before, after,
              cut, reduced);
    /* the reduction (distortion_reduce.h) pulls the cut pieces back toward stage 2's L */
    CHECK_MSG(number(r, "rounds") >= 1 && number(r, "distortion_after") < number(r, "distortion_before"),
              "distortion %.4f -> %.4f in %g rounds", number(r, "distortion_before"), number(r, "distortion_after"),
              number(r, "rounds"));
    CHECK(number(r, "pieces") == 2 && reduced > 0 && reduced <= 1);
    /* both pieces carry a gap layer, and the box layout keeps the packer's gutter (4) between them */
    CHECK_MSG(direct > 0 && direct <= 1 && number(r, "direct_gap") >= 4 && number(r, "charts_without_gap") == 0,
              "direct %.4f, gap %.3f, %g pieces without a layer", direct, number(r, "direct_gap"),
              number(r, "charts_without_gap"));
    CHECK(number(a, "distortion") > 1.0 && number(a, "distortion") <= 1.1);
    CHECK(number(a, "boundary_length_before") > 0 && number(a, "boundary_length_after") > 0);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(d_on, "layout_check"), "passed")));
    CHECK(number(a, "charts_cut") == 1 && number(a, "pieces") == 2 && number(a, "cuts") == 1);
    /* a cut across the L's 6 cells, along mesh edges: about 7 vertices */
    CHECK_MSG(number(a, "vertices_split") >= 6 && number(a, "vertices_split") <= 12, "%g vertices split",
              number(a, "vertices_split"));
    CHECK(number(a, "boundary_length_cut") > number(a, "boundary_length_after"));
    /* two rectangles pack tighter than the refined L (0.82 against 0.69) */
    CHECK_MSG(cut > after + 0.05 && cut <= 1, "cut %.3f", cut);
    CHECK_MSG(fabs(number(d_on, "packing_efficiency") - cut) < 1e-9, "written %.4f, cut %.4f",
              number(d_on, "packing_efficiency"), cut);
    /* the file: the L's 133 grid vertices, the cut's copies, two charts, no overlap */
    CHECK_EQ_INT(w_off.vertices, 133);
    CHECK_EQ_INT(w_off.charts, 1);
    CHECK_EQ_INT(w_on.vertices, 133 + (size_t)number(a, "vertices_split"));
    CHECK_EQ_INT(w_on.charts, 2);
    CHECK_EQ_INT(w_on.overlapping, 0);
    CHECK_EQ_INT(w_on.folded, 0);
    cJSON_Delete(on);
    cJSON_Delete(off);
}
