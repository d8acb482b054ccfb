/* Tests of metric_maps.c: the signal metrics' targets from every map of a domain, each
 * triangle its most demanding map's (issue 45, item 4). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "lit_weight.h"
#include "metric_maps.h"
#include "ssp.h"
#include "test.h"
#include "tewari.h"

/* An 8 x 8 grid with a flat base colour and, when emissive is non-zero, an emissive image
 * of "half" (flat left half, glyph strokes on the right). */
static texopt_model *flat_base(int emissive)
{
    char err[256] = "";
    texopt_model *m = fixture_grid(8, 128, "flat");
    texopt_image *e = m && emissive ? fixture_add_slot_image(m, TEXOPT_SLOT_EMISSIVE, 128) : NULL;
    if (!m || (emissive && (!e || fixture_fill_pattern(e, "half") != 0)) ||
        texopt_model_build_domains(m, err, sizeof err) != TEXOPT_OK) {
        texopt_model_destroy(m);
        return NULL;
    }
    return m;
}

static double centroid_u(const texopt_mesh *mesh, size_t t)
{
    double u = 0;
    for (int k = 0; k < 3; k++)
        u += mesh->texel[2 * mesh->triangle[3 * t + k]] / mesh->width / 3;
    return u;
}

typedef texopt_status (*targets_fn)(const texopt_model *, const texopt_mesh *, double, const double *, int,
                                    texopt_triangle_target *, char *, size_t);

/* texopt_tewari_targets (base colour alone) as a targets_fn. */
static texopt_status tewari_base_colour(const texopt_model *m, const texopt_mesh *mesh, double lambda_min,
                                        const double *weights, int threads, texopt_triangle_target *g, char *err,
                                        size_t err_len)
{
    (void)weights;
    (void)threads;
    return texopt_tewari_targets(m, mesh, lambda_min, g, err, err_len);
}

/* Mean target area over the left (flat) and right (strokes) halves. */
static void half_areas(targets_fn fn, int emissive, double *left, double *right)
{
    texopt_model *m = flat_base(emissive);
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    texopt_triangle_target *g = calloc(mesh->triangle_count, sizeof *g);
    CHECK(g);
    CHECK_OK(fn(m, mesh, 0.1, NULL, 2, g, err, sizeof err), err);
    double sum[2] = {0, 0};
    int count[2] = {0, 0};
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        int side = centroid_u(mesh, t) > 0.5;
        sum[side] += g[t].lambda1 * g[t].lambda2;
        count[side]++;
    }
    *left = sum[0] / count[0];
    *right = sum[1] / count[1];
    free(g);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}

TEST(detail_in_a_second_map_shrinks_the_flat_half_only)
{
    double left, right;
    /* Base colour alone is flat: every triangle lambda 1. */
    half_areas(tewari_base_colour, 1, &left, &right);
    CHECK_NEAR(left, 1, 1e-12);
    CHECK_NEAR(right, 1, 1e-12);
    /* Every map: the emissive strokes keep their half, the flat half shrinks toward lambda_min
     * (its triangles next to the strokes, and at u = 0 where REPEAT wraps them, see some). */
    half_areas(texopt_tewari_targets_every_map, 1, &left, &right);
    CHECK_MSG(left < 0.1 && right > 0.5, "tewari: left %g right %g", left, right);
    half_areas(texopt_ssp_targets_every_map, 1, &left, &right);
    CHECK_MSG(left < 0.1 && right > 0.5, "ssp: left %g right %g", left, right);
}

/* Whether fn_a(threads_a) and fn_b(threads_b) give m's domain 0 the same targets, bit for bit. */
static int same_targets(texopt_model *m, targets_fn fn_a, int threads_a, targets_fn fn_b, int threads_b)
{
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    int same = 0;
    if (m && texopt_mesh_create(&mesh, m, 0, err, sizeof err) == TEXOPT_OK) {
        size_t n = mesh->triangle_count;
        texopt_triangle_target *a = calloc(n, sizeof *a), *b = calloc(n, sizeof *b);
        same = a && b && fn_a(m, mesh, 0.1, NULL, threads_a, a, err, sizeof err) == TEXOPT_OK &&
               fn_b(m, mesh, 0.1, NULL, threads_b, b, err, sizeof err) == TEXOPT_OK && memcmp(a, b, n * sizeof *a) == 0;
        free(a);
        free(b);
    }
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
    return same;
}

TEST(threads_do_not_change_the_targets)
{
    CHECK(same_targets(flat_base(1), texopt_ssp_targets_every_map, 1, texopt_ssp_targets_every_map, 3));
}

TEST(all_flat_maps_give_lambda_one)
{
    double left, right;
    half_areas(texopt_tewari_targets_every_map, 0, &left, &right);
    CHECK_NEAR(left, 1, 1e-12);
    CHECK_NEAR(right, 1, 1e-12);
}

TEST(one_map_gives_the_targets_of_that_map)
{
    CHECK(same_targets(fixture_grid(8, 128, "half"), tewari_base_colour, 1, texopt_tewari_targets_every_map, 2));
}

TEST(a_map_no_light_shows_asks_nothing)
{
    /* Weight 0 for the emissive image (image 1, read as a colour: its luma weight [0]) leaves
     * the flat base colour alone: lambda 1 everywhere; weight 1 brings the strokes back. */
    texopt_model *m = flat_base(1);
    CHECK(m);
    texopt_mesh *mesh = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&mesh, m, 0, err, sizeof err), err);
    double weights[2 * TEXOPT_LIT_WEIGHT_STRIDE];
    for (int i = 0; i < 2 * TEXOPT_LIT_WEIGHT_STRIDE; i++)
        weights[i] = 1;
    weights[TEXOPT_LIT_WEIGHT_STRIDE] = 0;
    texopt_triangle_target *g = calloc(mesh->triangle_count, sizeof *g);
    CHECK(g);
    CHECK_OK(texopt_tewari_targets_every_map(m, mesh, 0.1, weights, 2, g, err, sizeof err), err);
    double smallest = 1;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        smallest = fmin(smallest, g[t].lambda1 * g[t].lambda2);
    CHECK_NEAR(smallest, 1, 1e-12);
    weights[TEXOPT_LIT_WEIGHT_STRIDE] = 1;
    CHECK_OK(texopt_tewari_targets_every_map(m, mesh, 0.1, weights, 2, g, err, sizeof err), err);
    smallest = 1;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        smallest = fmin(smallest, g[t].lambda1 * g[t].lambda2);
    CHECK(smallest < 0.05);
    free(g);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(m);
}
