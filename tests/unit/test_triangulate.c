/* test_triangulate.c - the constrained triangulation (engine/layout/triangulate.c). */
#include <math.h>
#include <stdlib.h>

#include "test.h"
#include "triangulate.h"

static double area2(const double *p, const uint32_t *t)
{
    const double *a = p + 2 * (size_t)t[0], *b = p + 2 * (size_t)t[1], *c = p + 2 * (size_t)t[2];
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

static int has_edge(const texopt_triangulation *tr, uint32_t a, uint32_t b)
{
    for (size_t t = 0; t < tr->triangle_count; t++)
        for (int j = 0; j < 3; j++) {
            uint32_t x = tr->triangle[3 * t + j], y = tr->triangle[3 * t + (j + 1) % 3];
            if ((x == a && y == b) || (x == b && y == a))
                return 1;
        }
    return 0;
}

/* Sum of doubled areas at depth `depth` (-1: all); every triangle must be counter-clockwise. */
static double area_at(const double *p, const texopt_triangulation *tr, int depth, int *clockwise)
{
    double s = 0.0;
    for (size_t t = 0; t < tr->triangle_count; t++) {
        double a = area2(p, tr->triangle + 3 * t);
        *clockwise += !(a > 0.0);
        if (depth < 0 || tr->depth[t] == depth)
            s += a;
    }
    return 0.5 * s;
}

TEST(points_only_tile_their_hull)
{
    double p[] = {0, 0, 10, 0, 10, 10, 0, 10, 3, 4, 7, 6, 5, 0}; /* (5, 0) on the hull edge */
    texopt_triangulation tr;
    char err[256];
    CHECK_OK(texopt_triangulate(p, 7, NULL, 0, &tr, err, sizeof err), err);
    int cw = 0;
    CHECK_NEAR(area_at(p, &tr, -1, &cw), 100.0, 1e-9);
    CHECK_EQ_INT(cw, 0);
    CHECK_EQ_INT(tr.triangle_count, 7); /* 2 n - h - 2: n = 7 points, h = 5 on the hull */
    texopt_triangulation_destroy(&tr);
}

TEST(a_segment_the_delaunay_triangulation_lacks_is_recovered)
{
    /* The short edge (5, 4.9)-(5, 5.1) is Delaunay and crosses segment 4-5. */
    double p[] = {0, 0, 10, 0, 10, 10, 0, 10, 2, 5, 8, 5, 5, 4.9, 5, 5.1};
    uint32_t seg[] = {4, 5};
    texopt_triangulation tr;
    char err[256];
    CHECK_OK(texopt_triangulate(p, 8, NULL, 0, &tr, err, sizeof err), err);
    CHECK(!has_edge(&tr, 4, 5));
    CHECK(has_edge(&tr, 6, 7));
    texopt_triangulation_destroy(&tr);
    CHECK_OK(texopt_triangulate(p, 8, seg, 1, &tr, err, sizeof err), err);
    CHECK(has_edge(&tr, 4, 5));
    CHECK(!has_edge(&tr, 6, 7));
    int cw = 0;
    CHECK_NEAR(area_at(p, &tr, -1, &cw), 100.0, 1e-9);
    CHECK_EQ_INT(cw, 0);
    texopt_triangulation_destroy(&tr);
}

TEST(depth_counts_the_segments_crossed_from_outside)
{
    /* Box 0..10 with its edges as segments, a square 3..7 inside it with a square hole
     * 4..6: depths 1 (ring between box and square), 2 (the square's ring), 3 (the hole). */
    double p[] = {0, 0, 10, 0, 10, 10, 0, 10, 3, 3, 7, 3, 7, 7, 3, 7, 4, 4, 6, 4, 6, 6, 4, 6};
    uint32_t seg[24];
    for (uint32_t k = 0; k < 3; k++)
        for (uint32_t j = 0; j < 4; j++) {
            seg[8 * k + 2 * j] = 4 * k + j;
            seg[8 * k + 2 * j + 1] = 4 * k + (j + 1) % 4;
        }
    texopt_triangulation tr;
    char err[256];
    CHECK_OK(texopt_triangulate(p, 12, seg, 12, &tr, err, sizeof err), err);
    int cw = 0;
    CHECK_NEAR(area_at(p, &tr, 1, &cw), 100.0 - 16.0, 1e-9);
    CHECK_NEAR(area_at(p, &tr, 2, &cw), 16.0 - 4.0, 1e-9);
    CHECK_NEAR(area_at(p, &tr, 3, &cw), 4.0, 1e-9);
    CHECK_NEAR(area_at(p, &tr, 0, &cw), 0.0, 1e-9);
    CHECK_EQ_INT(cw, 0);
    texopt_triangulation_destroy(&tr);
}

TEST(bad_input_is_refused)
{
    texopt_triangulation tr;
    char err[256];
    double dup[] = {0, 0, 10, 0, 10, 10, 10, 0};
    CHECK(texopt_triangulate(dup, 4, NULL, 0, &tr, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    double line[] = {0, 0, 5, 0, 10, 0, 5, 5};
    uint32_t through[] = {0, 2}; /* passes through point 1 */
    CHECK(texopt_triangulate(line, 4, through, 1, &tr, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    double cross[] = {0, 0, 10, 10, 10, 0, 0, 10};
    uint32_t x[] = {0, 1, 2, 3}; /* the two diagonals */
    CHECK(texopt_triangulate(cross, 4, x, 2, &tr, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    double collinear[] = {0, 0, 1, 1, 2, 2};
    CHECK(texopt_triangulate(collinear, 3, NULL, 0, &tr, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(tr.triangle == NULL);
}

TEST(a_jittered_grid_boundary_is_kept)
{
    /* 400 random points in a box with a 40-gon as segments: every segment is an edge and
     * the triangles tile the hull. */
    enum { N = 40, R = 400 };
    double p[2 * (N + R + 4)];
    uint32_t seg[2 * N];
    unsigned s = 7;
    for (int k = 0; k < N; k++) {
        double a = 2 * 3.14159265358979 * k / N, r = 30 + 10 * ((k * 7) % 3);
        p[2 * k] = 50 + r * cos(a);
        p[2 * k + 1] = 50 + r * sin(a);
        seg[2 * k] = (uint32_t)k;
        seg[2 * k + 1] = (uint32_t)((k + 1) % N);
    }
    for (int k = 0; k < R; k++) {
        s = s * 1103515245u + 12345u;
        p[2 * (N + k)] = 1 + 98 * ((s >> 8) & 0xffff) / 65535.0;
        s = s * 1103515245u + 12345u;
        p[2 * (N + k) + 1] = 1 + 98 * ((s >> 8) & 0xffff) / 65535.0;
    }
    double box[] = {0, 0, 100, 0, 100, 100, 0, 100};
    for (int k = 0; k < 8; k++)
        p[2 * (N + R) + k] = box[k];
    texopt_triangulation tr;
    char err[256];
    CHECK_OK(texopt_triangulate(p, N + R + 4, seg, N, &tr, err, sizeof err), err);
    for (int k = 0; k < N; k++)
        CHECK_MSG(has_edge(&tr, seg[2 * k], seg[2 * k + 1]), "segment %d missing", k);
    int cw = 0;
    CHECK_NEAR(area_at(p, &tr, -1, &cw), 10000.0, 1e-6);
    CHECK_EQ_INT(cw, 0);
    texopt_triangulation_destroy(&tr);
}

TEST(a_lattice_with_points_on_edges_tiles_its_square)
{
    /* 12 x 12 lattice points in a scrambled order: many land on an existing edge, where the
     * triangle past one side of the split edge can border both triangles being split. */
    enum { S = 12, N = S * S };
    double p[2 * N];
    for (int k = 0; k < N; k++) {
        int m = (k * 37) % N; /* 37 is prime to 144: a permutation */
        p[2 * k] = m % S;
        p[2 * k + 1] = m / S;
    }
    texopt_triangulation tr;
    char err[256];
    CHECK_OK(texopt_triangulate(p, N, NULL, 0, &tr, err, sizeof err), err);
    int cw = 0;
    CHECK_NEAR(area_at(p, &tr, -1, &cw), (S - 1) * (S - 1), 1e-9);
    CHECK_EQ_INT(cw, 0);
    CHECK_EQ_INT(tr.triangle_count, 2 * (S - 1) * (S - 1)); /* 2 n - h - 2, h = 4 (S - 1) */
    texopt_triangulation_destroy(&tr);
}
