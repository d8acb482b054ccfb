/* test_param_square_models_slow.c - the square parameterization's corner searches compared
 * as in Dechvijankit et al. 2013 (stretch, parameterizations run and time of brute force,
 * step sampling and particle swarm), on the largest disk chart of each model and on a
 * generated curved grid (charts with ears are skipped: the paper assumes none). Models: tests/data/spot/spot.glb, or (for scripts/bench.d/
 * param_square) the colon-separated paths in TEXOPT_PARAM_MODELS. Prints one "square" line
 * per chart and search and checks what must hold: no search beats brute force, which tries
 * every candidate, and none evaluates more candidates than there are. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gltf_io.h"
#include "mesh.h"
#include "param_grids.h"
#include "param_square.h"
#include "test.h"

enum { MIN_TRIANGLES = 200, MAX_TRIANGLES = 4000, PSO_SEEDS = 10 };

typedef struct chart_copy {
    texopt_param_chart chart;
    double *position;
    uint32_t *triangle;
} chart_copy;

static void chart_copy_free(chart_copy *c)
{
    free(c->position);
    free(c->triangle);
    memset(c, 0, sizeof *c);
}

/* Whether a triangle has all three vertices on the boundary (an ear): the paper's method
 * assumes charts without, so its comparison runs on those. */
static int has_ears(const texopt_param_chart *chart, const texopt_param_boundary *b)
{
    for (size_t t = 0; t < chart->triangle_count; t++) {
        const uint32_t *v = chart->triangle + 3 * t;
        if (b->on_boundary[v[0]] && b->on_boundary[v[1]] && b->on_boundary[v[2]])
            return 1;
    }
    return 0;
}
/* Chart `chart` of `mesh` with its own vertex numbering; 0 when it is a disk of a useful size. */
static int extract_chart(const texopt_mesh *mesh, uint32_t chart, chart_copy *out)
{
    size_t nt = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (mesh->chart_of[t] != chart)
            continue;
        if (mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV))
            return -1;
        nt++;
    }
    if (nt < MIN_TRIANGLES || nt > MAX_TRIANGLES)
        return -1;
    uint32_t *local = malloc(mesh->vertex_count * sizeof *local);
    out->triangle = malloc(3 * nt * sizeof *out->triangle);
    out->position = malloc(3 * 3 * nt * sizeof *out->position);
    size_t nv = 0, k = 0;
    for (size_t v = 0; v < mesh->vertex_count; v++)
        local[v] = UINT32_MAX;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (mesh->chart_of[t] != chart)
            continue;
        for (int c = 0; c < 3; c++) {
            uint32_t v = mesh->triangle[3 * t + c];
            if (local[v] == UINT32_MAX) {
                memcpy(out->position + 3 * nv, texopt_mesh_vertex_point(mesh, v), 3 * sizeof(double));
                local[v] = (uint32_t)nv++;
            }
            out->triangle[k++] = local[v];
        }
    }
    free(local);
    out->chart = (texopt_param_chart){nv, out->position, nt, out->triangle};
    char err[256];
    texopt_param_boundary *b = NULL;
    if (texopt_param_boundary_create(&b, &out->chart, err, sizeof err) != TEXOPT_OK || b->count < 8 ||
        has_ears(&out->chart, b)) {
        texopt_param_boundary_destroy(b);
        chart_copy_free(out);
        return -1;
    }
    texopt_param_boundary_destroy(b);
    return 0;
}

static double cpu_seconds(clock_t since)
{
    return (double)(clock() - since) / CLOCKS_PER_SEC;
}

static void compare_searches(const char *name, const texopt_param_chart *chart)
{
    double *uv = malloc(2 * chart->vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    texopt_square_report brute, step, pso;
    p.search = TEXOPT_SQUARE_BRUTE_FORCE;
    clock_t t0 = clock();
    CHECK_OK(texopt_param_square(chart, &p, uv, &brute, err, sizeof err), err);
    double brute_s = cpu_seconds(t0);
    printf("square %s triangles %zu candidates %zu brute_force l2 %.6f evaluations %zu cpu_s %.3f\n", name,
           chart->triangle_count, brute.candidates, brute.l2_stretch, brute.evaluations, brute_s);
    p.search = TEXOPT_SQUARE_STEP_SAMPLING;
    t0 = clock();
    CHECK_OK(texopt_param_square(chart, &p, uv, &step, err, sizeof err), err);
    printf("square %s triangles %zu candidates %zu step_sampling l2 %.6f evaluations %zu cpu_s %.3f optimum %s\n", name,
           chart->triangle_count, step.candidates, step.l2_stretch, step.evaluations, cpu_seconds(t0),
           step.corner == brute.corner ? "same" : "other");
    CHECK(step.l2_stretch >= brute.l2_stretch - 1e-12 && step.evaluations <= step.candidates);
    double l2 = 0.0, evaluations = 0.0, seconds = 0.0;
    int found = 0;
    p.search = TEXOPT_SQUARE_PSO;
    for (int seed = 1; seed <= PSO_SEEDS; seed++) {
        p.seed = (uint64_t)seed;
        t0 = clock();
        CHECK_OK(texopt_param_square(chart, &p, uv, &pso, err, sizeof err), err);
        seconds += cpu_seconds(t0) / PSO_SEEDS;
        l2 += pso.l2_stretch / PSO_SEEDS;
        evaluations += (double)pso.evaluations / PSO_SEEDS;
        found += pso.corner == brute.corner;
        CHECK(pso.l2_stretch >= brute.l2_stretch - 1e-12 && pso.evaluations <= pso.candidates);
    }
    printf("square %s triangles %zu candidates %zu pso l2 %.6f evaluations %.1f cpu_s %.3f optimum %d/%d "
           "(means over seeds)\n",
           name, chart->triangle_count, brute.candidates, l2, evaluations, seconds, found, PSO_SEEDS);
    free(uv);
}

static void compare_on_model(const char *path)
{
    char err[512] = "";
    texopt_model *model = NULL;
    texopt_load_options opt = {.skip_images = 1};
    CHECK_MSG(texopt_model_load(&model, path, &opt, err, sizeof err) == TEXOPT_OK, "%s: %s", path, err);
    chart_copy best = {0};
    for (int d = 0; d < model->domain_count; d++) {
        texopt_mesh *mesh = NULL;
        if (texopt_mesh_create(&mesh, model, d, err, sizeof err) != TEXOPT_OK)
            continue;
        for (uint32_t c = 0; c < mesh->chart_count; c++) {
            chart_copy copy = {0};
            if (extract_chart(mesh, c, &copy) != 0)
                continue;
            if (copy.chart.triangle_count > best.chart.triangle_count) {
                chart_copy_free(&best);
                best = copy;
            } else {
                chart_copy_free(&copy);
            }
        }
        texopt_mesh_destroy(mesh);
    }
    texopt_model_destroy(model);
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    if (best.chart.triangle_count == 0)
        printf("square %s: no disk chart without ears of %d to %d triangles\n", name, MIN_TRIANGLES, MAX_TRIANGLES);
    else
        compare_searches(name, &best.chart);
    chart_copy_free(&best);
}

TEST(largest_disk_charts_of_models)
{
    const char *list = getenv("TEXOPT_PARAM_MODELS");
    if (!list || !*list) {
        compare_on_model(TEXOPT_TEST_DATA_DIR "/spot/spot.glb");
        return;
    }
    char *copy = strdup(list);
    CHECK(copy);
    for (char *save = NULL, *p = strtok_r(copy, ":", &save); p; p = strtok_r(NULL, ":", &save))
        compare_on_model(p);
    free(copy);
}

TEST(generated_curved_grid)
{
    param_grid *g = param_grid_create(24, SHAPE_BUMP, 11);
    compare_searches("bump_grid_24", &g->chart);
    param_grid_destroy(g);
}
