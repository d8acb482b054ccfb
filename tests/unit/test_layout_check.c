/* Tests of layout_check.c on the grids of sliver_grids.h: the input layout passes against
 * itself; a zero-area strip opened (each of its triangles then 20 times the mean) fails
 * "area" and lists strip triangles; mirrored twins on
 * one region fail "overlap" as separate groups and pass as one sharing group; a vertex
 * pushed across its neighbours fails "foldover". Within one chart: a triangle moved onto
 * another of its chart is counted (not failed) with the centres it covers twice, unless
 * mirrored (a fold's sides) or already so in the input; in another chart it fails. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "handmesh.h"
#include "layout_check.h"
#include "mesh.h"
#include "sliver_grids.h"
#include "test.h"

#define N 8

static texopt_mesh *grid_mesh(sliver_grid *g, int twins, int n)
{
    texopt_mesh *mesh = NULL;
    if (sliver_grid_make(g, n, 0.0, twins) != 0)
        return NULL;
    texopt_model *m = fixture_model_from_arrays(g->positions, g->uvs, g->vertex_count, g->triangles, g->triangle_count,
                                                64, 64, "checker");
    if (m)
        texopt_mesh_create(&mesh, m, 0, NULL, 0);
    texopt_model_destroy(m);
    return mesh;
}

static double *copy_layout(const texopt_mesh *mesh)
{
    double *t = malloc(2 * mesh->vertex_count * sizeof *t);
    if (t)
        memcpy(t, mesh->texel, 2 * mesh->vertex_count * sizeof *t);
    return t;
}

TEST(the_input_layout_passes_against_itself)
{
    sliver_grid g;
    texopt_mesh *mesh = grid_mesh(&g, 0, N);
    CHECK(mesh);
    texopt_layout_check c;
    CHECK(texopt_layout_check_run(mesh, mesh->texel, mesh->width, mesh->height, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_PASSED);
    CHECK(texopt_layout_failure_name(c.failed) == NULL);
    texopt_mesh_destroy(mesh);
    sliver_grid_free(&g);
}

TEST(an_opened_zero_area_strip_fails_area_and_names_its_triangles)
{
    sliver_grid g;
    texopt_mesh *mesh = grid_mesh(&g, 0, 32);
    CHECK(mesh);
    double *t = copy_layout(mesh);
    CHECK(t);
    for (size_t v = 0; v < mesh->vertex_count; v++) /* the rows above the strip (in 3D) move 100 texels */
        if (texopt_mesh_vertex_point(mesh, (uint32_t)v)[1] > 0.5 + 1e-6)
            t[2 * v + 1] += 100.0;
    texopt_layout_check c;
    CHECK(texopt_layout_check_run(mesh, t, mesh->width, mesh->height, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_AREA);
    CHECK(c.oversized > 0 && c.listed > 0);
    for (size_t i = 0; i < c.listed; i++)
        CHECK(sliver_grid_in_strip(&g, c.triangles[i]));
    free(t);
    texopt_mesh_destroy(mesh);
    sliver_grid_free(&g);
}

TEST(mirrored_twins_overlap_unless_one_sharing_group)
{
    sliver_grid g;
    texopt_mesh *mesh = grid_mesh(&g, 1, N);
    CHECK(mesh);
    CHECK_EQ_INT(mesh->chart_count, 2);
    texopt_layout_check c;
    CHECK(texopt_layout_check_run(mesh, mesh->texel, mesh->width, mesh->height, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_OVERLAP);
    CHECK(c.overlapping > 0);
    const uint32_t one_group[2] = {0, 0};
    CHECK(texopt_layout_check_run(mesh, mesh->texel, mesh->width, mesh->height, one_group, NULL, &c, NULL, 0) ==
          TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_PASSED);
    texopt_mesh_destroy(mesh);
    sliver_grid_free(&g);
}

TEST(a_vertex_pushed_across_its_neighbours_fails_foldover)
{
    sliver_grid g;
    texopt_mesh *mesh = grid_mesh(&g, 0, N);
    CHECK(mesh);
    double *t = copy_layout(mesh);
    CHECK(t);
    uint32_t v = mesh->triangle[3 * 2 + 2]; /* corner c of quad (1, 0): grid vertex (2, 1), interior */
    t[2 * v] += 20.0;
    texopt_layout_check c;
    CHECK(texopt_layout_check_run(mesh, t, mesh->width, mesh->height, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_FOLDOVER);
    CHECK(c.folded > 0);
    free(t);
    texopt_mesh_destroy(mesh);
    sliver_grid_free(&g);
}

TEST(texel_positions_far_outside_the_frame_are_clamped_not_converted)
{
    /* A file's UVs may be any finite value: a chart 1e10 texels away once made the int
     * conversion of its triangles' boxes undefined (found by fuzz_gltf; UBSan stops this test
     * on the old code). Moved out of the frame, the twin no longer overlaps its sibling. */
    sliver_grid g;
    texopt_mesh *mesh = grid_mesh(&g, 1, N);
    CHECK(mesh);
    CHECK_EQ_INT(mesh->chart_count, 2);
    double *t = copy_layout(mesh);
    CHECK(t);
    for (size_t k = 0; k < mesh->triangle_count; k++)
        if (mesh->chart_of[k] == 1)
            for (int j = 0; j < 3; j++)
                t[2 * (size_t)mesh->triangle[3 * k + j]] = mesh->texel[2 * (size_t)mesh->triangle[3 * k + j]] + 1e10;
    texopt_layout_check c;
    CHECK(texopt_layout_check_run(mesh, t, mesh->width, mesh->height, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_PASSED);
    CHECK(texopt_layout_check_run(mesh, mesh->texel, mesh->width, mesh->height, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.failed, TEXOPT_LAYOUT_OVERLAP);
    free(t);
    texopt_mesh_destroy(mesh);
    sliver_grid_free(&g);
}

/* Two triangles 40 texels apart (legs of 20 texels), chart_of and orientation as given. */
static texopt_mesh *two_triangles(uint32_t second_chart, int mirrored)
{
    texopt_mesh *m = handmesh_alloc(6, 2);
    if (!m)
        return NULL;
    m->model_triangle = calloc(2, sizeof *m->model_triangle);
    const double xy[12] = {10, 10, 30, 10, 10, 30, 50, 10, 70, 10, 50, 30};
    memcpy(m->texel, xy, sizeof xy);
    for (uint32_t k = 0; k < 6; k++)
        m->triangle[k] = k;
    if (mirrored) { /* the second one clockwise: a fold's other side */
        m->triangle[4] = 5;
        m->triangle[5] = 4;
    }
    m->model_triangle[1] = 1;
    m->chart_of[1] = second_chart;
    m->chart_count = second_chart + 1;
    handmesh_finish(m);
    return m;
}

/* texel with the second triangle moved onto the first (its corners onto theirs). */
static void second_onto_first(const texopt_mesh *m, double *t)
{
    memcpy(t, m->texel, 12 * sizeof *t);
    for (int k = 3; k < 6; k++)
        t[2 * k] -= 40;
}

TEST(a_chart_over_itself_is_counted_and_another_chart_fails)
{
    double t[12];
    texopt_layout_check c;
    texopt_mesh *m = two_triangles(0, 0);
    CHECK(m && m->model_triangle);
    CHECK(texopt_layout_check_run(m, m->texel, 256, 256, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK(c.overlapping_within == 0 && c.failed == TEXOPT_LAYOUT_PASSED);
    second_onto_first(m, t);
    CHECK(texopt_layout_check_run(m, t, 256, 256, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    /* a right triangle of legs 20 on integer corners holds 190 centres strictly inside */
    CHECK_MSG(c.overlapping_within == 1 && c.overlap_within_texels == 190 && c.first_within == 1,
              "within %zu triangles, %zu texels", c.overlapping_within, c.overlap_within_texels);
    CHECK(c.failed == TEXOPT_LAYOUT_PASSED && c.overlapping == 0);
    /* already over itself in the input: nothing new */
    memcpy(m->texel, t, sizeof t);
    CHECK(texopt_layout_check_run(m, t, 256, 256, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.overlapping_within, 0);
    texopt_mesh_destroy(m);

    m = two_triangles(0, 1);
    CHECK(m && m->model_triangle);
    second_onto_first(m, t);
    CHECK(texopt_layout_check_run(m, t, 256, 256, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(c.overlapping_within, 0);
    texopt_mesh_destroy(m);

    m = two_triangles(1, 0);
    CHECK(m && m->model_triangle);
    second_onto_first(m, t);
    CHECK(texopt_layout_check_run(m, t, 256, 256, NULL, NULL, &c, NULL, 0) == TEXOPT_OK);
    CHECK(c.failed == TEXOPT_LAYOUT_OVERLAP && c.overlapping == 1 && c.overlapping_within == 0);
    texopt_mesh_destroy(m);
}
