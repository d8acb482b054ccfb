/* test_param_square.c - square parameterization and its corner searches
 * (engine/param/param_square.c) on generated grids. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

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
    /* One triangle: a boundary of three vertices cannot go onto four corners. */
    static const double corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t one[3] = {0, 1, 2};
    texopt_param_chart single = {3, corners, 1, one};
    CHECK_EQ_INT(texopt_param_square(&single, &p, uv, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    free(uv);
    param_grid_destroy(g);
}

/* Smallest |signed area| over the chart's triangles in uv, times the sign agreement: negative
 * when two triangles disagree in orientation. */
static double least_signed_area(const texopt_param_chart *c, const double *uv)
{
    double least = INFINITY, first = 0;
    for (size_t t = 0; t < c->triangle_count; t++) {
        const double *a = uv + 2 * (size_t)c->triangle[3 * t], *b = uv + 2 * (size_t)c->triangle[3 * t + 1],
                     *d = uv + 2 * (size_t)c->triangle[3 * t + 2];
        double area = 0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]));
        if (t == 0)
            first = area;
        least = fmin(least, area * (first > 0 ? 1 : -1));
    }
    return least;
}

TEST(ears_at_corners_are_laid_out_without_flattening)
{
    /* The 4 x 4 grid with its four corner quads cut the other way: each corner is the apex of
     * an ear, whose base joins two points of the boundary. Only the placements with those
     * apexes at the square's corners keep the ears open (Floater's condition). */
    param_grid *g = param_grid_create(4, SHAPE_TILTED_PLANE, 0);
    uint32_t *tris = malloc(3 * g->chart.triangle_count * sizeof *tris);
    for (size_t i = 0; i < 3 * g->chart.triangle_count; i++)
        tris[i] = g->chart.triangle[i];
    static const size_t quads[4] = {0, 3, 12, 15}; /* quad (i, j) = 4 j + i: the corners */
    for (int q = 0; q < 4; q++) {
        size_t i = quads[q] % 4, j = quads[q] / 4;
        uint32_t a = (uint32_t)(5 * j + i), b = a + 1, c = a + 6, d = a + 5;
        uint32_t bd[6] = {a, b, d, b, c, d}, ac[6] = {a, b, c, a, c, d}; /* the diagonal away from the corner */
        for (int k = 0; k < 6; k++)
            tris[6 * quads[q] + (size_t)k] = i == j ? bd[k] : ac[k];
    }
    texopt_param_chart eared = g->chart;
    eared.triangle = tris;
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    for (int search = TEXOPT_SQUARE_BRUTE_FORCE; search <= TEXOPT_SQUARE_PSO; search++) {
        p.search = (texopt_square_search)search;
        texopt_square_report rep;
        CHECK_OK(texopt_param_square(&eared, &p, uv, &rep, err, sizeof err), err);
        CHECK(least_signed_area(&eared, uv) > 1e-3);
    }
    free(uv);
    free(tris);
    param_grid_destroy(g);
}

TEST(a_strip_one_quad_wide_is_refused)
{
    /* Two rows of 9 points: every vertex is on the boundary and each rung and diagonal joins
     * the rows, so any four corners leave some of them on one side. */
    double pos[2 * 9 * 3];
    uint32_t tri[8 * 6];
    for (uint32_t k = 0; k < 9; k++)
        for (uint32_t r = 0; r < 2; r++) {
            pos[3 * (2 * k + r)] = k;
            pos[3 * (2 * k + r) + 1] = r;
            pos[3 * (2 * k + r) + 2] = 0;
        }
    for (uint32_t k = 0; k < 8; k++) {
        uint32_t a = 2 * k, b = 2 * k + 2, c = 2 * k + 3, d = 2 * k + 1, quad[6] = {a, b, c, a, c, d};
        for (int i = 0; i < 6; i++)
            tri[6 * k + (uint32_t)i] = quad[i];
    }
    texopt_param_chart strip = {18, pos, 16, tri};
    double uv[36];
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    CHECK_EQ_INT(texopt_param_square(&strip, &p, uv, NULL, err, sizeof err), TEXOPT_E_UNSUPPORTED);
    CHECK(strstr(err, "interior edge") != NULL);
}
