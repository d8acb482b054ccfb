/* Scale test of mesh.c and coverage.c: a million-triangle grid on a 4096^2 frame. Prints the
 * times scripts/bench.d/mesh reports; fails when either step loses its linear behaviour. */
#include <time.h>

#include "coverage.h"
#include "fixtures.h"
#include "mesh.h"
#include "test.h"

static double seconds_since(const struct timespec *t0)
{
    struct timespec t1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    return (double)(t1.tv_sec - t0->tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0->tv_nsec);
}

TEST(million_triangles_on_a_4096_frame)
{
    texopt_model *model = fixture_grid(708, 8, "flat"); /* 2 * 708^2 = 1,002,528 triangles */
    CHECK(model != NULL);
    /* The frame is the largest image's size; the pixels are not read. */
    model->images[0].width = model->images[0].height = 4096;
    char err[256] = "";
    CHECK_OK(texopt_model_build_domains(model, err, sizeof err), err);
    model->images[0].width = model->images[0].height = 8;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    texopt_mesh *m = NULL;
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    double build = seconds_since(&t0);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    texopt_coverage cov;
    texopt_coverage_options opt = {.triangle_flags = m->flags};
    CHECK_OK(texopt_coverage_measure(m, &opt, &cov, err, sizeof err), err);
    double cover = seconds_since(&t0);
    printf("mesh %zu triangles %zu vertices: mesh_create %.3f s, coverage 4096^2 %.3f s\n", m->triangle_count,
           m->vertex_count, build, cover);
    CHECK_EQ_INT(m->triangle_count, 1002528);
    CHECK_EQ_INT(m->chart_count, 1);
    CHECK_EQ_INT(cov.covered_texels, 4096ull * 4096ull);
    CHECK_EQ_INT(cov.overlap_texels, 0);
    CHECK(build < 5.0);
    CHECK(cover < 5.0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}
