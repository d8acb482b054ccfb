/* test_axis_deform.c - deformation toward axis-aligned charts (engine/layout/axis_deform.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "axis_angles.h"
#include "axis_deform.h"
#include "test.h"

#define PI 3.14159265358979323846

/* The boundary loop of counter-clockwise triangles: directed edges without their reverse,
 * chained; returns its length (0 when it is not one loop). */
static size_t boundary_loop(const uint32_t *tri, size_t nt, uint32_t *loop)
{
    size_t cap = 3 * nt, n = 0;
    uint32_t *from = malloc(cap * sizeof *from), *to = malloc(cap * sizeof *to);
    for (size_t t = 0; t < nt; t++)
        for (int j = 0; j < 3; j++) {
            uint32_t a = tri[3 * t + j], b = tri[3 * t + (j + 1) % 3];
            int twin = 0;
            for (size_t u = 0; u < nt && !twin; u++)
                for (int k = 0; k < 3; k++)
                    twin |= tri[3 * u + k] == b && tri[3 * u + (k + 1) % 3] == a;
            if (!twin) {
                from[n] = a;
                to[n++] = b;
            }
        }
    size_t len = 0;
    if (n == 0) {
        free(from);
        free(to);
        return 0;
    }
    uint32_t first = from[0], v = first;
    do {
        loop[len++] = v;
        size_t e = 0;
        while (e < n && from[e] != v)
            e++;
        v = to[e];
    } while (v != first && len < n);
    free(from);
    free(to);
    return v == first ? len : 0;
}

static size_t flipped(const double *xy, const uint32_t *tri, size_t nt)
{
    size_t k = 0;
    for (size_t t = 0; t < nt; t++) {
        const double *a = xy + 2 * tri[3 * t], *b = xy + 2 * tri[3 * t + 1], *c = xy + 2 * tri[3 * t + 2];
        k += !((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
    }
    return k;
}

static void run(const double *rest, size_t nv, const uint32_t *tri, size_t nt, texopt_axis_deform_report *rep,
                double *xy, uint32_t *loop, size_t *nb)
{
    char err[256];
    *nb = boundary_loop(tri, nt, loop);
    double *pts = malloc(2 * *nb * sizeof *pts);
    for (size_t i = 0; i < *nb; i++)
        memcpy(pts + 2 * i, rest + 2 * loop[i], 2 * sizeof *pts);
    texopt_axis_angles a;
    texopt_status st = texopt_axis_angles_compute(pts, *nb, &a, err, sizeof err);
    if (st == TEXOPT_OK)
        st = texopt_axis_deform(nv, rest, nt, tri, loop, &a, xy, rep, err, sizeof err);
    if (st != TEXOPT_OK)
        rep->rounds = -1;
    texopt_axis_angles_destroy(&a);
    free(pts);
}

/* Largest angle (radians) between a boundary edge and its closest axis. */
static double worst_axis_angle(const double *xy, const uint32_t *loop, size_t nb)
{
    double worst = 0.0;
    for (size_t i = 0; i < nb; i++) {
        const double *a = xy + 2 * loop[i], *b = xy + 2 * loop[(i + 1) % nb];
        double ang = atan2(b[1] - a[1], b[0] - a[0]);
        double off = fabs(ang - 0.5 * PI * round(ang / (0.5 * PI)));
        worst = fmax(worst, off);
    }
    return worst;
}

TEST(a_disk_becomes_axis_aligned_without_folding)
{
    enum { N = 32 };
    double rest[2 * (2 * N + 1)];
    uint32_t tri[3 * 3 * N];
    /* two rings and a centre: inner ring radius 5, outer 10 */
    rest[0] = rest[1] = 0.0;
    for (int k = 0; k < N; k++) {
        double a = 2 * PI * (k + 0.3) / N;
        rest[2 * (1 + k)] = 5 * cos(a);
        rest[2 * (1 + k) + 1] = 5 * sin(a);
        rest[2 * (1 + N + k)] = 10 * cos(a);
        rest[2 * (1 + N + k) + 1] = 10 * sin(a);
    }
    size_t nt = 0;
    for (uint32_t k = 0; k < N; k++) {
        uint32_t i0 = 1 + k, i1 = 1 + (k + 1) % N, o0 = 1 + N + k, o1 = 1 + N + (k + 1) % N;
        uint32_t t[9] = {0, i0, i1, i0, o0, o1, i0, o1, i1};
        memcpy(tri + 3 * nt, t, sizeof t);
        nt += 3;
    }
    double xy[2 * (2 * N + 1)];
    uint32_t loop[2 * N];
    size_t nb;
    texopt_axis_deform_report rep;
    run(rest, 2 * N + 1, tri, nt, &rep, xy, loop, &nb);
    CHECK_EQ_INT(nb, N);
    CHECK(rep.rounds > 0);
    CHECK_EQ_INT(flipped(xy, tri, nt), 0);
    CHECK_MSG(rep.max_angle_error < 0.1, "angle error %g after %d rounds", rep.max_angle_error, rep.rounds);
    CHECK(worst_axis_angle(xy, loop, nb) < 0.1);
    CHECK(worst_axis_angle(rest, loop, nb) > 0.7); /* the circle was far from it */
    CHECK_MSG(rep.distortion >= 1.0 && rep.distortion < 3.0, "distortion %g, %d rounds", rep.distortion, rep.rounds);
}

TEST(a_nearly_aligned_l_keeps_its_shape)
{
    /* An L of 2 x 2 cells plus 2 cells up (4 cells), turned by 25 degrees. */
    int cells[4][2] = {{0, 0}, {1, 0}, {0, 1}, {0, 2}};
    double rest[2 * 16];
    uint32_t id[16], tri[3 * 8];
    memset(id, 0xff, sizeof id);
    size_t nv = 0, nt = 0;
    double c = cos(25 * PI / 180), s = sin(25 * PI / 180);
    for (int k = 0; k < 4; k++) {
        uint32_t v[4];
        for (int q = 0; q < 4; q++) {
            int i = cells[k][0] + q % 2, j = cells[k][1] + q / 2;
            if (id[j * 4 + i] == 0xffffffffu) {
                id[j * 4 + i] = (uint32_t)nv;
                rest[2 * nv] = 8 * (c * i - s * j);
                rest[2 * nv + 1] = 8 * (s * i + c * j);
                nv++;
            }
            v[q] = id[j * 4 + i];
        }
        uint32_t t[6] = {v[0], v[1], v[3], v[0], v[3], v[2]};
        memcpy(tri + 3 * nt, t, sizeof t);
        nt += 2;
    }
    double xy[2 * 16];
    uint32_t loop[16];
    size_t nb;
    texopt_axis_deform_report rep;
    run(rest, nv, tri, nt, &rep, xy, loop, &nb);
    CHECK_EQ_INT(nb, 10);
    CHECK(rep.rounds >= 0);
    CHECK_EQ_INT(flipped(xy, tri, nt), 0);
    CHECK(worst_axis_angle(xy, loop, nb) < 1e-3);
    CHECK_NEAR(rep.distortion, 1.0, 1e-6); /* a rotation only */
}
