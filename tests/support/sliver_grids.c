/* sliver_grids.c - grids with a strip of zero-area or sliver UV triangles; see sliver_grids.h. */
#include "sliver_grids.h"

#include <stdlib.h>
#include <string.h>

/* UV of grid vertex (i, j): rows above the strip (j > k) shifted by half a column and by
 * strip_height - 1 rows, so that the strip spans strip_height of a row. */
static void grid_uv(int n, int i, int j, double strip_height, float uv[2])
{
    int k = n / 2;
    double shift = j > k ? 0.5 : 0.0;
    double row = j > k ? j - 1 + strip_height : j;
    uv[0] = (float)(0.05 + 0.9 * (i + shift) / (n + 0.5));
    uv[1] = (float)(0.05 + 0.9 * row / (n - 1 + strip_height));
}

static void make_copy(sliver_grid *g, int n, double strip_height, int copy)
{
    size_t nv = (size_t)(n + 1) * (n + 1), base_v = nv * (size_t)copy, base_t = g->copy_triangles * (size_t)copy;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t v = base_v + (size_t)j * (n + 1) + (size_t)i;
            float *p = g->positions + 3 * v, *uv = g->uvs + 2 * v;
            p[0] = (float)((double)i / n + 1.5 * copy);
            p[1] = (float)((double)j / n);
            p[2] = 0.0f;
            grid_uv(n, i, j, strip_height, uv);
            if (copy)
                uv[0] = 1.0f - uv[0];
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(base_v + (size_t)j * (n + 1) + (size_t)i), b = a + 1, c = a + (uint32_t)(n + 1) + 1,
                     d = a + (uint32_t)(n + 1);
            uint32_t *t = g->triangles + 3 * (base_t + 2 * ((size_t)j * n + (size_t)i));
            uint32_t quad[6] = {a, b, c, a, c, d};
            memcpy(t, quad, sizeof quad);
        }
}

int sliver_grid_make(sliver_grid *g, int n, double strip_height, int twins)
{
    memset(g, 0, sizeof *g);
    if (n < 4 || n % 2 || !(strip_height >= 0 && strip_height < 1))
        return -1;
    int copies = twins ? 2 : 1;
    g->copy_triangles = 2 * (size_t)n * (size_t)n;
    g->vertex_count = (size_t)copies * (n + 1) * (n + 1);
    g->triangle_count = (size_t)copies * g->copy_triangles;
    g->positions = malloc(3 * g->vertex_count * sizeof *g->positions);
    g->uvs = malloc(2 * g->vertex_count * sizeof *g->uvs);
    g->triangles = malloc(3 * g->triangle_count * sizeof *g->triangles);
    if (!g->positions || !g->uvs || !g->triangles) {
        sliver_grid_free(g);
        return -1;
    }
    for (int c = 0; c < copies; c++)
        make_copy(g, n, strip_height, c);
    g->strip_first = 2 * (size_t)(n / 2) * (size_t)n;
    g->strip_count = 2 * (size_t)n;
    return 0;
}

int sliver_grid_in_strip(const sliver_grid *g, size_t t)
{
    size_t local = t % g->copy_triangles;
    return local >= g->strip_first && local < g->strip_first + g->strip_count;
}

void sliver_grid_free(sliver_grid *g)
{
    free(g->positions);
    free(g->uvs);
    free(g->triangles);
    memset(g, 0, sizeof *g);
}
