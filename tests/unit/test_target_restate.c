/* test_target_restate.c - targets restated for another layout (engine/layout/target_restate.c).
 *
 * One triangle laid out twice, the second layout a known linear map A of the first: a
 * target J found for the first must ask the same output of the second, J' = J A^-1. */
#include <math.h>
#include <string.h>

#include "handmesh.h"
#include "target_restate.h"
#include "test.h"
#include "triloss.h"

static const double corner[6] = {10, 20, 18, 21, 12, 26};

/* A one-triangle mesh with corners A x (x the corners above). */
static texopt_mesh *triangle_mapped(const double A[4])
{
    texopt_mesh *m = handmesh_alloc(3, 1);
    for (uint32_t v = 0; v < 3; v++) {
        m->triangle[v] = v;
        m->texel[2 * v] = A[0] * corner[2 * v] + A[1] * corner[2 * v + 1];
        m->texel[2 * v + 1] = A[2] * corner[2 * v] + A[3] * corner[2 * v + 1];
        m->position[3 * v] = corner[2 * v];
        m->position[3 * v + 1] = corner[2 * v + 1];
    }
    handmesh_finish(m);
    return m;
}

/* The output edges (b - a, c - a) the target asks of mesh's triangle, 4 numbers. */
static void asked_edges(const texopt_mesh *m, const texopt_triangle_target *g, double out[4])
{
    double J[4];
    texopt_jacobian_from_params(g->alpha, g->lambda1, g->lambda2, g->beta, J);
    for (int e = 0; e < 2; e++) {
        double dx = m->texel[2 * (e + 1)] - m->texel[0], dy = m->texel[2 * (e + 1) + 1] - m->texel[1];
        out[2 * e] = J[0] * dx + J[1] * dy;
        out[2 * e + 1] = J[2] * dx + J[3] * dy;
    }
}

static texopt_triangle_target known_target(void)
{
    texopt_triangle_target g = {0};
    g.alpha = 0.3;
    g.lambda1 = 1.0;
    g.lambda2 = 0.4;
    g.beta = 0.5;
    g.w_rotation = 2.0;
    g.w_stretch = 1.0;
    return g;
}

TEST(a_restated_target_asks_the_same_output_of_the_new_layout)
{
    const double I[4] = {1, 0, 0, 1};
    const double c = cos(1.1), s = sin(1.1), A[4] = {1.7 * c, -0.8 * s, 1.7 * s, 0.8 * c}; /* turn + stretch */
    texopt_mesh *in = triangle_mapped(I), *out = triangle_mapped(A);
    texopt_triangle_target g = known_target();
    double want[4], got[4];
    asked_edges(in, &g, want);
    texopt_targets_restate(in, out, &g);
    asked_edges(out, &g, got);
    /* rotation targets are defined up to a quarter turn (target.h: alpha in [0, pi/2)) */
    int turns = 0;
    while (turns < 4 && !(fabs(got[0] - want[0]) < 1e-8 && fabs(got[1] - want[1]) < 1e-8)) {
        for (int e = 0; e < 2; e++) {
            double x = got[2 * e];
            got[2 * e] = -got[2 * e + 1];
            got[2 * e + 1] = x;
        }
        turns++;
    }
    CHECK(turns < 4);
    for (int k = 0; k < 4; k++)
        CHECK_NEAR(got[k], want[k], 1e-8);
    CHECK_NEAR(g.w_rotation, 2.0, 0);
    CHECK(g.alpha >= 0 && g.alpha < 1.5707963267948966);
    texopt_mesh_destroy(in);
    texopt_mesh_destroy(out);
}

TEST(a_mirroring_map_keeps_the_stretch_and_drops_the_rotation)
{
    const double I[4] = {1, 0, 0, 1}, A[4] = {2, 0, 0, -0.5}; /* mirrored in y */
    texopt_mesh *in = triangle_mapped(I), *out = triangle_mapped(A);
    texopt_triangle_target g = known_target();
    double J[4];
    texopt_jacobian_from_params(g.alpha, g.lambda1, g.lambda2, g.beta, J);
    texopt_targets_restate(in, out, &g);
    CHECK_NEAR(g.w_rotation, 0, 0);
    /* singular values of J A^-1 */
    double M[4] = {J[0] / 2, J[1] / -0.5, J[2] / 2, J[3] / -0.5};
    double t = M[0] * M[0] + M[1] * M[1] + M[2] * M[2] + M[3] * M[3], d = fabs(M[0] * M[3] - M[1] * M[2]);
    double s1 = sqrt(0.5 * (t + sqrt(t * t - 4 * d * d))), s2 = d / s1;
    CHECK_NEAR(fmax(g.lambda1, g.lambda2), s1, 1e-9);
    CHECK_NEAR(fmin(g.lambda1, g.lambda2), s2, 1e-9);
    texopt_mesh_destroy(in);
    texopt_mesh_destroy(out);
}

TEST(a_triangle_the_layout_does_not_move_keeps_its_target_exactly)
{
    const double I[4] = {1, 0, 0, 1};
    texopt_mesh *in = triangle_mapped(I), *out = triangle_mapped(I);
    texopt_triangle_target g = known_target(), before = g;
    texopt_targets_restate(in, out, &g);
    CHECK(memcmp(&g, &before, sizeof g) == 0);
    texopt_mesh_destroy(in);
    texopt_mesh_destroy(out);
}
