/* test_param_square.c - square parameterization and its corner searches
 * (engine/param/param_square.c) on generated grids. */
#include <math.h>
#include <stdlib.h>

#include "param_grids.h"
#include "param_square.h"
#include "test.h"

/* The grid is the unit square itself: with a true corner at P00 the map is the identity up
 * to a quarter turn (stretch exactly 1). The loop starts at grid point (3, 0) (vertex 0
 * after the shift), so the corner (8, 0) is candidate 5 of the first quarter's 8. */
static void check_identity(texopt_square_search search)
{
    param_grid *g = param_grid_create(8, SHAPE_TILTED_PLANE, 3);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    p.search = search;
    texopt_square_report rep;
    CHECK_OK(texopt_param_square(&g->chart, &p, uv, &rep, err, sizeof err), err);
    CHECK_EQ_INT(rep.candidates, 8);
    CHECK_EQ_INT(rep.corner, 5);
    CHECK_NEAR(rep.l2_stretch, 1.0, 1e-9);
    CHECK_NEAR(rep.linf_stretch, 1.0, 1e-6); /* normal equations: ~1e-8 */
    double scale;
    CHECK(param_similarity_residual(g, uv, &scale) < 1e-9);
    CHECK_NEAR(scale, 1.0, 1e-9);
    for (size_t v = 0; v < 2 * g->chart.vertex_count; v++)
        CHECK(uv[v] > -1e-12 && uv[v] < 1.0 + 1e-12);
    if (search == TEXOPT_SQUARE_BRUTE_FORCE)
        CHECK_EQ_INT(rep.evaluations, 8);
    else
        CHECK(rep.evaluations < 8);
    free(uv);
    param_grid_destroy(g);
}

TEST(square_patch_brute_force_finds_the_corner)
{
    check_identity(TEXOPT_SQUARE_BRUTE_FORCE);
}

TEST(square_patch_step_sampling_finds_the_corner)
{
    check_identity(TEXOPT_SQUARE_STEP_SAMPLING);
}

TEST(square_patch_particle_swarm_finds_the_corner)
{
    check_identity(TEXOPT_SQUARE_PSO);
}

/* On a curved patch no corner gives stretch 1; the searches agree with brute force or come
 * close, and the stretch-minimising rounds beat the plain mean-value map. */
TEST(curved_patch_searches_compare_with_brute_force)
{
    param_grid *g = param_grid_create(10, SHAPE_BUMP, 7);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    texopt_square_report brute, step, plain;
    p.search = TEXOPT_SQUARE_BRUTE_FORCE;
    CHECK_OK(texopt_param_square(&g->chart, &p, uv, &brute, err, sizeof err), err);
    CHECK(brute.l2_stretch > 1.01);
    CHECK_EQ_INT(param_layout_flips(&g->chart, uv), 0);
    p.search = TEXOPT_SQUARE_STEP_SAMPLING;
    CHECK_OK(texopt_param_square(&g->chart, &p, uv, &step, err, sizeof err), err);
    CHECK(step.l2_stretch >= brute.l2_stretch - 1e-12);
    CHECK(step.l2_stretch < 1.02 * brute.l2_stretch);
    p.search = TEXOPT_SQUARE_BRUTE_FORCE;
    p.stretch_rounds = 0;
    CHECK_OK(texopt_param_square(&g->chart, &p, uv, &plain, err, sizeof err), err);
    CHECK(plain.l2_stretch > brute.l2_stretch);
    free(uv);
    param_grid_destroy(g);
}

TEST(bad_parameters_are_refused)
{
    param_grid *g = param_grid_create(3, SHAPE_TILTED_PLANE, 0);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    p.particles = 0;
    CHECK_EQ_INT(texopt_param_square(&g->chart, &p, uv, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    texopt_square_params_default(&p);
    p.search = (texopt_square_search)7;
    CHECK_EQ_INT(texopt_param_square(&g->chart, &p, uv, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    /* The grid with its two corner quads cut the other way: those corners are ears. */
    uint32_t *tris = malloc(3 * g->chart.triangle_count * sizeof *tris);
    for (size_t i = 0; i < 3 * g->chart.triangle_count; i++)
        tris[i] = g->chart.triangle[i];
    size_t corner_quad = 2; /* (n - 1, 0) of the 3 x 3 grid: a b c d = 2 3 7 6 */
    uint32_t a = 2, b = 3, c = 7, d = 6, quad[6] = {a, b, c, a, c, d};
    for (int k = 0; k < 6; k++)
        tris[6 * corner_quad + (size_t)k] = quad[k];
    texopt_param_chart eared = g->chart;
    eared.triangle = tris;
    texopt_square_params_default(&p);
    CHECK_EQ_INT(texopt_param_square(&eared, &p, uv, NULL, err, sizeof err), TEXOPT_E_UNSUPPORTED);
    free(tris);
    /* One triangle: a boundary of three vertices cannot go onto four corners. */
    static const double corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t one[3] = {0, 1, 2};
    texopt_param_chart single = {3, corners, 1, one};
    CHECK_EQ_INT(texopt_param_square(&single, &p, uv, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    free(uv);
    param_grid_destroy(g);
}
