/* turned_rects.c - rectangles turned by given angles as a hand-built layout (see
 * turned_rects.h). */
#include "turned_rects.h"

#include <math.h>

#include "handmesh.h"

static double unit_random(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)((*s >> 8) & 0xffffff) / 16777216.0;
}

texopt_mesh *turned_rects(size_t charts, const double *turn, double aspect, double size, double *sides, uint32_t seed)
{
    texopt_mesh *m = handmesh_alloc(charts * 4, charts * 2);
    if (!m)
        return NULL;
    m->chart_count = charts;
    for (size_t c = 0; c < charts; c++) {
        double w = size * (1 + 15 * unit_random(&seed)) / 16, h = size * (1 + 15 * unit_random(&seed)) / 16;
        if (aspect > 0)
            h = w / aspect;
        double ox = 8 * size * unit_random(&seed), oy = 8 * size * unit_random(&seed);
        double co = cos(turn[c]), si = sin(turn[c]);
        const double corner[4][2] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
        sides[2 * c] = w;
        sides[2 * c + 1] = h;
        for (int i = 0; i < 4; i++) {
            size_t v = 4 * c + (size_t)i;
            m->texel[2 * v] = ox + co * corner[i][0] - si * corner[i][1];
            m->texel[2 * v + 1] = oy + si * corner[i][0] + co * corner[i][1];
            m->position[3 * v] = m->texel[2 * v];
            m->position[3 * v + 1] = m->texel[2 * v + 1];
        }
        const uint32_t tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int k = 0; k < 2; k++) {
            for (int j = 0; j < 3; j++)
                m->triangle[3 * (2 * c + k) + j] = (uint32_t)(4 * c) + tris[k][j];
            m->chart_of[2 * c + k] = (uint32_t)c;
        }
    }
    handmesh_finish(m);
    return m;
}
