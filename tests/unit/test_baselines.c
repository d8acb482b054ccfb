/* test_baselines.c - SSP, Tewari and ARAP targets (engine/stage1/ssp.h, tewari.h, arap.h). */
#include <math.h>
#include <stdlib.h>

#include "arap.h"
#include "fixtures.h"
#include "mesh.h"
#include "ssp.h"
#include "test.h"
#include "tewari.h"

typedef texopt_status (*signal_targets_fn)(const texopt_model *, const texopt_mesh *, double, texopt_triangle_target *,
                                           char *, size_t);

static double centroid_u(const texopt_mesh *mesh, size_t t)
{
    double s = 0;
    for (int k = 0; k < 3; k++)
        s += mesh->texel[2 * mesh->triangle[3 * t + k]];
    return s / 3 / mesh->width;
}

/* On the "half" texture, flat-half triangles sit at lambda_min and detailed-half ones get
 * several times more area. */
static void check_half(signal_targets_fn fn)
{
    texopt_model *m = fixture_grid(8, 128, "half");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target *g = calloc(mesh->triangle_count, sizeof *g);
    CHECK(g);
    CHECK_OK(fn(m, mesh, 0.1, g, err, sizeof err), err);
    double flat_max = 0, detail_min = 1;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        double u = centroid_u(mesh, t), area = g[t].lambda1 * g[t].lambda2;
        CHECK(g[t].w_rotation == 0 && g[t].w_stretch == 1 && g[t].alpha == 0);
        CHECK(g[t].beta >= 0 && g[t].beta < 1.5707963267948966);
        /* Away from u = 0, where REPEAT wraps the detailed column onto the flat one. */
        if (u > 0.1 && u < 0.4)
            flat_max = fmax(flat_max, area);
        if (u > 0.6)
            detail_min = fmin(detail_min, area);
    }
    CHECK_NEAR(flat_max, 0.01, 1e-12); /* both directions at lambda_min = 0.1 */
    CHECK_MSG(detail_min > 0.1, "detail_min %g", detail_min);
    free(g);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(ssp_gives_the_flat_half_less_area)
{
    check_half(texopt_ssp_targets);
}

TEST(tewari_gives_the_flat_half_less_area)
{
    check_half(texopt_tewari_targets);
}

static void check_flat(signal_targets_fn fn)
{
    texopt_model *m = fixture_grid(4, 64, "flat");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target g[32];
    CHECK_EQ_INT(mesh->triangle_count, 32);
    CHECK_OK(fn(m, mesh, 0.2, g, err, sizeof err), err);
    for (size_t t = 0; t < 32; t++) {
        CHECK(g[t].lambda1 == 1 && g[t].lambda2 == 1 && g[t].beta == 0);
        CHECK(g[t].w_stretch == 1);
    }
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(ssp_flat_texture_gives_equal_targets)
{
    check_flat(texopt_ssp_targets);
}

TEST(tewari_flat_texture_gives_equal_targets)
{
    check_flat(texopt_tewari_targets);
}

TEST(ssp_metric_is_in_texel_units)
{
    /* "gradient": r = (x + 0.5)/W, g = (y + 0.5)/H, so |dr/dx| = 1/W and |dg/dy| = 1/H per
     * texel, exactly, away from the wrapping border. */
    texopt_model *m = fixture_grid(8, 64, "gradient");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    double *metric = calloc(3 * mesh->triangle_count, sizeof *metric);
    CHECK(metric);
    CHECK_OK(texopt_ssp_metric(m, mesh, metric, err, sizeof err), err);
    int checked = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], mesh->texel[2 * mesh->triangle[3 * t + k] + a]);
                hi[a] = fmax(hi[a], mesh->texel[2 * mesh->triangle[3 * t + k] + a]);
            }
        if (lo[0] < 2 || lo[1] < 2 || hi[0] > 62 || hi[1] > 62)
            continue;
        CHECK_NEAR(metric[3 * t], 1.0 / 4096, 1e-9);
        CHECK_NEAR(metric[3 * t + 1], 0, 1e-9);
        CHECK_NEAR(metric[3 * t + 2], 1.0 / 4096, 1e-9);
        checked++;
    }
    CHECK(checked >= 18);
    /* A linear ramp has no second derivative: Tewari sees nothing there. */
    CHECK_OK(texopt_tewari_metric(m, mesh, metric, err, sizeof err), err);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        double u = centroid_u(mesh, t);
        if (u > 0.2 && u < 0.8 && metric[3 * t + 2] < 1e-6)
            CHECK_NEAR(metric[3 * t], 0, 1e-9);
    }
    free(metric);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(ssp_stripes_stretch_across_the_stripes)
{
    /* Vertical stripes change along x only: the x direction keeps its texels, y shrinks. */
    texopt_model *m = fixture_grid(4, 64, "stripes0");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target *g = calloc(mesh->triangle_count, sizeof *g);
    CHECK(g);
    CHECK_OK(texopt_ssp_targets(m, mesh, 0.1, g, err, sizeof err), err);
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        CHECK_NEAR(g[t].beta, 0, 1e-9);
        CHECK_NEAR(g[t].lambda1, 1, 1e-6); /* float texels: equal up to rounding */
        CHECK_NEAR(g[t].lambda2, 0.1, 1e-9);
    }
    free(g);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(arap_targets_undo_a_stretched_input)
{
    /* The 3D quad is twice as wide as its texture square: an isometric layout must widen x
     * by sqrt(2) and narrow y by sqrt(2) at the same total area. */
    const float pos[] = {0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0};
    const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3};
    texopt_model *m = fixture_model_from_arrays(pos, uv, 4, tri, 2, 64, 64, "flat");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target g[2];
    CHECK_OK(texopt_arap_targets(mesh, g, err, sizeof err), err);
    for (int t = 0; t < 2; t++) {
        CHECK_NEAR(g[t].beta, 0, 1e-9);
        CHECK_NEAR(g[t].lambda1, sqrt(2.0), 1e-9);
        CHECK_NEAR(g[t].lambda2, 1 / sqrt(2.0), 1e-9);
        CHECK(g[t].w_rotation == 0 && g[t].w_stretch == 1);
    }
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(arap_targets_of_an_isometric_input_are_identity)
{
    /* Mirrored in u as exporters do for symmetric halves: still the identity. */
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const float uv[] = {1, 0, 0, 0, 0, 1, 1, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3};
    texopt_model *m = fixture_model_from_arrays(pos, uv, 4, tri, 2, 32, 32, "flat");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target g[2];
    CHECK_OK(texopt_arap_targets(mesh, g, err, sizeof err), err);
    for (int t = 0; t < 2; t++) {
        CHECK_NEAR(g[t].lambda1, 1, 1e-9);
        CHECK_NEAR(g[t].lambda2, 1, 1e-9);
    }
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(baselines_refuse_bad_arguments)
{
    char err[256] = "";
    texopt_triangle_target g[1];
    CHECK(texopt_arap_targets(NULL, g, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_ssp_targets(NULL, NULL, 0.1, g, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_model *m = fixture_grid(2, 16, "flat");
    CHECK(m);
    texopt_mesh *mesh = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target gg[8];
    CHECK(texopt_tewari_targets(m, mesh, 1.5, gg, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    /* An undecoded image cannot be measured. */
    texopt_image_destroy(&m->images[0]);
    CHECK(texopt_ssp_targets(m, mesh, 0.1, gg, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}
