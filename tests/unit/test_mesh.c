/* Tests of mesh.c: welding, points across seams, charts, areas, flags, one-rings, and the
 * fixtures of tests/support/fixtures.c the other tests rely on. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fixtures.h"
#include "mesh.h"
#include "test.h"

static size_t count_flag(const texopt_mesh *m, unsigned flag)
{
    size_t n = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        n += (m->flags[t] & flag) != 0;
    return n;
}

/* Independent one-ring: every triangle with a corner on one of t's points. */
static size_t brute_one_ring(const texopt_mesh *m, uint32_t t, uint32_t *out)
{
    size_t n = 0;
    out[n++] = t;
    for (uint32_t s = 0; s < m->triangle_count; s++) {
        if (s == t)
            continue;
        int shares = 0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                shares |= m->point_of[m->triangle[3 * s + i]] == m->point_of[m->triangle[3 * t + j]];
        if (shares)
            out[n++] = s;
    }
    return n;
}

static int contains(const uint32_t *list, size_t n, uint32_t x)
{
    for (size_t i = 0; i < n; i++)
        if (list[i] == x)
            return 1;
    return 0;
}

/* The mesh's one-ring equals the brute-force one, as a set, with t first and no repeats. */
static int one_ring_matches(const texopt_mesh *m, uint32_t t)
{
    uint32_t got[512], want[512];
    size_t n = texopt_mesh_one_ring(m, t, got, 512);
    size_t k = brute_one_ring(m, t, want);
    if (n != k || got[0] != t)
        return 0;
    for (size_t i = 0; i < n; i++) {
        if (!contains(want, k, got[i]))
            return 0;
        for (size_t j = i + 1; j < n; j++)
            if (got[i] == got[j])
                return 0;
    }
    return 1;
}

TEST(quad_is_one_chart_of_four_vertices)
{
    texopt_model *model = fixture_textured_quad(64, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->width, 64);
    CHECK_EQ_INT(m->vertex_count, 4);
    CHECK_EQ_INT(m->point_count, 4);
    CHECK_EQ_INT(m->triangle_count, 2);
    CHECK_EQ_INT(m->chart_count, 1);
    CHECK_EQ_INT(m->chart_sign[0], 1);
    CHECK_NEAR(m->area_texel[0], 64.0 * 64.0 / 2, 1e-9);
    CHECK_NEAR(m->area_texel[1], 64.0 * 64.0 / 2, 1e-9);
    CHECK_NEAR(m->area_3d[0] + m->area_3d[1], 1.0, 1e-12);
    for (size_t t = 0; t < 2; t++)
        CHECK_EQ_INT(m->flags[t], 0);
    /* texel = (W u, H v): vertex 2 is UV (1, 1) */
    uint32_t v2 = m->vertex_of_model_vertex[2];
    CHECK_NEAR(m->texel[2 * v2], 64.0, 0);
    CHECK_NEAR(m->texel[2 * v2 + 1], 64.0, 0);
    CHECK_EQ_INT(m->model_vertex[v2], 2);
    for (size_t v = 0; v < 4; v++)
        CHECK_EQ_INT(m->vertex_on_boundary[v], 1);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(grid_interior_vertices_are_not_boundary_and_one_rings_match_brute_force)
{
    texopt_model *model = fixture_grid(4, 32, "checker");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->vertex_count, 25);
    CHECK_EQ_INT(m->triangle_count, 32);
    CHECK_EQ_INT(m->chart_count, 1);
    size_t boundary = 0;
    for (size_t v = 0; v < m->vertex_count; v++)
        boundary += m->vertex_on_boundary[v];
    CHECK_EQ_INT(boundary, 16);
    CHECK_EQ_INT(m->vertex_on_boundary[m->vertex_of_model_vertex[12]], 0); /* centre */
    for (uint32_t t = 0; t < m->triangle_count; t++)
        CHECK_MSG(one_ring_matches(m, t), "one-ring of triangle %u", t);
    /* Interior triangle (quad (1,1), first half: vertices 6, 7, 12): with this diagonal
     * direction its three corners touch 6 + 6 + 6 triangles, minus shared ones: 13. */
    uint32_t ring[64];
    CHECK_EQ_INT(texopt_mesh_one_ring(m, 10, ring, 64), 13);
    /* A short buffer still gets the full count and only cap entries. */
    uint32_t small[3] = {99, 99, 99};
    CHECK_EQ_INT(texopt_mesh_one_ring(m, 10, small, 2), 13);
    CHECK_EQ_INT(small[0], 10);
    CHECK_EQ_INT(small[2], 99);
    CHECK_EQ_INT(texopt_mesh_one_ring(m, 32, ring, 64), 0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(cube_welds_eight_points_three_charts_and_rings_cross_the_seam)
{
    texopt_model *model = fixture_cube_with_seams(64);
    CHECK(model != NULL);
    CHECK_EQ_INT(model->vertex_count, 24);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->point_count, 8);
    CHECK_EQ_INT(m->vertex_count, 18);
    CHECK_EQ_INT(m->triangle_count, 12);
    CHECK_EQ_INT(m->chart_count, 3);
    /* strip = faces 0..3 (triangles 0..7), top = 8, 9, bottom = 10, 11 */
    for (size_t t = 0; t < 8; t++)
        CHECK_EQ_INT(m->chart_of[t], 0);
    CHECK_EQ_INT(m->chart_of[8], 1);
    CHECK_EQ_INT(m->chart_of[9], 1);
    CHECK_EQ_INT(m->chart_of[10], 2);
    CHECK_EQ_INT(m->chart_of[11], 2);
    double area3 = 0, texel = 0;
    for (size_t t = 0; t < 12; t++) {
        area3 += m->area_3d[t];
        texel += m->area_texel[t];
        CHECK_EQ_INT(m->flags[t], 0);
    }
    CHECK_NEAR(area3, 6.0, 1e-12);
    CHECK_NEAR(texel, 0.375 * 64 * 64, 1e-9);
    /* Front corner (0,0,1) at u = 0 and left corner (0,0,1) at u = 1: one point, two UV
     * vertices (model vertex 0 = front s=0,t=0; model vertex 13 = left s=1,t=0). */
    uint32_t va = m->vertex_of_model_vertex[0], vb = m->vertex_of_model_vertex[13];
    CHECK(va != vb);
    CHECK_EQ_INT(m->point_of[va], m->point_of[vb]);
    /* Strip neighbours share UV vertices: front s=1 (model 1) = right s=0 (model 4). */
    CHECK_EQ_INT(m->vertex_of_model_vertex[1], m->vertex_of_model_vertex[4]);
    /* The one-ring of front triangle 0 reaches the left face across the seam (triangle 6)
     * and the bottom face, another chart (triangle 11). */
    uint32_t ring[64];
    size_t n = texopt_mesh_one_ring(m, 0, ring, 64);
    CHECK(contains(ring, n, 6));
    CHECK(contains(ring, n, 11));
    for (uint32_t t = 0; t < 12; t++)
        CHECK_MSG(one_ring_matches(m, t), "one-ring of triangle %u", t);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(sphere_counts_follow_the_construction)
{
    const int S = 12, R = 7;
    texopt_model *model = fixture_uv_sphere(S, R, 128);
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->triangle_count, 2 * S * (R - 1));
    CHECK_EQ_INT(m->vertex_count, (S + 1) * (R - 1) + 2 * S);
    CHECK_EQ_INT(m->point_count, S * (R - 1) + 2);
    CHECK_EQ_INT(m->chart_count, 1);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV), 0);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_FLIPPED | TEXOPT_TRI_WRAPPED), 0);
    double area3 = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        area3 += m->area_3d[t];
        CHECK(m->area_texel[t] > 0);
    }
    /* inscribed polyhedron: a bit under 4 pi, well over 80% of it at this resolution */
    const double sphere_area = 4 * 3.14159265358979323846;
    CHECK(area3 < sphere_area);
    CHECK(area3 > 0.8 * sphere_area);
    /* The north pole is one point shared by the S fan triangles 0..S-1. */
    uint32_t ring[128];
    size_t n = texopt_mesh_one_ring(m, 0, ring, 128);
    for (uint32_t t = 0; t < (uint32_t)S; t++)
        CHECK(contains(ring, n, t));
    CHECK(one_ring_matches(m, 0));
    CHECK(one_ring_matches(m, (uint32_t)S)); /* touches the u = 0/1 seam */
    CHECK(one_ring_matches(m, (uint32_t)(2 * S - 1)));
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(degenerate_triangles_are_flagged_relative_to_their_size)
{
    /* t0: collinear in 3D; t1: all three UVs equal; t2: a well-shaped triangle 1e-6 across;
     * t3: a sliver whose 3D height is 1e-12 of its length. */
    const float pos[] = {0, 0, 0, 1,         0, 0, 2, 0,         0, 0, 0, 1, 1, 0, 1, 0,    1,      1,
                         5, 5, 5, 5.000001f, 5, 5, 5, 5.000001f, 5, 0, 0, 3, 1, 0, 3, 0.5f, 1e-12f, 3};
    const float uv[] = {0,    0,    0.5f, 0,    0.5f, 0.5f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f,
                        0.6f, 0.6f, 0.9f, 0.6f, 0.6f, 0.9f, 0.1f,  0.9f,  0.2f,  0.9f,  0.1f,  1.0f};
    const uint32_t tri[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    texopt_model *model = fixture_model_from_arrays(pos, uv, 12, tri, 4, 32, 32, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->flags[0], TEXOPT_TRI_DEGENERATE_3D);
    CHECK_EQ_INT(m->flags[1], TEXOPT_TRI_DEGENERATE_UV);
    CHECK_EQ_INT(m->flags[2], 0);
    CHECK(m->area_3d[2] > 0);
    CHECK_EQ_INT(m->flags[3], TEXOPT_TRI_DEGENERATE_3D);
    /* The layout's area: t0 16 x 16 / 2, t2 9.6 x 9.6 / 2, t3 3.2 x 3.2 / 2 texels, t1 none;
     * paid shares weigh each triangle. */
    CHECK_NEAR(texopt_layout_area(m, m->texel, NULL), 128.0 + 46.08 + 5.12, 1e-3);
    const double paid[4] = {0.5, 1, 1, 0};
    CHECK_NEAR(texopt_layout_area(m, m->texel, paid), 64.0 + 46.08, 1e-3);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(plane_edges_are_the_triangle_in_a_frame_of_its_plane)
{
    /* t0: b - a = (0, 0, 3), c - a = (0, 4, 1): along the first edge 3 then 1, across it 4.
     * t1: collinear, no frame. */
    const float pos[] = {2, 2, 2, 2, 2, 5, 2, 6, 3, 0, 0, 0, 1, 1, 1, 2, 2, 2};
    const float uv[] = {0, 0, 0.5f, 0, 0, 0.5f, 0.6f, 0.6f, 0.9f, 0.6f, 0.6f, 0.9f};
    const uint32_t tri[] = {0, 1, 2, 3, 4, 5};
    texopt_model *model = fixture_model_from_arrays(pos, uv, 6, tri, 2, 16, 16, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    double P[2][2];
    CHECK_EQ_INT(texopt_mesh_plane_edges(m, 0, P), 0);
    CHECK(fabs(P[0][0] - 3) < 1e-12 && fabs(P[0][1] - 1) < 1e-12);
    CHECK(P[1][0] == 0 && fabs(P[1][1] - 4) < 1e-12);
    CHECK_EQ_INT(texopt_mesh_plane_edges(m, 1, P), -1);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(fold_over_inside_a_chart_is_flipped_mirrored_chart_is_not)
{
    texopt_model *model = fixture_grid(2, 16, "flat");
    CHECK(model != NULL);
    /* Drag the centre vertex (4) to UV (1.25, 0.5): triangles (1,5,4) and (4,5,8), numbers
     * 3 and 6, fold over; the other six keep their orientation. */
    model->uvs[2 * 4] = 1.25f;
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->chart_sign[0], 1);
    for (size_t t = 0; t < 8; t++)
        CHECK_MSG(((m->flags[t] & TEXOPT_TRI_FLIPPED) != 0) == (t == 3 || t == 6), "triangle %zu flags %u", t,
                  m->flags[t]);
    CHECK(m->area_texel[3] < 0);
    /* The fold pushed UVs past u = 1: those triangles rely on the wrap mode. */
    CHECK(m->flags[3] & TEXOPT_TRI_WRAPPED);
    texopt_mesh_destroy(m);

    /* Mirror the whole layout: u -> 1 - u. Every triangle is negative, none is flipped. */
    for (size_t v = 0; v < model->vertex_count; v++)
        model->uvs[2 * v] = 1.0f - (float)(v % 3) * 0.5f;
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->chart_sign[0], -1);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_FLIPPED), 0);
    for (size_t t = 0; t < 8; t++)
        CHECK(m->area_texel[t] < 0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(wrapped_uvs_are_flagged_but_rounding_noise_is_not)
{
    texopt_model *model = fixture_textured_quad(32, "flat");
    CHECK(model != NULL);
    model->uvs[0] = -1e-7f; /* vertex 0 used by both triangles */
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(count_flag(m, TEXOPT_TRI_WRAPPED), 0);
    texopt_mesh_destroy(m);
    model->uvs[0] = 0.0f;
    model->uvs[2 * 1] += 1.0f; /* vertex 1 (1,0) -> (2,0): only triangle 0 uses it */
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->flags[0] & TEXOPT_TRI_WRAPPED, TEXOPT_TRI_WRAPPED);
    CHECK_EQ_INT(m->flags[1] & TEXOPT_TRI_WRAPPED, 0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(duplicates_and_signed_zeros_weld_across_primitives)
{
    /* Two primitives of one material, each with its own copy of the shared diagonal; the
     * second writes -0 where the first writes +0. One chart, 4 UV vertices, 4 points. */
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, -0.0f, 0, 0, 1, 1, 0, 0, 1, 0};
    const float uv[] = {0, 0, 1, 0, 1, 1, 0, -0.0f, 1, 1, 0, 1};
    const uint32_t tri[] = {0, 1, 2, 3, 4, 5};
    texopt_model *model = fixture_model_from_arrays(pos, uv, 6, tri, 2, 16, 16, "flat");
    CHECK(model != NULL);
    texopt_primitive *prims = realloc(model->primitives, 2 * sizeof *prims);
    CHECK(prims != NULL);
    model->primitives = prims;
    prims[1] = prims[0];
    prims[0].vertex_count = 3;
    prims[0].triangle_count = 1;
    prims[1].gltf_primitive = 1;
    prims[1].first_vertex = 3;
    prims[1].vertex_count = 3;
    prims[1].first_triangle = 1;
    prims[1].triangle_count = 1;
    model->primitive_count = 2;
    char err[256] = "";
    CHECK_OK(texopt_model_build_domains(model, err, sizeof err), err);
    CHECK_EQ_INT(model->domain_count, 1);
    texopt_mesh *m = NULL;
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->model_vertex_count, 6);
    CHECK_EQ_INT(m->vertex_count, 4);
    CHECK_EQ_INT(m->point_count, 4);
    CHECK_EQ_INT(m->chart_count, 1);
    CHECK_EQ_INT(m->vertex_of_model_vertex[3], m->vertex_of_model_vertex[0]);
    CHECK_EQ_INT(m->vertex_of_model_vertex[4], m->vertex_of_model_vertex[2]);
    CHECK_EQ_INT(m->model_triangle[1], 1);
    for (size_t v = 0; v < m->vertex_count; v++)
        CHECK(m->model_vertex[v] < 6 && m->vertex_of_model_vertex[m->model_vertex[v]] == v);
    /* Both triangles start at the welded corner (0, 0). */
    CHECK_EQ_INT(m->triangle[3 * 1], m->triangle[0]);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(unused_vertices_are_kept_and_mapped)
{
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
    const float uv[] = {0, 0, 1, 0, 0, 1, 0.5f, 0.5f};
    const uint32_t tri[] = {0, 1, 2};
    texopt_model *model = fixture_model_from_arrays(pos, uv, 4, tri, 1, 8, 8, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    CHECK_EQ_INT(m->vertex_count, 4);
    CHECK_EQ_INT(m->point_count, 4);
    CHECK_EQ_INT(m->chart_count, 1);
    uint32_t v = m->vertex_of_model_vertex[3];
    CHECK_EQ_INT(m->model_vertex[v], 3);
    CHECK_NEAR(m->texel[2 * v], 4.0, 0);
    CHECK_EQ_INT(m->vertex_on_boundary[v], 0);
    uint32_t p = m->point_of[v];
    CHECK_EQ_INT(m->point_triangle_start[p + 1] - m->point_triangle_start[p], 0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(bad_input_is_refused_with_a_named_element)
{
    char err[256] = "";
    texopt_mesh *m = (texopt_mesh *)1;
    texopt_model *model = fixture_textured_quad(8, "flat");
    CHECK(model != NULL);
    CHECK(texopt_mesh_create(&m, model, 1, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(m == NULL);
    CHECK(strstr(err, "domain 1") != NULL);
    CHECK(texopt_mesh_create(&m, NULL, 0, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);

    model->triangles[4] = 7; /* past the primitive's 4 vertices */
    CHECK(texopt_mesh_create(&m, model, 0, err, sizeof err) == TEXOPT_E_MALFORMED);
    CHECK(strstr(err, "vertex 7") != NULL);
    model->triangles[4] = 2;

    model->uvs[3] = NAN;
    CHECK(texopt_mesh_create(&m, model, 0, err, sizeof err) == TEXOPT_E_MALFORMED);
    CHECK(strstr(err, "non-finite UV") != NULL);
    model->uvs[3] = 0;
    model->positions[5] = INFINITY;
    CHECK(texopt_mesh_create(&m, model, 0, err, sizeof err) == TEXOPT_E_MALFORMED);
    CHECK(strstr(err, "non-finite position") != NULL);
    model->positions[5] = 0;

    float *uvs = model->uvs;
    model->uvs = NULL;
    CHECK(texopt_mesh_create(&m, model, 0, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    CHECK(strstr(err, "TEXCOORD_0") != NULL);
    model->uvs = uvs;
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    texopt_mesh_destroy(m);
    texopt_mesh_destroy(NULL);
    texopt_model_destroy(model);
}

TEST(large_grid_builds_fast)
{
    /* 2 * 256^2 = 131072 triangles: linear-time welding takes a few tens of milliseconds;
     * a quadratic step would take minutes. */
    texopt_model *model = fixture_grid(256, 64, "flat");
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    printf("  mesh_create: %zu triangles in %.3f s\n", m->triangle_count, seconds);
    CHECK_EQ_INT(m->triangle_count, 131072);
    CHECK_EQ_INT(m->vertex_count, 257 * 257);
    CHECK_EQ_INT(m->chart_count, 1);
    CHECK(seconds < 2.0);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}
