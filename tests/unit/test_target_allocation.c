/* test_target_allocation.c - water-filling of per-triangle targets to a texel budget (target_allocation.c), on
 * the meshes of generated grids: the allocated area meets the request, no singular value
 * passes input density, uncapped targets keep their ratios, lossless targets can grow slower,
 * the targets' area counts what each triangle pays, and bad input is refused; the
 * closed-loop reallocation moves area to the triangles with on-screen error, within its step
 * and cap. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "mesh.h"
#include "target_allocation.h"
#include "test.h"

/* Targets with varied sizes: triangle t gets lambdas from a small table, anisotropic. */
static void varied_targets(const texopt_mesh *mesh, texopt_triangle_target *t)
{
    static const double l1[4] = {0.1, 0.2, 0.5, 0.9}, l2[4] = {0.1, 0.4, 0.3, 0.8};
    for (size_t i = 0; i < mesh->triangle_count; i++) {
        t[i] = (texopt_triangle_target){0};
        t[i].lambda1 = l1[i % 4];
        t[i].lambda2 = l2[(i / 4) % 4];
        t[i].alpha = 0.3;
        t[i].beta = 0.1 * (double)(i % 5);
        t[i].loss = i % 3 == 0 ? 0 : 0.005;
        t[i].w_stretch = 1;
    }
}

/* The mesh of a 4 x 4 grid on a 64^2 texture (32 triangles of 32 texels each), varied
 * targets `in` on it and a zeroed array `out` of as many. */
typedef struct grid_case {
    texopt_model *model;
    texopt_mesh *mesh;
    size_t n;
    texopt_triangle_target *in, *out;
} grid_case;

static int grid_case_open(grid_case *g)
{
    memset(g, 0, sizeof *g);
    char err[256];
    g->model = fixture_grid(4, 64, "flat");
    if (!g->model || texopt_mesh_create(&g->mesh, g->model, 0, err, sizeof err) != TEXOPT_OK)
        return -1;
    g->n = g->mesh->triangle_count;
    g->in = calloc(g->n, sizeof *g->in);
    g->out = calloc(g->n, sizeof *g->out);
    if (!g->in || !g->out)
        return -1;
    varied_targets(g->mesh, g->in);
    return 0;
}

static void grid_case_close(grid_case *g)
{
    free(g->in);
    free(g->out);
    texopt_mesh_destroy(g->mesh);
    texopt_model_destroy(g->model);
}

static double total_area(const texopt_mesh *mesh, const texopt_triangle_target *t)
{
    double a = 0;
    for (size_t i = 0; i < mesh->triangle_count; i++)
        a += fabs(mesh->area_texel[i]) * t[i].lambda1 * t[i].lambda2;
    return a;
}

TEST(allocation_meets_the_request_and_caps_at_input_density)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    texopt_mesh *mesh = g.mesh;
    size_t n = g.n;
    texopt_triangle_target *in = g.in, *out = g.out;
    double input_area = 64.0 * 64.0;
    char err[256] = "";
    texopt_allocation rep;
    /* Half the input: far more than the targets' own area, so some singular values cap. */
    CHECK_OK(texopt_allocate_targets(mesh, in, 0.5 * input_area, NULL, out, &rep, err, sizeof err), err);
    CHECK_NEAR(total_area(mesh, out), 0.5 * input_area, 1e-6 * input_area);
    CHECK_NEAR(rep.area_allocated, 0.5 * input_area, 1e-6 * input_area);
    CHECK_NEAR(rep.area_input, input_area, 1e-9);
    CHECK(rep.capped > 0 && rep.capped < n);
    CHECK(rep.scale > 1);
    for (size_t i = 0; i < n; i++) {
        CHECK(out[i].lambda1 <= 1 && out[i].lambda2 <= 1);
        /* Each value is the common factor times the input, or the cap. */
        CHECK(fabs(out[i].lambda1 - rep.scale * in[i].lambda1) < 1e-12 || out[i].lambda1 == 1);
        CHECK(fabs(out[i].lambda2 - rep.scale * in[i].lambda2) < 1e-12 || out[i].lambda2 == 1);
        CHECK(out[i].alpha == in[i].alpha && out[i].beta == in[i].beta && out[i].w_stretch == in[i].w_stretch);
    }
    grid_case_close(&g);
}

TEST(small_request_scales_every_target_by_one_factor)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    texopt_mesh *mesh = g.mesh;
    size_t n = g.n;
    texopt_triangle_target *in = g.in, *out = g.out;
    double own = total_area(mesh, in);
    char err[256] = "";
    texopt_allocation rep;
    CHECK_OK(texopt_allocate_targets(mesh, in, 0.25 * own, NULL, out, &rep, err, sizeof err), err);
    CHECK_NEAR(rep.scale, 0.5, 1e-9); /* area goes as the square of the factor */
    CHECK_EQ_INT((int)rep.capped, 0);
    for (size_t i = 0; i < n; i++)
        CHECK_NEAR(out[i].lambda1 / in[i].lambda1, 0.5, 1e-9);
    grid_case_close(&g);
}

TEST(request_past_the_input_area_gives_input_density_everywhere)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    size_t n = g.n;
    texopt_triangle_target *t = g.in;
    char err[256] = "";
    texopt_allocation rep;
    /* In place (out == in) and more than the caps allow: every value at 1. */
    CHECK_OK(texopt_allocate_targets(g.mesh, t, 2 * 64.0 * 64.0, NULL, t, &rep, err, sizeof err), err);
    for (size_t i = 0; i < n; i++)
        CHECK(t[i].lambda1 == 1 && t[i].lambda2 == 1);
    CHECK_EQ_INT((int)rep.capped, (int)n);
    CHECK_NEAR(rep.area_allocated, 64.0 * 64.0, 1e-9);
    grid_case_close(&g);
}

/* Triangles on texels others pay for (paid 0: a fold's minority side, a sharing group's
 * secondaries) cost nothing but scale with the rest: a request of a quarter of the paying
 * targets' own area halves every target, the free ones too. */
TEST(triangles_that_pay_nothing_cost_nothing_but_scale_alike)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    double *paid = malloc(g.n * sizeof *paid), own = 0;
    for (size_t i = 0; i < g.n; i++) {
        paid[i] = i % 2 ? 0.0 : 1.0;
        own += paid[i] * fabs(g.mesh->area_texel[i]) * g.in[i].lambda1 * g.in[i].lambda2;
    }
    texopt_allocate_options opt = {.paid = paid};
    char err[256] = "";
    texopt_allocation rep;
    CHECK_OK(texopt_allocate_targets(g.mesh, g.in, 0.25 * own, &opt, g.out, &rep, err, sizeof err), err);
    CHECK_NEAR(rep.scale, 0.5, 1e-9);
    CHECK_NEAR(rep.area_allocated, 0.25 * own, 1e-9 * own);
    for (size_t i = 0; i < g.n; i++)
        CHECK_NEAR(g.out[i].lambda1 / g.in[i].lambda1, 0.5, 1e-9);
    /* Without the shares the same request is spread over twice the area: smaller targets. */
    CHECK_OK(texopt_allocate_targets(g.mesh, g.in, 0.25 * own, NULL, g.out, &rep, err, sizeof err), err);
    CHECK(rep.scale < 0.45);
    /* The targets' area as the allocation counts it: with the shares, and without. */
    CHECK_NEAR(texopt_targets_area(g.mesh, g.in, paid), own, 1e-9 * own);
    CHECK_NEAR(texopt_targets_area(g.mesh, g.in, NULL), total_area(g.mesh, g.in), 1e-9 * own);
    paid[5] = 1.5;
    CHECK(texopt_allocate_targets(g.mesh, g.in, 0.25 * own, &opt, g.out, &rep, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle 5") != NULL);
    free(paid);
    grid_case_close(&g);
}

TEST(lossless_targets_grow_slower_and_the_rest_take_the_budget)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    texopt_mesh *mesh = g.mesh;
    size_t n = g.n;
    texopt_triangle_target *in = g.in, *plain = g.out, *kept = calloc(n, sizeof *kept);
    double request = 0.3 * 64.0 * 64.0;
    char err[256] = "";
    texopt_allocation rp, rk;
    texopt_allocate_options keep = {1, 1e-6, 0, 0, NULL};
    CHECK_OK(texopt_allocate_targets(mesh, in, request, NULL, plain, &rp, err, sizeof err), err);
    CHECK_OK(texopt_allocate_targets(mesh, in, request, &keep, kept, &rk, err, sizeof err), err);
    CHECK_NEAR(rk.area_allocated, request, 1e-6 * request);
    CHECK(rk.scale > rp.scale); /* the others get what the lossless ones did not take */
    size_t lossless = 0;
    for (size_t i = 0; i < n; i++) {
        if (in[i].loss == 0) {
            lossless++;
            CHECK(kept[i].lambda1 == in[i].lambda1 && kept[i].lambda2 == in[i].lambda2);
        } else {
            CHECK(kept[i].lambda1 * kept[i].lambda2 >= plain[i].lambda1 * plain[i].lambda2 - 1e-12);
        }
    }
    CHECK_EQ_INT((int)rk.lossless, (int)lossless);
    /* A request below what the kept targets take on their own: everything scales. */
    double tiny = 0.1 * total_area(mesh, in);
    CHECK_OK(texopt_allocate_targets(mesh, in, tiny, &keep, kept, &rk, err, sizeof err), err);
    CHECK_EQ_INT((int)rk.lossless, 0);
    CHECK_NEAR(rk.area_allocated, tiny, 1e-6 * tiny);
    /* Growth 0.5: lossless targets scale by sqrt(s), the others by s. */
    texopt_allocate_options half = {1, 1e-6, 0, 0.5, NULL};
    CHECK_OK(texopt_allocate_targets(mesh, in, request, &half, kept, &rk, err, sizeof err), err);
    CHECK_NEAR(rk.area_allocated, request, 1e-6 * request);
    for (size_t i = 0; i < n; i++)
        if (in[i].loss == 0 && kept[i].lambda1 < 1)
            CHECK_NEAR(kept[i].lambda1, sqrt(rk.scale) * in[i].lambda1, 1e-12);
        else if (kept[i].lambda1 < 1)
            CHECK_NEAR(kept[i].lambda1, rk.scale * in[i].lambda1, 1e-12);
    free(kept);
    grid_case_close(&g);
}

TEST(bad_targets_and_requests_are_refused)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    texopt_mesh *mesh = g.mesh;
    texopt_triangle_target *t = g.in, *out = g.out;
    char err[256] = "";
    CHECK(texopt_allocate_targets(mesh, t, 0, NULL, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_allocate_targets(mesh, t, NAN, NULL, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    t[3].lambda2 = -0.5;
    CHECK(texopt_allocate_targets(mesh, t, 100, NULL, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle 3") != NULL);
    CHECK(texopt_allocate_targets(NULL, t, 100, NULL, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    grid_case_close(&g);
}

static double target_area(const texopt_mesh *mesh, const texopt_triangle_target *t, size_t i)
{
    return fabs(mesh->area_texel[i]) * t[i].lambda1 * t[i].lambda2;
}

TEST(reallocation_moves_texels_to_the_triangles_shown_wrong)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    texopt_mesh *mesh = g.mesh;
    size_t n = g.n;
    double *error = calloc(n, sizeof *error), request = 0.3 * 64.0 * 64.0;
    texopt_triangle_target *before = calloc(n, sizeof *before);
    for (size_t i = 0; i < n / 2; i++)
        error[i] = 1; /* the first half is shown wrong, the rest exactly */
    texopt_reallocate_options opt = {0.5, 0.5, 2.0, 2.0, NULL};
    char err[256] = "";
    texopt_allocation rep;
    texopt_allocate_options same_cap = {0, 0, 2.0, 0, NULL};
    CHECK_OK(texopt_allocate_targets(mesh, g.in, request, &same_cap, before, NULL, err, sizeof err), err);
    CHECK_OK(texopt_reallocate_by_error(mesh, g.in, error, request, &opt, g.out, &rep, err, sizeof err), err);
    CHECK_NEAR(total_area(mesh, g.out), request, 1e-6 * request);
    double wrong_before = 0, wrong_after = 0;
    for (size_t i = 0; i < n / 2; i++) {
        wrong_before += target_area(mesh, before, i);
        wrong_after += target_area(mesh, g.out, i);
    }
    CHECK(wrong_after > 1.2 * wrong_before);
    /* Equal 3D areas: mean error 0.5, floor 0.025; the step is (1.025 / 0.525)^0.5 on the
     * wrong half and (0.025 / 0.525)^0.5, clamped to 0.5, on the rest, times one common
     * factor. Anisotropy, angles and weights stay; nothing passes the cap. */
    double up = sqrt(1.025 / 0.525), down = 0.5;
    for (size_t i = 0; i < n; i++) {
        CHECK(g.out[i].lambda1 <= 2 && g.out[i].lambda2 <= 2);
        CHECK(g.out[i].alpha == g.in[i].alpha && g.out[i].beta == g.in[i].beta);
        CHECK(g.out[i].w_stretch == g.in[i].w_stretch);
        if (g.out[i].lambda1 < 2 && g.out[i].lambda2 < 2) {
            CHECK_NEAR(g.out[i].lambda1 / g.out[i].lambda2, g.in[i].lambda1 / g.in[i].lambda2, 1e-9);
            double step = target_area(mesh, g.out, i) / target_area(mesh, g.in, i);
            CHECK_NEAR(step, rep.scale * rep.scale * (i < n / 2 ? up : down), 1e-9 * step);
        }
    }
    /* No error anywhere: the targets are only rescaled. */
    memset(error, 0, n * sizeof *error);
    CHECK_OK(texopt_reallocate_by_error(mesh, g.in, error, request, &opt, g.out, NULL, err, sizeof err), err);
    for (size_t i = 0; i < n; i++)
        CHECK(g.out[i].lambda1 == before[i].lambda1 && g.out[i].lambda2 == before[i].lambda2);
    free(error);
    free(before);
    grid_case_close(&g);
}

TEST(reallocation_refuses_bad_errors_and_steps)
{
    grid_case g;
    CHECK(grid_case_open(&g) == 0);
    double *error = calloc(g.n, sizeof *error);
    texopt_reallocate_options opt = {0.5, 0.5, 2.0, 2.0, NULL}, bad = opt;
    char err[256] = "";
    error[5] = -1;
    CHECK(texopt_reallocate_by_error(g.mesh, g.in, error, 100, &opt, g.out, NULL, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle 5") != NULL);
    error[5] = NAN;
    CHECK(texopt_reallocate_by_error(g.mesh, g.in, error, 100, &opt, g.out, NULL, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    error[5] = 0;
    bad.step_min = 1.5;
    CHECK(texopt_reallocate_by_error(g.mesh, g.in, error, 100, &bad, g.out, NULL, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_reallocate_by_error(g.mesh, g.in, error, 100, NULL, g.out, NULL, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_reallocate_by_error(g.mesh, g.in, NULL, 100, &opt, g.out, NULL, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    free(error);
    grid_case_close(&g);
}
