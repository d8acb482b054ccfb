/* test_axis_angles.c - target polar angles of Liu et al. 2019, 3.1.1 (engine/layout/axis_angles.c). */
#include <math.h>
#include <stdlib.h>

#include "axis_angles.h"
#include "test.h"

#define PI 3.14159265358979323846

/* The polygon `corners` (counter-clockwise), each side cut into `parts` edges, rotated by
 * `angle` about the origin, into xy; returns the point count. */
static size_t subdivided(const double *corners, size_t nc, int parts, double angle, double *xy)
{
    size_t n = 0;
    for (size_t c = 0; c < nc; c++) {
        const double *a = corners + 2 * c, *b = corners + 2 * ((c + 1) % nc);
        for (int k = 0; k < parts; k++) {
            double t = (double)k / parts, x = a[0] + t * (b[0] - a[0]), y = a[1] + t * (b[1] - a[1]);
            xy[2 * n] = cos(angle) * x - sin(angle) * y;
            xy[2 * n + 1] = sin(angle) * x + cos(angle) * y;
            n++;
        }
    }
    return n;
}

static int turn_sum(const texopt_axis_angles *a)
{
    int s = 0;
    for (size_t i = 0; i < a->count; i++)
        s += a->turn[i];
    return s;
}

/* Theta_{i+1} = Theta_i + K_i all around, closing with one full turn. */
static int consistent(const texopt_axis_angles *a)
{
    size_t n = a->count, last = (a->start + n - 1) % n;
    for (size_t step = 1; step < n; step++) {
        size_t i = (a->start + step) % n, prev = (a->start + step - 1) % n;
        if (a->theta[i] != a->theta[prev] + a->turn[prev])
            return 0;
    }
    return a->theta[last] + a->turn[last] == a->theta[a->start] + 4;
}

TEST(a_rotated_l_shape_gets_its_corners_back)
{
    double L[] = {0, 0, 20, 0, 20, 10, 10, 10, 10, 30, 0, 30}; /* 5 convex corners, 1 reflex */
    double xy[2 * 6 * 3];
    size_t n = subdivided(L, 6, 3, 30.0 * PI / 180.0, xy);
    texopt_axis_angles a;
    char err[256];
    CHECK_OK(texopt_axis_angles_compute(xy, n, &a, err, sizeof err), err);
    CHECK_NEAR(a.rotation, -30.0 * PI / 180.0, 1e-6);
    int plus = 0, minus = 0;
    for (size_t i = 0; i < n; i++) {
        plus += a.turn[i] == 1;
        minus += a.turn[i] == -1;
        /* corner points are every third point: point i + 1 ends edge i */
        if ((i + 1) % 3 != 0)
            CHECK_EQ_INT(a.turn[i], 0);
    }
    CHECK_EQ_INT(plus, 5);
    CHECK_EQ_INT(minus, 1);
    CHECK_EQ_INT(a.turn[3 * 3 - 1], -1); /* the reflex corner (10, 10) is point 9 */
    CHECK(consistent(&a));
    /* the first edge runs along +x before the rotation: a multiple of 4 quarter turns */
    CHECK_EQ_INT(((a.theta[0] % 4) + 4) % 4, 0);
    texopt_axis_angles_destroy(&a);
}

TEST(a_circle_gets_four_corners)
{
    enum { N = 64 };
    double xy[2 * N];
    for (int k = 0; k < N; k++) {
        xy[2 * k] = 10 * cos(2 * PI * (k + 0.37) / N);
        xy[2 * k + 1] = 10 * sin(2 * PI * (k + 0.37) / N);
    }
    texopt_axis_angles a;
    char err[256];
    CHECK_OK(texopt_axis_angles_compute(xy, N, &a, err, sizeof err), err);
    int corners = 0;
    for (size_t i = 0; i < a.count; i++) {
        CHECK(a.turn[i] == 0 || a.turn[i] == 1);
        corners += a.turn[i] == 1;
    }
    CHECK_EQ_INT(corners, 4);
    CHECK(consistent(&a));
    texopt_axis_angles_destroy(&a);
}

TEST(a_sharp_corner_is_split_so_nothing_folds)
{
    /* Apex of 10 degrees: snapped, it would turn by two quarters (interior angle 0). */
    double h = 20.0 / tan(5.0 * PI / 180.0);
    double tri[] = {-20, 0, 20, 0, 0, h};
    double xy[2 * 3 * 6];
    size_t n = subdivided(tri, 3, 6, 0.0, xy);
    texopt_axis_angles a;
    char err[256];
    CHECK_OK(texopt_axis_angles_compute(xy, n, &a, err, sizeof err), err);
    for (size_t i = 0; i < n; i++)
        CHECK_MSG(a.turn[i] <= 1, "point %zu turns by %d quarters", (i + 1) % n, a.turn[i]);
    CHECK_EQ_INT(turn_sum(&a), 4);
    CHECK(consistent(&a));
    texopt_axis_angles_destroy(&a);
}

TEST(bad_loops_are_refused)
{
    double cw[] = {0, 0, 0, 10, 10, 10, 10, 0};
    double dup[] = {0, 0, 10, 0, 10, 0, 10, 10, 0, 10};
    texopt_axis_angles a;
    char err[256];
    CHECK(texopt_axis_angles_compute(cw, 4, &a, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_axis_angles_compute(dup, 5, &a, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_axis_angles_compute(cw, 3, &a, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(a.theta == NULL);
}
