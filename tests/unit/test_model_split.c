/* test_model_split.c - model_split.h on a 2 x 2 grid (fixtures.h fixture_grid): the quads'
 * left column one group, the right column another, so the middle column of vertices is
 * copied once; the model draws as before (positions, UVs, normals) and file_vertex names what each copy repeats. */
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "model_split.h"
#include "test.h"

/* Groups: quad (i, j) gives triangles 2 (2 j + i) and 2 (2 j + i) + 1; group = i. */
static uint32_t *column_groups(const texopt_model *m)
{
    uint32_t *g = malloc(3 * m->triangle_count * sizeof *g);
    for (size_t t = 0; g && t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            g[3 * t + (size_t)k] = (uint32_t)((t / 2) % 2);
    return g;
}

TEST(a_shared_column_is_copied_once_and_the_model_draws_as_before)
{
    texopt_model *m = fixture_grid(2, 8, "checker");
    CHECK(m != NULL);
    if (!m)
        return;
    size_t nt = m->triangle_count;
    /* Distinct normals per vertex, so a copy that took another vertex's would show. */
    m->normals = malloc(3 * m->vertex_count * sizeof *m->normals);
    CHECK(m->normals != NULL);
    for (size_t v = 0; m->normals && v < 3 * m->vertex_count; v++)
        m->normals[v] = (float)v;
    float before_pos[8 * 9], before_uv[8 * 6], before_normal[8 * 9];
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = m->triangles[3 * t + (size_t)k];
            memcpy(before_pos + 9 * t + 3 * k, m->positions + 3 * v, 3 * sizeof(float));
            memcpy(before_uv + 6 * t + 2 * k, m->uvs + 2 * v, 2 * sizeof(float));
            memcpy(before_normal + 9 * t + 3 * k, m->normals + 3 * v, 3 * sizeof(float));
        }
    uint32_t *g = column_groups(m);
    size_t added = 0;
    char err[256] = "";
    CHECK_OK(texopt_model_split_vertices(m, g, &added, err, sizeof err), err);
    CHECK_EQ_INT(added, 3);
    CHECK_EQ_INT(m->vertex_count, 12);
    CHECK_EQ_INT(m->primitives[0].vertex_count, 12);
    CHECK(m->file_vertex != NULL);
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = m->triangles[3 * t + (size_t)k];
            CHECK(memcmp(before_pos + 9 * t + 3 * k, m->positions + 3 * v, 3 * sizeof(float)) == 0);
            CHECK(memcmp(before_uv + 6 * t + 2 * k, m->uvs + 2 * v, 2 * sizeof(float)) == 0);
            CHECK(memcmp(before_normal + 9 * t + 3 * k, m->normals + 3 * v, 3 * sizeof(float)) == 0);
            CHECK_EQ_INT(m->file_vertex[v] == v || v >= 9, 1);
        }
    /* no vertex is used by both groups any more, and the copies repeat the middle column
     * (file vertices 1, 4, 7) */
    int group_of[12];
    for (int v = 0; v < 12; v++)
        group_of[v] = -1;
    for (size_t c = 0; c < 3 * nt; c++) {
        uint32_t v = m->triangles[c];
        CHECK(group_of[v] == -1 || group_of[v] == (int)g[c]);
        group_of[v] = (int)g[c];
    }
    for (uint32_t v = 9; v < 12; v++)
        CHECK(m->file_vertex[v] == 1 || m->file_vertex[v] == 4 || m->file_vertex[v] == 7);
    /* splitting again by the same groups copies nothing and keeps file_vertex */
    CHECK_OK(texopt_model_split_vertices(m, g, &added, err, sizeof err), err);
    CHECK_EQ_INT(added, 0);
    CHECK_EQ_INT(m->vertex_count, 12);
    for (uint32_t v = 9; v < 12; v++)
        CHECK(m->file_vertex[v] == 1 || m->file_vertex[v] == 4 || m->file_vertex[v] == 7);
    free(g);
    texopt_model_destroy(m);
}

TEST(one_group_copies_nothing)
{
    texopt_model *m = fixture_grid(3, 8, "flat");
    CHECK(m != NULL);
    if (!m)
        return;
    uint32_t *g = calloc(3 * m->triangle_count, sizeof *g);
    size_t added = 1;
    char err[256] = "";
    CHECK_OK(texopt_model_split_vertices(m, g, &added, err, sizeof err), err);
    CHECK_EQ_INT(added, 0);
    CHECK_EQ_INT(m->vertex_count, 16);
    for (uint32_t v = 0; v < 16; v++)
        CHECK_EQ_INT(m->file_vertex[v], v);
    free(g);
    texopt_model_destroy(m);
}
