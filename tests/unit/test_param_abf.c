/* test_param_abf.c - linear ABF with least-squares reconstruction (engine/param/param_abf.c). */
#include <math.h>
#include <stdlib.h>

#include "param_abf.h"
#include "param_grids.h"
#include "param_tutte.h"
#include "test.h"

static double layout_length(const double *uv, uint32_t a, uint32_t b)
{
    return hypot(uv[2 * (size_t)a] - uv[2 * (size_t)b], uv[2 * (size_t)a + 1] - uv[2 * (size_t)b + 1]);
}

/* A rolled sheet is developable: its 3D angles are already flat, ABF keeps them (zero angle
 * error) and the reconstruction unrolls it isometrically. */
TEST(developable_patch_keeps_its_angles_and_lengths)
{
    param_grid *g = param_grid_create(10, SHAPE_CYLINDER, 3);
    double *uv = malloc(2 * g->chart.vertex_count * sizeof *uv);
    char err[256] = "";
    texopt_abf_report rep;
    CHECK_OK(texopt_param_abf(&g->chart, uv, &rep, err, sizeof err), err);
    CHECK(rep.max_angle_change < 1e-10);
    CHECK(rep.max_angle_error < 1e-9);
    CHECK_EQ_INT(param_layout_flips(&g->chart, uv), 0);
    for (size_t t = 0; t < g->chart.triangle_count; t++) {
        double e[3];
        texopt_param_edge_lengths(&g->chart, t, e);
        const uint32_t *v = g->chart.triangle + 3 * t;
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(layout_length(uv, v[(k + 1) % 3], v[(k + 2) % 3]), e[k], 1e-9);
    }
    free(uv);
    param_grid_destroy(g);
}

static double mean_conformal(const texopt_param_chart *chart, const double *uv)
{
    double sum = 0.0;
    for (size_t t = 0; t < chart->triangle_count; t++) {
        double a3[3];
        texopt_param_corner_angles(chart, t, a3);
        const uint32_t *v = chart->triangle + 3 * t;
        for (int k = 0; k < 3; k++) {
            const double *p = uv + 2 * (size_t)v[k], *q = uv + 2 * (size_t)v[(k + 1) % 3],
                         *r = uv + 2 * (size_t)v[(k + 2) % 3];
            double e1[2] = {q[0] - p[0], q[1] - p[1]}, e2[2] = {r[0] - p[0], r[1] - p[1]};
            double a2 = atan2(e1[0] * e2[1] - e1[1] * e2[0], e1[0] * e2[0] + e1[1] * e2[1]);
            sum += fabs(a2 - a3[k]);
        }
    }
    return sum / (3.0 * (double)chart->triangle_count);
}

/* On a curved patch the angles must change; the layout realises the flattened angles closely,
 * does not flip, and keeps angles better than a circle-bounded Tutte map. */
TEST(curved_patch_flattens_without_flips_and_beats_tutte_on_angles)
{
    param_grid *g = param_grid_create(12, SHAPE_BUMP, 0);
    size_t nv = g->chart.vertex_count;
    double *uv = malloc(2 * nv * sizeof *uv), *tutte = malloc(2 * nv * sizeof *tutte);
    char err[256] = "";
    texopt_abf_report rep;
    CHECK_OK(texopt_param_abf(&g->chart, uv, &rep, err, sizeof err), err);
    CHECK(rep.max_angle_change > 1e-3);
    CHECK(rep.max_angle_error < 0.05);
    CHECK_EQ_INT(param_layout_flips(&g->chart, uv), 0);
    CHECK_OK(texopt_param_tutte(&g->chart, tutte, err, sizeof err), err);
    CHECK(mean_conformal(&g->chart, uv) < 0.5 * mean_conformal(&g->chart, tutte));
    free(uv);
    free(tutte);
    param_grid_destroy(g);
}
