/* test_param_ears.c - ears peeled for the square method and put back
 * (engine/param/param_ears.c) on a generated grid with ears added along its bottom side. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "param_ears.h"
#include "param_grids.h"
#include "param_square.h"
#include "test.h"

enum { N = 4 };

static texopt_status square_layout(const texopt_param_chart *chart, void *params, double *uv, char *err, size_t err_len)
{
    return texopt_param_square(chart, params, uv, NULL, err, err_len);
}

/* The 4 x 4 grid (a tilted plane, every corner in two triangles) with three triangles added
 * below its bottom side: one ear on grid edge (1, 0)-(2, 0), and on edge (2, 0)-(3, 0) an
 * ear carrying a second ear on its outer edge (only peelable once the second is off).
 * Apexes in the plane's coordinates (x, y), y < 0 outside the grid. */
typedef struct eared_grid {
    param_grid *grid;
    texopt_param_chart chart;
    double *position;
    uint32_t *triangle;
} eared_grid;

static void put_point(const param_grid *g, double x, double y, double *out)
{
    /* The tilted plane is affine in (x, y) and its boundary is not jittered: the corner and
     * its two neighbours span it. */
    uint32_t v00 = 0, v10 = 1, v01 = N + 1; /* shift 0: grid point (i, j) is vertex j (N + 1) + i */
    const double *o = g->position + 3 * (size_t)v00;
    const double *px = g->position + 3 * (size_t)v10, *py = g->position + 3 * (size_t)v01;
    for (int d = 0; d < 3; d++)
        out[d] = o[d] + N * (x * (px[d] - o[d]) + y * (py[d] - o[d]));
}

static eared_grid *eared_grid_create(void)
{
    eared_grid *e = calloc(1, sizeof *e);
    e->grid = param_grid_create(N, SHAPE_TILTED_PLANE, 0);
    const texopt_param_chart *c = &e->grid->chart;
    size_t nv = c->vertex_count, nt = c->triangle_count;
    e->position = malloc(3 * (nv + 3) * sizeof *e->position);
    e->triangle = malloc(3 * (nt + 3) * sizeof *e->triangle);
    memcpy(e->position, c->position, 3 * nv * sizeof *e->position);
    memcpy(e->triangle, c->triangle, 3 * nt * sizeof *e->triangle);
    /* Plane coordinates are in grid cells / N (the grid spans the unit square). */
    put_point(e->grid, 1.5 / N, -0.6 / N, e->position + 3 * nv);
    put_point(e->grid, 2.5 / N, -0.6 / N, e->position + 3 * (nv + 1));
    put_point(e->grid, 3.3 / N, -0.9 / N, e->position + 3 * (nv + 2));
    uint32_t p = (uint32_t)nv, q = p + 1, r = p + 2;
    /* The grid's loop runs left to right along the bottom; the ears run it back. */
    uint32_t added[9] = {2, 1, p, 3, 2, q, 3, q, r};
    memcpy(e->triangle + 3 * nt, added, sizeof added);
    e->chart = (texopt_param_chart){nv + 3, e->position, nt + 3, e->triangle};
    return e;
}

static void eared_grid_destroy(eared_grid *e)
{
    param_grid_destroy(e->grid);
    free(e->position);
    free(e->triangle);
    free(e);
}

static double distance2(const double *a, const double *b)
{
    return hypot(a[0] - b[0], a[1] - b[1]);
}

/* |apex - a| / |b - a| and |apex - b| / |b - a| of triangle t in the layout and in 3D. */
static void check_shape_kept(const texopt_param_chart *chart, const double *uv, size_t t)
{
    const uint32_t *v = chart->triangle + 3 * t;
    const double *a = uv + 2 * (size_t)v[0], *b = uv + 2 * (size_t)v[1], *p = uv + 2 * (size_t)v[2];
    const double *A = chart->position + 3 * (size_t)v[0], *B = chart->position + 3 * (size_t)v[1];
    const double *P = chart->position + 3 * (size_t)v[2];
    double base = distance2(a, b),
           base3 = sqrt((B[0] - A[0]) * (B[0] - A[0]) + (B[1] - A[1]) * (B[1] - A[1]) + (B[2] - A[2]) * (B[2] - A[2]));
    double pa3 = sqrt((P[0] - A[0]) * (P[0] - A[0]) + (P[1] - A[1]) * (P[1] - A[1]) + (P[2] - A[2]) * (P[2] - A[2]));
    double pb3 = sqrt((P[0] - B[0]) * (P[0] - B[0]) + (P[1] - B[1]) * (P[1] - B[1]) + (P[2] - B[2]) * (P[2] - B[2]));
    CHECK_NEAR(distance2(p, a) / base, pa3 / base3, 1e-9);
    CHECK_NEAR(distance2(p, b) / base, pb3 / base3, 1e-9);
}

TEST(the_square_method_refuses_ears_it_cannot_put_at_corners)
{
    eared_grid *e = eared_grid_create();
    double *uv = malloc(2 * e->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    /* Three ears two edges apart along one side: no four corners a quarter apart open them all. */
    CHECK_EQ_INT(texopt_param_square(&e->chart, &p, uv, NULL, err, sizeof err), TEXOPT_E_UNSUPPORTED);
    /* One layer peels the lone ear and the outer one of the pair; the inner one is left, and
     * the square opens it by putting its apex at a corner. */
    size_t peeled = 99;
    CHECK_OK(texopt_param_without_ears(&e->chart, square_layout, &p, 1, uv, &peeled, err, sizeof err), err);
    CHECK_EQ_INT(peeled, 2);
    CHECK_EQ_INT(param_layout_flips(&e->chart, uv), 0);
    free(uv);
    eared_grid_destroy(e);
}

TEST(two_layers_peel_every_ear_and_keep_the_square)
{
    eared_grid *e = eared_grid_create();
    const texopt_param_chart *grid = &e->grid->chart;
    double *uv = malloc(2 * e->chart.vertex_count * sizeof *uv),
           *alone = malloc(2 * grid->vertex_count * sizeof *alone);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    size_t peeled = 0;
    CHECK_OK(texopt_param_without_ears(&e->chart, square_layout, &p, 2, uv, &peeled, err, sizeof err), err);
    CHECK_EQ_INT(peeled, 3);
    /* The grid is laid out exactly as without the ears (same vertex numbering). */
    CHECK_OK(texopt_param_square(grid, &p, alone, NULL, err, sizeof err), err);
    CHECK(memcmp(uv, alone, 2 * grid->vertex_count * sizeof *uv) == 0);
    /* Every ear keeps its 3D shape, counter-clockwise like the rest, outside the square. */
    CHECK_EQ_INT(param_layout_flips(&e->chart, uv), 0);
    for (size_t t = grid->triangle_count; t < e->chart.triangle_count; t++)
        check_shape_kept(&e->chart, uv, t);
    texopt_param_boundary *b = NULL;
    CHECK_OK(texopt_param_boundary_create(&b, &e->chart, err, sizeof err), err);
    CHECK(!texopt_param_boundary_crosses(b, uv));
    texopt_param_boundary_destroy(b);
    free(uv);
    free(alone);
    eared_grid_destroy(e);
}

TEST(a_chart_without_ears_goes_to_the_method_as_it_is)
{
    param_grid *g = param_grid_create(N, SHAPE_BUMP, 5);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv),
           *direct = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_square_params p;
    texopt_square_params_default(&p);
    size_t peeled = 99;
    CHECK_OK(texopt_param_without_ears(&g->chart, square_layout, &p, 3, uv, &peeled, err, sizeof err), err);
    CHECK_EQ_INT(peeled, 0);
    CHECK_OK(texopt_param_square(&g->chart, &p, direct, NULL, err, sizeof err), err);
    CHECK(memcmp(uv, direct, 2 * g->chart.vertex_count * sizeof *uv) == 0);
    free(uv);
    free(direct);
    param_grid_destroy(g);
}
