/* disc_charts.c - generated discs and annuli (see disc_charts.h). */
#include "disc_charts.h"

#include <math.h>
#include <string.h>

#include "handmesh.h"

#define PI 3.14159265358979323846
#define RADIUS 40.0
#define SPACING 100.0

/* Appends one chart centred at (cx, 0) from vertex *v and triangle *t. */
static void add_disc(texopt_mesh *m, size_t *v, size_t *t, uint32_t chart, double cx, int rings, int segments,
                     double hole)
{
    int annulus = hole > 0;
    if (!annulus) {
        m->texel[2 * *v] = cx;
        m->texel[2 * *v + 1] = 0.0;
        (*v)++;
    }
    size_t ring0 = *v, centre = ring0 - 1;
    for (int r = annulus ? 0 : 1; r <= rings; r++)
        for (int s = 0; s < segments; s++) {
            double radius = annulus ? hole + (RADIUS - hole) * r / rings : RADIUS * r / rings;
            double angle = 2 * PI * s / segments;
            m->texel[2 * *v] = cx + radius * cos(angle);
            m->texel[2 * *v + 1] = radius * sin(angle);
            (*v)++;
        }
    if (!annulus)
        for (int s = 0; s < segments; s++) {
            uint32_t tri[3] = {(uint32_t)centre, (uint32_t)(ring0 + s), (uint32_t)(ring0 + (s + 1) % segments)};
            memcpy(m->triangle + 3 * *t, tri, sizeof tri);
            m->chart_of[(*t)++] = chart;
        }
    int ring_count = annulus ? rings + 1 : rings;
    for (int r = 0; r + 1 < ring_count; r++)
        for (int s = 0; s < segments; s++) {
            uint32_t a = (uint32_t)(ring0 + (size_t)r * segments + s);
            uint32_t b = (uint32_t)(ring0 + (size_t)r * segments + (s + 1) % segments);
            uint32_t c = a + (uint32_t)segments, d = b + (uint32_t)segments;
            uint32_t tris[6] = {a, d, b, a, c, d};
            memcpy(m->triangle + 3 * *t, tris, sizeof tris);
            m->chart_of[*t] = m->chart_of[*t + 1] = chart;
            *t += 2;
        }
}

texopt_mesh *disc_charts(int count, int rings, int segments, double hole)
{
    int annulus = hole > 0;
    size_t nv = annulus ? (size_t)(rings + 1) * segments : 1 + (size_t)rings * segments;
    size_t nt = annulus ? 2 * (size_t)rings * segments : (size_t)segments + 2 * (size_t)(rings - 1) * segments;
    texopt_mesh *m = handmesh_alloc(nv * count, nt * count);
    if (!m)
        return NULL;
    m->chart_count = (size_t)count;
    size_t v = 0, t = 0;
    for (int c = 0; c < count; c++)
        add_disc(m, &v, &t, (uint32_t)c, SPACING * c, rings, segments, hole);
    for (size_t k = 0; k < m->vertex_count; k++) {
        m->position[3 * k] = m->texel[2 * k] / 16.0;
        m->position[3 * k + 1] = m->texel[2 * k + 1] / 16.0;
    }
    handmesh_finish(m);
    return m;
}
