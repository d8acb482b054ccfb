/* test_tri_bins.c - the triangle-bin grid for point location (engine/stage2/tri_bins.c): every kept
 * triangle that holds a point is listed in the point's bin, no other triangle is listed
 * at all, and keeping none gives an empty grid. */
#include <stdlib.h>
#include <string.h>

#include "handmesh.h"
#include "test.h"
#include "tri_bins.h"

/* An n x n grid of 4-texel cells, inner vertices jittered, at (x0, 0). */
static texopt_mesh *jittered_grid(int n, double x0)
{
    texopt_mesh *m = handmesh_alloc((size_t)(n + 1) * (n + 1), 2 * (size_t)n * n);
    unsigned state = 99u;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t v = (size_t)j * (n + 1) + i;
            int inner = i > 0 && i < n && j > 0 && j < n;
            state = state * 1103515245u + 12345u;
            double jx = inner ? 1.5 * (((state >> 8) & 0xffff) / 65535.0 - 0.5) : 0.0;
            m->texel[2 * v] = x0 + 4.0 * i + jx;
            m->texel[2 * v + 1] = 4.0 * j - jx;
            m->position[3 * v] = m->texel[2 * v];
            m->position[3 * v + 1] = m->texel[2 * v + 1];
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, d = a + (uint32_t)(n + 1), e = d + 1;
            uint32_t tris[6] = {a, b, e, a, e, d};
            memcpy(m->triangle + 6 * ((size_t)j * n + i), tris, sizeof tris);
        }
    handmesh_finish(m);
    return m;
}

static int listed(const texopt_tri_bins *b, size_t bin, size_t t)
{
    for (uint32_t k = b->start[bin]; k < b->start[bin + 1]; k++)
        if (b->tri[k] == t)
            return 1;
    return 0;
}

TEST(every_kept_triangle_holding_a_point_is_in_its_bin)
{
    int n = 12;
    texopt_mesh *m = jittered_grid(n, 3.0);
    unsigned char *keep = calloc(m->triangle_count, 1);
    for (size_t t = 0; t < m->triangle_count; t++)
        keep[t] = t % 3 != 0;
    texopt_tri_bins b;
    char err[256] = "";
    CHECK_OK(texopt_tri_bins_build(&b, m, keep, err, sizeof err), err);
    CHECK(b.start != NULL && b.nx * b.ny > 1);
    size_t found = 0;
    for (int y = 0; y < 4 * n * 4; y++)
        for (int x = 0; x < 4 * n * 4; x++) {
            double p[2] = {3.0 + 0.25 * x + 0.1, 0.25 * y + 0.1}, w[3];
            size_t bin = texopt_tri_bins_index(&b, p[1], 1) * b.nx + texopt_tri_bins_index(&b, p[0], 0);
            for (size_t t = 0; t < m->triangle_count; t++)
                if (keep[t] && handmesh_barycentric(m, t, p, w)) {
                    CHECK(listed(&b, bin, t));
                    found++;
                }
        }
    CHECK(found > 1000);
    for (size_t k = 0; k < b.start[b.nx * b.ny]; k++)
        CHECK(keep[b.tri[k]]);
    texopt_tri_bins_free(&b);
    free(keep);
    texopt_mesh_destroy(m);
}

TEST(keeping_no_triangle_gives_an_empty_grid)
{
    texopt_mesh *m = jittered_grid(3, 0.0);
    unsigned char *keep = calloc(m->triangle_count, 1);
    texopt_tri_bins b;
    char err[256] = "";
    CHECK_OK(texopt_tri_bins_build(&b, m, keep, err, sizeof err), err);
    CHECK(b.start == NULL && b.tri == NULL);
    texopt_tri_bins_free(&b);
    texopt_tri_bins_free(NULL);
    free(keep);
    texopt_mesh_destroy(m);
}
