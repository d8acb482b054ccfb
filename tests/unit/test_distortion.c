/* test_distortion.c - symmetric Dirichlet distortion and flip counting (engine/param/distortion.c)
 * on hand-built meshes whose exact values follow from the definition. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "distortion.h"
#include "handmesh.h"
#include "test.h"

/* An n x n grid on a tilted plane in 3D (so the 3D frame is not the texel frame), texels
 * = 10 x the in-plane coordinates: an isometry up to scale. */
static texopt_mesh *tilted_grid(int n)
{
    size_t nv = (size_t)(n + 1) * (n + 1), nt = 2 * (size_t)n * n;
    texopt_mesh *m = handmesh_alloc(nv, nt);
    double c = cos(0.7), s = sin(0.7);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t v = (size_t)j * (n + 1) + i;
            double x = i * 0.1 + 0.013 * ((i * 7 + j * 3) % 5), y = j * 0.1 + 0.011 * ((i * 2 + j * 5) % 4);
            m->texel[2 * v] = 10.0 * x;
            m->texel[2 * v + 1] = 10.0 * y;
            m->position[3 * v] = x;
            m->position[3 * v + 1] = c * y; /* plane rotated about the x axis */
            m->position[3 * v + 2] = s * y;
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            size_t t = 2 * ((size_t)j * n + i);
            uint32_t a = (uint32_t)((size_t)j * (n + 1) + i), b = a + 1, d = a + (uint32_t)(n + 1), e = d + 1;
            uint32_t tris[6] = {a, b, e, a, e, d};
            memcpy(m->triangle + 3 * t, tris, sizeof tris);
        }
    handmesh_finish(m);
    return m;
}

TEST(isometric_layout_measures_four_at_any_resolution)
{
    texopt_mesh *m = tilted_grid(6);
    texopt_distortion d;
    char err[256] = "";
    CHECK_OK(texopt_distortion_measure(m, NULL, &d, err, sizeof err), err);
    CHECK_NEAR(d.symmetric_dirichlet, 4.0, 1e-9);
    CHECK_NEAR(d.max_symmetric_dirichlet, 4.0, 1e-9);
    CHECK_EQ_INT(d.counted, m->triangle_count);
    CHECK_EQ_INT(d.flipped, 0);
    /* A rotated, 3x smaller copy of the layout is still an isometry up to scale. */
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    for (size_t v = 0; v < m->vertex_count; v++) {
        double x = m->texel[2 * v], y = m->texel[2 * v + 1];
        out[2 * v] = (0.6 * x - 0.8 * y) / 3.0 + 50.0;
        out[2 * v + 1] = (0.8 * x + 0.6 * y) / 3.0;
    }
    CHECK_OK(texopt_distortion_measure(m, out, &d, err, sizeof err), err);
    CHECK_NEAR(d.symmetric_dirichlet, 4.0, 1e-9);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(two_to_one_stretch_measures_five)
{
    /* Stretch x by 2: after area normalisation J = diag(sqrt 2, 1/sqrt 2), so
     * |J|^2 + |J^-1|^2 = (2 + 1/2) + (1/2 + 2) = 5 on every triangle. */
    texopt_mesh *m = tilted_grid(5);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    for (size_t v = 0; v < m->vertex_count; v++) {
        out[2 * v] = 2.0 * m->texel[2 * v];
        out[2 * v + 1] = m->texel[2 * v + 1];
    }
    texopt_distortion d;
    char err[256] = "";
    CHECK_OK(texopt_distortion_measure(m, out, &d, err, sizeof err), err);
    CHECK_NEAR(d.symmetric_dirichlet, 5.0, 1e-9);
    /* The lecture's other metrics of diag(sqrt 2, 1/sqrt 2), the same on every triangle. */
    CHECK_NEAR(d.conformal.mean, 2.0, 1e-9);
    CHECK_NEAR(d.mips.mean, 2.5, 1e-9);
    CHECK_NEAR(d.isometric.mean, 2.0, 1e-9);
    CHECK_NEAR(d.max_isometric.max, sqrt(2.0), 1e-9);
    CHECK_NEAR(d.area.max, 1.0, 1e-9);
    CHECK_NEAR(d.l2_stretch.mean, sqrt(1.25), 1e-9);
    CHECK_NEAR(d.linf_stretch.max, sqrt(2.0), 1e-9);
    /* Stretch 2x only on one half: area normalisation makes it uneven; the mean lies
     * strictly between the two pure cases and above 4. */
    for (size_t v = 0; v < m->vertex_count; v++)
        out[2 * v] = m->texel[2 * v] < 2.5 ? m->texel[2 * v] : 2.5 + 2.0 * (m->texel[2 * v] - 2.5);
    CHECK_OK(texopt_distortion_measure(m, out, &d, err, sizeof err), err);
    CHECK(d.symmetric_dirichlet > 4.05);
    CHECK(d.max_symmetric_dirichlet > d.symmetric_dirichlet);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(flips_are_judged_against_the_input_orientation)
{
    texopt_mesh *m = tilted_grid(4);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    /* A mirrored copy of the layout flips every triangle. */
    for (size_t v = 0; v < m->vertex_count; v++) {
        out[2 * v] = -m->texel[2 * v];
        out[2 * v + 1] = m->texel[2 * v + 1];
    }
    CHECK_EQ_INT(texopt_count_flipped(m, out), m->triangle_count);
    /* Now make the mirrored layout the input: the same positions are then unflipped. */
    double *mirrored = malloc(2 * m->vertex_count * sizeof *mirrored);
    memcpy(mirrored, out, 2 * m->vertex_count * sizeof *out);
    memcpy(out, m->texel, 2 * m->vertex_count * sizeof *out);
    memcpy(m->texel, mirrored, 2 * m->vertex_count * sizeof *out);
    CHECK_EQ_INT(texopt_count_flipped(m, NULL), 0);
    CHECK_EQ_INT(texopt_count_flipped(m, mirrored), 0);
    CHECK_EQ_INT(texopt_count_flipped(m, out), m->triangle_count);
    /* Push interior vertex 6 (i=1, j=1) past its neighbours: exactly the triangles around it
     * that turn over are counted. */
    memcpy(out, mirrored, 2 * m->vertex_count * sizeof *out);
    out[2 * 6] -= 15.0;
    size_t flipped = texopt_count_flipped(m, out);
    CHECK(flipped >= 1 && flipped < 6);
    texopt_distortion d;
    char err[256] = "";
    CHECK_OK(texopt_distortion_measure(m, out, &d, err, sizeof err), err);
    CHECK_EQ_INT(d.flipped, flipped);
    CHECK(isinf(d.symmetric_dirichlet));
    free(mirrored);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(degenerate_triangles_are_not_counted_and_bad_input_fails)
{
    texopt_mesh *m = tilted_grid(3);
    m->flags[0] = TEXOPT_TRI_DEGENERATE_3D;
    m->flags[1] = TEXOPT_TRI_DEGENERATE_UV;
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    memcpy(out, m->texel, 2 * m->vertex_count * sizeof *out);
    texopt_distortion d;
    char err[256] = "";
    CHECK_OK(texopt_distortion_measure(m, out, &d, err, sizeof err), err);
    CHECK_EQ_INT(d.counted, m->triangle_count - 2);
    CHECK_NEAR(d.symmetric_dirichlet, 4.0, 1e-9);
    out[3] = NAN;
    CHECK_EQ_INT(texopt_distortion_measure(m, out, &d, err, sizeof err), TEXOPT_E_NUMERIC);
    for (size_t t = 0; t < m->triangle_count; t++)
        m->flags[t] = TEXOPT_TRI_DEGENERATE_3D;
    CHECK_EQ_INT(texopt_distortion_measure(m, NULL, &d, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK_EQ_INT(texopt_distortion_measure(NULL, NULL, &d, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    free(out);
    texopt_mesh_destroy(m);
}

/* J = R(0.4) diag(3, 0.5) R(-1.1): every metric is a function of the singular values 3 and
 * 0.5 alone, whatever the rotations. */
TEST(triangle_metrics_follow_the_singular_values)
{
    double c1 = cos(0.4), s1 = sin(0.4), c2 = cos(-1.1), s2 = sin(-1.1);
    double A[2][2] = {{3.0 * c1, -0.5 * s1}, {3.0 * s1, 0.5 * c1}};
    double J[2][2] = {{A[0][0] * c2 + A[0][1] * s2, -A[0][0] * s2 + A[0][1] * c2},
                      {A[1][0] * c2 + A[1][1] * s2, -A[1][0] * s2 + A[1][1] * c2}};
    texopt_triangle_distortion d;
    texopt_triangle_distortion_of(J, &d);
    CHECK_NEAR(d.sigma_max, 3.0, 1e-12);
    CHECK_NEAR(d.sigma_min, 0.5, 1e-12);
    CHECK_NEAR(d.conformal, 6.0, 1e-12);
    CHECK_NEAR(d.mips, 6.0 + 1.0 / 6.0, 1e-12);
    CHECK_NEAR(d.isometric, sqrt(13.0), 1e-12);
    CHECK_NEAR(d.max_isometric, 3.0, 1e-12);
    CHECK_NEAR(d.area, 1.5, 1e-12);
    CHECK_NEAR(d.symmetric_dirichlet, 9.0 + 0.25 + 1.0 / 9.0 + 4.0, 1e-12);
    CHECK_NEAR(d.l2_stretch, sqrt((4.0 + 1.0 / 9.0) / 2.0), 1e-12);
    CHECK_NEAR(d.linf_stretch, 2.0, 1e-12);
    /* A mirror (det < 0) is not a valid map of the triangle. */
    double M[2][2] = {{J[0][0], J[0][1]}, {-J[1][0], -J[1][1]}};
    texopt_triangle_distortion_of(M, &d);
    CHECK(isinf(d.conformal) && isinf(d.l2_stretch) && isinf(d.area));
    /* Area only: J = diag(2, 2) keeps angles and doubles lengths. */
    double S[2][2] = {{2.0, 0.0}, {0.0, 2.0}};
    texopt_triangle_distortion_of(S, &d);
    CHECK_NEAR(d.conformal, 1.0, 1e-12);
    CHECK_NEAR(d.mips, 2.0, 1e-12);
    CHECK_NEAR(d.area, 4.0, 1e-12);
    CHECK_NEAR(d.l2_stretch, 0.5, 1e-12);
}

TEST(metrics_json_writes_null_for_infinity)
{
    texopt_distortion d = {0};
    d.symmetric_dirichlet = d.max_symmetric_dirichlet = INFINITY;
    d.conformal = (texopt_distortion_stat){1.5, 2.5};
    d.flipped = 3;
    cJSON *o = texopt_distortion_json(&d);
    CHECK(o != NULL);
    CHECK(cJSON_IsNull(cJSON_GetObjectItem(cJSON_GetObjectItem(o, "symmetric_dirichlet"), "mean")));
    CHECK_NEAR(cJSON_GetObjectItem(cJSON_GetObjectItem(o, "conformal"), "max")->valuedouble, 2.5, 0);
    CHECK_NEAR(cJSON_GetObjectItem(o, "flipped")->valuedouble, 3, 0);
    cJSON_Delete(o);
}
