/* test_param_lscm.c - least squares conformal maps (engine/param/param_lscm.c) on generated grids. */
#include <math.h>
#include <stdlib.h>

#include "distortion.h"
#include "param_grids.h"
#include "param_lscm.h"
#include "test.h"
#include "vec3.h"

TEST(planar_patch_is_reproduced_up_to_similarity)
{
    param_grid *g = param_grid_create(10, SHAPE_TILTED_PLANE, 17);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    CHECK_OK(texopt_param_lscm(&g->chart, uv, err, sizeof err), err);
    double scale = 0.0;
    CHECK(param_similarity_residual(g, uv, &scale) < 1e-9);
    /* The pinned pair keeps its 3D distance and the plane is isometric to the grid. */
    CHECK_NEAR(scale, 1.0, 1e-9);
    CHECK_EQ_INT(param_layout_flips(&g->chart, uv), 0);
    free(uv);
    param_grid_destroy(g);
}

TEST(curved_patch_is_nearly_conformal)
{
    param_grid *g = param_grid_create(12, SHAPE_BUMP, 0);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    CHECK_OK(texopt_param_lscm(&g->chart, uv, err, sizeof err), err);
    CHECK_EQ_INT(param_layout_flips(&g->chart, uv), 0);
    double l2, linf;
    CHECK(texopt_param_stretch(&g->chart, uv, &l2, &linf, NULL) == 0);
    CHECK(l2 > 1.0 && l2 < 1.5);
    /* The mean conformal distortion (smax / smin) stays near 1: the bump is smooth. */
    double worst = 0.0;
    for (size_t t = 0; t < g->chart.triangle_count; t++) {
        const uint32_t *v = g->chart.triangle + 3 * t;
        double P[2][2], T[2][2], J[2][2];
        texopt_plane_edges(g->position + 3 * (size_t)v[0], g->position + 3 * (size_t)v[1],
                           g->position + 3 * (size_t)v[2], P);
        texopt_layout_edges(uv, v, T);
        texopt_jacobian(T, P, 1.0, J);
        texopt_triangle_distortion d;
        texopt_triangle_distortion_of(J, &d);
        worst = fmax(worst, d.conformal);
    }
    CHECK(worst < 1.6);
    free(uv);
    param_grid_destroy(g);
}
