/* Tests of budget.c on generated meshes: the packed cost lands within 2% of c_r c(input)
 * (measured here independently with coverage.h), a texture size is filled as far as it can
 * be (a 1% larger scale no longer fits), and bad requests are refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "budget.h"
#include "coverage.h"
#include "fixtures.h"
#include "mesh.h"
#include "test.h"

static texopt_mesh *mesh_of(texopt_model *model)
{
    texopt_mesh *mesh = NULL;
    if (!model || texopt_mesh_create(&mesh, model, 0, NULL, 0) != TEXOPT_OK)
        return NULL;
    return mesh;
}

static double packed_cost(const texopt_mesh *mesh, const double *texel, int w, int h)
{
    texopt_coverage_options o = {0};
    o.texel = texel;
    o.width = w;
    o.height = h;
    texopt_coverage c;
    if (texopt_coverage_measure(mesh, &o, &c, NULL, 0) != TEXOPT_OK)
        return -1;
    return (double)c.covered_texels;
}

static void check_relative_cost(const char *what, texopt_model *model, double cr)
{
    texopt_mesh *mesh = mesh_of(model);
    CHECK(mesh != NULL);
    texopt_coverage in;
    char err[256] = "";
    CHECK_OK(texopt_coverage_measure(mesh, NULL, &in, err, sizeof err), err);
    texopt_budget_request req = {0};
    req.kind = TEXOPT_BUDGET_RELATIVE_COST;
    req.relative_cost = cr;
    req.input_cost = (double)in.covered_texels;
    req.input_width = mesh->width;
    req.input_height = mesh->height;
    double *out = malloc(sizeof(double) * 2 * mesh->vertex_count);
    texopt_budget_result res;
    CHECK_OK(texopt_budget_fit(mesh, mesh->texel, &req, out, &res, err, sizeof err), err);
    double cost = packed_cost(mesh, out, res.width, res.height);
    CHECK_MSG(fabs(cost / (cr * (double)in.covered_texels) - 1) <= 0.02, "%s: cost %.0f for target %.0f",
              what, cost, cr * (double)in.covered_texels);
    CHECK_NEAR(res.cost, cost, 0.5);
    CHECK_NEAR(res.relative_cost, cost / (double)in.covered_texels, 1e-12);
    CHECK(res.width % 4 == 0 && res.height % 4 == 0);
    CHECK_NEAR(res.packing_efficiency, cost / ((double)res.width * res.height), 1e-12);
    for (size_t v = 0; v < 2 * mesh->vertex_count; v++)
        CHECK(out[v] >= 0 && out[v] <= (v % 2 ? res.height : res.width));
    free(out);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(half_relative_cost_of_a_sphere_is_within_two_percent)
{
    check_relative_cost("sphere 0.5", fixture_uv_sphere(24, 12, 256), 0.5);
}

TEST(relative_costs_of_a_seamed_cube_are_within_two_percent)
{
    check_relative_cost("cube 0.5", fixture_cube_with_seams(256), 0.5);
    check_relative_cost("cube 0.2", fixture_cube_with_seams(256), 0.2);
    check_relative_cost("cube 1.5", fixture_cube_with_seams(128), 1.5);
}

TEST(texture_size_is_filled_as_far_as_the_packer_allows)
{
    texopt_model *model = fixture_cube_with_seams(256);
    texopt_mesh *mesh = mesh_of(model);
    CHECK(mesh != NULL);
    texopt_budget_request req = {0};
    req.kind = TEXOPT_BUDGET_TEXTURE_SIZE;
    req.texture_width = 96;
    req.texture_height = 64;
    req.input_cost = 6.0 * 64 * 64;
    req.input_width = req.input_height = 256;
    double *out = malloc(sizeof(double) * 2 * mesh->vertex_count);
    texopt_budget_result res;
    char err[256] = "";
    CHECK_OK(texopt_budget_fit(mesh, mesh->texel, &req, out, &res, err, sizeof err), err);
    CHECK_EQ_INT(res.width, 96);
    CHECK_EQ_INT(res.height, 64);
    /* The cube's charts are a strip of four faces and two single faces (side S each). With
     * 2-texel pads a footprint spans floor(extent + 4) + 1 cells, so the strip fits 96
     * columns while 4 S + 4 < 96: S < 23; the two rows (strip, then the two squares) need
     * only 2 (S + 5) <= 64. The bisection must end just below 23. */
    double side = res.scale * 64.0;
    CHECK_MSG(side > 22.9 && side < 23.0, "face side %.4f", side);
    /* One percent more scale no longer fits. */
    double *bigger = malloc(sizeof(double) * 2 * mesh->vertex_count);
    for (size_t i = 0; i < 2 * mesh->vertex_count; i++)
        bigger[i] = mesh->texel[i] * res.scale * 1.01;
    texopt_pack_result pr;
    int fits = 1;
    CHECK_OK(texopt_pack_charts(mesh, bigger, 96, 64, NULL, out, &pr, &fits, err, sizeof err), err);
    CHECK(fits == 0);
    texopt_pack_result_destroy(&pr);
    free(bigger);
    free(out);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(budget_refuses_impossible_requests)
{
    texopt_model *model = fixture_textured_quad(64, "flat");
    texopt_mesh *mesh = mesh_of(model);
    CHECK(mesh != NULL);
    double *out = malloc(sizeof(double) * 2 * mesh->vertex_count);
    texopt_budget_result res;
    char err[256] = "";
    texopt_budget_request req = {0};
    req.kind = TEXOPT_BUDGET_RELATIVE_COST;
    req.relative_cost = 0.5;
    req.input_cost = 0; /* unknown input cost */
    req.input_width = req.input_height = 64;
    CHECK(texopt_budget_fit(mesh, mesh->texel, &req, out, &res, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    req.input_cost = 4096;
    req.relative_cost = 1e6; /* needs a texture far past 16384 a side */
    CHECK(texopt_budget_fit(mesh, mesh->texel, &req, out, &res, err, sizeof err) == TEXOPT_E_LIMIT);
    free(out);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(budget_stops_when_canceled)
{
    texopt_model *model = fixture_cube_with_seams(64);
    texopt_mesh *mesh = mesh_of(model);
    CHECK(mesh != NULL);
    atomic_int cancel = 1;
    texopt_monitor mon = {NULL, NULL, &cancel};
    texopt_budget_request req = {0};
    req.kind = TEXOPT_BUDGET_RELATIVE_COST;
    req.relative_cost = 0.5;
    req.input_cost = 6.0 * 16 * 16;
    req.input_width = req.input_height = 64;
    req.monitor = &mon;
    double *out = malloc(sizeof(double) * 2 * mesh->vertex_count);
    texopt_budget_result res;
    char err[256] = "";
    CHECK(texopt_budget_fit(mesh, mesh->texel, &req, out, &res, err, sizeof err) == TEXOPT_E_CANCELED);
    free(out);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}
