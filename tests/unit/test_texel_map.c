/* test_texel_map.c - one triangle's texel map, its rotation and the normal-map turn
 * (engine/core/texel_map.h). */
#include <math.h>

#include "test.h"
#include "texel_map.h"

/* `to` is `from` turned by 30 degrees and stretched 2x along x before the turn: m = d from /
 * d to is the inverse, and its rotation part is -30 degrees whatever the stretch. */
TEST(rotation_of_a_stretched_and_turned_map)
{
    const double from[3][2] = {{1, 2}, {4, 2}, {1, 7}};
    const double t = 30.0 * 3.14159265358979323846 / 180.0, c = cos(t), s = sin(t);
    double to[3][2];
    for (int k = 0; k < 3; k++) {
        double x = 2.0 * from[k][0], y = from[k][1];
        to[k][0] = c * x - s * y + 5;
        to[k][1] = s * x + c * y - 3;
    }
    double m[4], area2, rc, rs;
    CHECK(texopt_texel_map(from, (const double(*)[2])to, m, &area2) == 1);
    CHECK_NEAR(area2, 2 * 15, 1e-9); /* from: twice area 15; the stretch doubles it */
    /* m applied to a `to` edge gives the `from` edge. */
    CHECK_NEAR(m[0] * (to[1][0] - to[0][0]) + m[1] * (to[1][1] - to[0][1]), 3, 1e-9);
    CHECK_NEAR(m[2] * (to[2][0] - to[0][0]) + m[3] * (to[2][1] - to[0][1]), 5, 1e-9);
    texopt_texel_map_rotation(m, &rc, &rs);
    CHECK_NEAR(rc, c, 1e-9);
    CHECK_NEAR(rs, -s, 1e-9);
}

TEST(degenerate_triangle_has_no_map)
{
    const double from[3][2] = {{0, 0}, {1, 0}, {0, 1}}, to[3][2] = {{0, 0}, {1, 1}, {2, 2}};
    double m[4] = {7, 7, 7, 7}, area2 = 1;
    CHECK(texopt_texel_map(from, to, m, &area2) == 0);
    CHECK_NEAR(area2, 0, 1e-12);
    CHECK(m[0] == 7 && m[3] == 7);
}

/* A quarter turn sends X = +1 to Y = +1 (decoded), Z untouched; (c, -s) brings it back. */
TEST(normal_turn_and_its_inverse)
{
    float xy[3] = {1.0f, 0.5f, 0.25f};
    texopt_normal_turn(0, 1, xy);
    CHECK_NEAR(xy[0], 0.5, 1e-6);
    CHECK_NEAR(xy[1], 1.0, 1e-6);
    CHECK_NEAR(xy[2], 0.25, 0);
    float v[2] = {0.8f, 0.3f};
    double t = 1.1;
    texopt_normal_turn(cos(t), sin(t), v);
    texopt_normal_turn(cos(t), -sin(t), v);
    CHECK_NEAR(v[0], 0.8, 1e-6);
    CHECK_NEAR(v[1], 0.3, 1e-6);
}
