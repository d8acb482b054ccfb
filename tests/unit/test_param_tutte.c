/* test_param_tutte.c - mean-value Tutte embedding (engine/param/param_tutte.c) and the disk check
 * and boundary edges of engine/param/param_chart.c, on generated grids
 * (tests/support/param_grids.h) and a hand-made non-manifold fan. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "param_grids.h"
#include "param_tutte.h"
#include "test.h"

TEST(curved_disk_has_no_flips_and_a_circle_boundary)
{
    param_grid *g = param_grid_create(12, SHAPE_BUMP, 5);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    CHECK_OK(texopt_param_tutte(&g->chart, uv, err, sizeof err), err);
    CHECK_EQ_INT(param_layout_flips(&g->chart, uv), 0);
    texopt_param_boundary *b = NULL;
    CHECK_OK(texopt_param_boundary_create(&b, &g->chart, err, sizeof err), err);
    CHECK_EQ_INT(b->count, 4 * 12);
    double radius = b->arc[b->count] / (2.0 * 3.14159265358979323846);
    for (size_t i = 0; i < b->count; i++)
        CHECK_NEAR(hypot(uv[2 * (size_t)b->vertex[i]], uv[2 * (size_t)b->vertex[i] + 1]), radius, 1e-12);
    texopt_param_boundary_destroy(b);
    free(uv);
    param_grid_destroy(g);
}

/* Mean-value weights reproduce linear functions: a planar chart whose boundary is held where
 * it lies comes back exactly (uniform weights would not, the interior is jittered). */
TEST(planar_chart_with_its_own_boundary_is_reproduced)
{
    param_grid *g = param_grid_create(9, SHAPE_TILTED_PLANE, 0);
    size_t nv = g->chart.vertex_count;
    double *uv = malloc(2 * nv * sizeof *uv);
    char err[256] = "";
    texopt_param_boundary *b = NULL;
    CHECK_OK(texopt_param_boundary_create(&b, &g->chart, err, sizeof err), err);
    for (size_t v = 0; v < nv; v++)
        uv[2 * v] = uv[2 * v + 1] = b->on_boundary[v] ? 0.0 : 1e3;
    for (size_t i = 0; i < b->count; i++)
        for (int k = 0; k < 2; k++)
            uv[2 * (size_t)b->vertex[i] + k] = g->plane[2 * (size_t)b->vertex[i] + k];
    CHECK_OK(texopt_param_embed_interior(&g->chart, b, NULL, uv, err, sizeof err), err);
    for (size_t v = 0; v < 2 * nv; v++)
        CHECK_NEAR(uv[v], g->plane[v], 1e-10);
    texopt_param_boundary_destroy(b);
    free(uv);
    param_grid_destroy(g);
}

TEST(non_disks_are_refused_with_a_reason)
{
    param_grid *g = param_grid_create(4, SHAPE_TILTED_PLANE, 0);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_param_chart holed = g->chart;
    /* Drop the two triangles of an interior quad: a hole, two boundary loops. */
    uint32_t *tris = malloc(3 * holed.triangle_count * sizeof *tris);
    size_t kept = 0;
    for (size_t t = 0; t < holed.triangle_count; t++)
        if (t / 2 != 5) {
            for (int k = 0; k < 3; k++)
                tris[3 * kept + k] = holed.triangle[3 * t + k];
            kept++;
        }
    holed.triangle = tris;
    holed.triangle_count = kept;
    CHECK_EQ_INT(texopt_param_tutte(&holed, uv, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    texopt_param_chart bad = g->chart;
    bad.vertex_count = 10; /* triangles use vertices beyond it */
    CHECK_EQ_INT(texopt_param_tutte(&bad, uv, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    bad = g->chart;
    bad.vertex_count += 1; /* an unused vertex */
    CHECK_EQ_INT(texopt_param_tutte(&bad, uv, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    /* One triangle reversed: its edges run the same way as its neighbours'. */
    for (size_t i = 0; i < 3 * g->chart.triangle_count; i++)
        tris[i] = g->chart.triangle[i];
    uint32_t swap = tris[3 * 7 + 1];
    tris[3 * 7 + 1] = tris[3 * 7 + 2];
    tris[3 * 7 + 2] = swap;
    bad = g->chart;
    bad.triangle = tris;
    CHECK_EQ_INT(texopt_param_tutte(&bad, uv, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK_EQ_INT(texopt_param_tutte(&g->chart, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    free(tris);
    free(uv);
    param_grid_destroy(g);
}

/* Boundary edges come in triangle order, directed as their triangle lists them; an edge of
 * three triangles (0-2) or of two in the same direction (4 -> 2) is none of them. */
TEST(boundary_edges_are_the_edges_of_one_triangle)
{
    const uint32_t tri[12] = {0, 1, 2, 0, 2, 3, 2, 0, 4, 5, 4, 2};
    const uint32_t want[14] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 4, 5, 4, 2, 5};
    uint32_t *edge = NULL;
    size_t count = 99;
    char err[256] = "";
    CHECK_OK(texopt_param_boundary_edges(tri, 4, &edge, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 7);
    CHECK(memcmp(edge, want, sizeof want) == 0);
    free(edge);
    CHECK_OK(texopt_param_boundary_edges(tri, 0, &edge, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 0);
    free(edge);
    /* On a disk they are its boundary loop's edges. */
    param_grid *g = param_grid_create(5, SHAPE_TILTED_PLANE, 7);
    texopt_param_boundary *b = NULL;
    CHECK_OK(texopt_param_boundary_create(&b, &g->chart, err, sizeof err), err);
    CHECK_OK(texopt_param_boundary_edges(g->chart.triangle, g->chart.triangle_count, &edge, &count, err, sizeof err),
             err);
    CHECK_EQ_INT(count, b->count);
    for (size_t e = 0; e < count; e++) {
        size_t i = 0;
        while (i < b->count && b->vertex[i] != edge[2 * e])
            i++;
        CHECK(i < b->count && b->vertex[(i + 1) % b->count] == edge[2 * e + 1]);
    }
    free(edge);
    texopt_param_boundary_destroy(b);
    param_grid_destroy(g);
}
