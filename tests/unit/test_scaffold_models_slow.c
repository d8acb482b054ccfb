/* test_scaffold_models_slow.c - scaffold bijectivity on real models (engine/layout/scaffold.c).
 *
 * Loads tests/data/spot/spot.glb and tests/data/Fox/Fox.glb (or, for scripts/bench.d/scaffold,
 * the colon-separated paths in TEXOPT_SCAFFOLD_MODELS), gives every triangle the random
 * targets of test_meshwise_models_slow (a conflicting field that makes charts run over
 * themselves), solves each domain with and without scaffolds and checks: no flip, and no
 * texel centre covered twice within a scaffolded chart. Prints one line per domain with the
 * overlap counts, times and distortion, which the benchmark script collects. With
 * TEXOPT_SCAFFOLD_FILES (colon-separated) it only prints the overlap counts of each file's
 * own layout (a written output, say). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "distortion.h"
#include "gltf_io.h"
#include "mesh.h"
#include "meshwise.h"
#include "random_targets.h"
#include "scaffold.h"
#include "test.h"

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *base_name(const char *path)
{
    return strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
}

static void solve_domain(const char *path, const texopt_model *model, int domain)
{
    char err[512] = "";
    texopt_mesh *mesh = NULL;
    CHECK_MSG(texopt_mesh_create(&mesh, model, domain, err, sizeof err) == TEXOPT_OK, "%s: %s", path, err);
    texopt_triangle_target *tg = random_targets(mesh->triangle_count, 7);
    double *plain = calloc(2 * mesh->vertex_count, sizeof *plain), *bij = calloc(2 * mesh->vertex_count, sizeof *bij);
    CHECK(tg && plain && bij);
    texopt_meshwise_options opt = {.threads = 1};
    double t0 = seconds_now();
    CHECK_OK(texopt_meshwise_solve(mesh, tg, NULL, &opt, plain, NULL, NULL, err, sizeof err), err);
    double t1 = seconds_now();
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(mesh, tg, NULL, &opt, NULL, bij, &rep, NULL, err, sizeof err), err);
    double t2 = seconds_now();
    CHECK_EQ_INT(texopt_count_flipped(mesh, bij), 0);
    size_t w_in, b_in, w_plain, b_plain, w_bij, b_bij;
    CHECK_OK(texopt_count_overlap(mesh, mesh->texel, &w_in, &b_in, err, sizeof err), err);
    CHECK_OK(texopt_count_overlap(mesh, plain, &w_plain, &b_plain, err, sizeof err), err);
    CHECK_OK(texopt_count_overlap(mesh, bij, &w_bij, &b_bij, err, sizeof err), err);
    texopt_distortion d_plain, d_bij;
    CHECK_OK(texopt_distortion_measure(mesh, plain, &d_plain, err, sizeof err), err);
    CHECK_OK(texopt_distortion_measure(mesh, bij, &d_bij, err, sizeof err), err);
    printf("scaffold %s domain %d: %zu faces %zu charts (%zu scaffolded, %zu skipped), %d rounds: "
           "texel centres twice within a chart input %zu / plain %zu / bijective %zu; "
           "seconds plain %.2f / bijective %.2f; symmetric Dirichlet plain %.4f / bijective %.4f\n",
           base_name(path), domain, mesh->triangle_count, mesh->chart_count, rep.charts_scaffolded, rep.charts_skipped,
           rep.rounds, w_in, w_plain, w_bij, t1 - t0, t2 - t1, d_plain.symmetric_dirichlet, d_bij.symmetric_dirichlet);
    fflush(stdout);
    if (rep.charts_skipped == 0)
        CHECK_EQ_INT(w_bij, 0);
    free(plain);
    free(bij);
    free(tg);
    texopt_mesh_destroy(mesh);
}

static void for_each_domain(const char *path, void (*fn)(const char *, const texopt_model *, int))
{
    char err[512] = "";
    texopt_model *model = NULL;
    texopt_load_options opt = {.skip_images = 1};
    CHECK_MSG(texopt_model_load(&model, path, &opt, err, sizeof err) == TEXOPT_OK, "%s: %s", path, err);
    for (int d = 0; d < model->domain_count; d++) {
        int failed_before = test_failed_now();
        fn(path, model, d);
        if (test_failed_now() && !failed_before)
            break;
    }
    texopt_model_destroy(model);
}

static void own_overlap(const char *path, const texopt_model *model, int domain)
{
    char err[512] = "";
    texopt_mesh *mesh = NULL;
    CHECK_MSG(texopt_mesh_create(&mesh, model, domain, err, sizeof err) == TEXOPT_OK, "%s: %s", path, err);
    size_t within, between;
    CHECK_OK(texopt_count_overlap(mesh, mesh->texel, &within, &between, err, sizeof err), err);
    printf("overlap %s domain %d: %d x %d, texel centres twice within a chart %zu, between charts %zu\n",
           base_name(path), domain, mesh->width, mesh->height, within, between);
    fflush(stdout);
    texopt_mesh_destroy(mesh);
}

static void for_each_path(const char *list, void (*fn)(const char *, const texopt_model *, int))
{
    char *copy = strdup(list);
    for (char *save = NULL, *p = strtok_r(copy, ":", &save); p; p = strtok_r(NULL, ":", &save))
        for_each_domain(p, fn);
    free(copy);
}

TEST(real_models_stay_bijective_with_scaffolds)
{
    const char *files = getenv("TEXOPT_SCAFFOLD_FILES");
    if (files && *files)
        return;
    const char *list = getenv("TEXOPT_SCAFFOLD_MODELS");
    if (!list || !*list) {
        for_each_domain(TEXOPT_TEST_DATA_DIR "/spot/spot.glb", solve_domain);
        for_each_domain(TEXOPT_TEST_DATA_DIR "/Fox/Fox.glb", solve_domain);
        return;
    }
    for_each_path(list, solve_domain);
}

TEST(written_files_overlap)
{
    const char *files = getenv("TEXOPT_SCAFFOLD_FILES");
    if (files && *files)
        for_each_path(files, own_overlap);
}
