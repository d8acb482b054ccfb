/* Tests of layout_check.c on the grids of sliver_grids.h: the input layout passes against
 * itself; a zero-area strip opened (each of its triangles then 20 times the mean) fails
 * "area" and lists strip triangles; mirrored twins on
 * one region fail "overlap" as separate groups and pass as one sharing group; a vertex
 * pushed across its neighbours fails "foldover". */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
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
