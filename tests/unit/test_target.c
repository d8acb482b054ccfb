/* test_target.c - the stretch helpers of engine/core/target.h on matrices with known answers, and
 * the floor raising targets below a share of another's area. */
#include <math.h>

#include "target.h"
#include "test.h"

#define PI 3.14159265358979323846

/* R(t) diag(a, b) R(t)^T as [m0, m1, m2]. */
static void rotated_diagonal(double t, double a, double b, double m[3])
{
    double c = cos(t), s = sin(t);
    m[0] = a * c * c + b * s * s;
    m[1] = (a - b) * c * s;
    m[2] = a * s * s + b * c * c;
}

TEST(eigen_of_a_rotated_diagonal_gives_back_its_values_and_direction)
{
    double m[3], mu1, mu2, theta;
    rotated_diagonal(0.3, 4.0, 1.0, m);
    texopt_sym2_eigen(m, &mu1, &mu2, &theta);
    CHECK_NEAR(mu1, 4.0, 1e-12);
    CHECK_NEAR(mu2, 1.0, 1e-12);
    CHECK_NEAR(theta, 0.3, 1e-12);
    /* A direction in the second quadrant stays in [0, pi). */
    rotated_diagonal(2.5, 9.0, 0.25, m);
    texopt_sym2_eigen(m, &mu1, &mu2, &theta);
    CHECK_NEAR(mu1, 9.0, 1e-12);
    CHECK_NEAR(mu2, 0.25, 1e-12);
    CHECK_NEAR(theta, 2.5, 1e-12);
}

TEST(eigenvalues_are_clamped_at_zero)
{
    double m[3] = {-1e-18, 0.0, 2.0}, mu1, mu2, theta;
    texopt_sym2_eigen(m, &mu1, &mu2, &theta);
    CHECK_NEAR(mu1, 2.0, 1e-15);
    CHECK(mu2 == 0.0);
    CHECK_NEAR(theta, PI / 2, 1e-12);
}

TEST(stretch_direction_past_a_quarter_turn_swaps_the_scales)
{
    texopt_triangle_target g = {0};
    texopt_target_set_stretch(&g, 0.4, 0.9, 0.2);
    CHECK_NEAR(g.beta, 0.4, 0);
    CHECK_NEAR(g.lambda1, 0.9, 0);
    CHECK_NEAR(g.lambda2, 0.2, 0);
    texopt_target_set_stretch(&g, PI / 2 + 0.4, 0.9, 0.2);
    CHECK_NEAR(g.beta, 0.4, 1e-15);
    CHECK_NEAR(g.lambda1, 0.2, 0);
    CHECK_NEAR(g.lambda2, 0.9, 0);
}

/* Below k^2 of the floor's area a target takes k times the floor's values and axes, keeping
 * its rotation and weights; at or above it, it is left as it is. */
TEST(a_floor_raises_only_the_targets_below_k_squared_of_its_area)
{
    texopt_triangle_target t[3] = {
        {.alpha = 0.2, .lambda1 = 0.1, .lambda2 = 0.1, .beta = 0.3, .loss = 0.5, .w_rotation = 2, .w_stretch = 3},
        {.lambda1 = 0.5, .lambda2 = 0.125, .beta = 0.1}, /* 0.0625: exactly k^2 times the floor's */
        {.lambda1 = 1.0, .lambda2 = 0.05, .beta = 0.2},  /* 0.05: below, though one value is not */
    };
    const texopt_triangle_target floor[3] = {
        {.lambda1 = 0.8, .lambda2 = 0.4, .beta = 1.0},
        {.lambda1 = 0.5, .lambda2 = 0.5, .beta = 1.0},
        {.lambda1 = 0.5, .lambda2 = 0.5, .beta = 1.2},
    };
    CHECK_EQ_INT(texopt_targets_raise_to_floor(t, floor, 3, 0.5), 2);
    CHECK_NEAR(t[0].lambda1, 0.4, 0);
    CHECK_NEAR(t[0].lambda2, 0.2, 0);
    CHECK_NEAR(t[0].beta, 1.0, 0);
    CHECK(t[0].alpha == 0.2 && t[0].loss == 0.5 && t[0].w_rotation == 2 && t[0].w_stretch == 3);
    CHECK(t[1].lambda1 == 0.5 && t[1].lambda2 == 0.125 && t[1].beta == 0.1);
    CHECK(t[2].lambda1 == 0.25 && t[2].lambda2 == 0.25 && t[2].beta == 1.2);
    /* Raised targets are at the floor: a second pass raises none. */
    CHECK_EQ_INT(texopt_targets_raise_to_floor(t, floor, 3, 0.5), 0);
}
