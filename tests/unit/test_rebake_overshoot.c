/* Tests that the re-bake (rebake.c with its least-squares fit, texel_fit.c) does not ring on
 * sharp edges more than a Lanczos-3 resize of the same map to the same texels (issue 45, item
 * 3): the emissive "PLAY button" of map_patterns.h, baked into a uniform half-size layout and
 * into a warped one (some triangles shrunk 3x, others kept near input density, as an
 * allocation does), its overshoot measured by overshoot.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "lanczos.h"
#include "overshoot.h"
#include "rebake.h"
#include "test.h"

#define SRC 256
#define OUT 128
#define GRID 8
#define RADIUS 1.5

typedef struct grid_layout {
    size_t nv, nt;
    float uv_in[(GRID + 1) * (GRID + 1) * 2], uv_out[(GRID + 1) * (GRID + 1) * 2];
    double uv_in_d[(GRID + 1) * (GRID + 1) * 2], uv_out_d[(GRID + 1) * (GRID + 1) * 2];
    uint32_t tris[GRID * GRID * 6];
} grid_layout;

/* A monotone warp of [0,1] onto itself whose slope runs from 1/3 to 5/3: x + (1/3) sin(2 pi x) / pi. */
static double warp(double x)
{
    return x + sin(2 * 3.14159265358979323846 * x) / (3 * 3.14159265358979323846);
}

static void make_layout(grid_layout *g, int warped)
{
    g->nv = (GRID + 1) * (GRID + 1);
    g->nt = 2 * GRID * GRID;
    for (int j = 0; j <= GRID; j++)
        for (int i = 0; i <= GRID; i++) {
            size_t v = (size_t)j * (GRID + 1) + i;
            double u = (double)i / GRID, w = (double)j / GRID;
            g->uv_in_d[2 * v] = u, g->uv_in_d[2 * v + 1] = w;
            g->uv_out_d[2 * v] = warped ? warp(u) : u, g->uv_out_d[2 * v + 1] = warped ? warp(w) : w;
        }
    for (size_t k = 0; k < 2 * g->nv; k++) {
        g->uv_in[k] = (float)g->uv_in_d[k];
        g->uv_out[k] = (float)g->uv_out_d[k];
    }
    for (int j = 0; j < GRID; j++)
        for (int i = 0; i < GRID; i++) {
            uint32_t a = (uint32_t)(j * (GRID + 1) + i), b = a + 1, c = a + GRID + 2, d = a + GRID + 1;
            uint32_t *t = g->tris + 6 * (size_t)(j * GRID + i);
            t[0] = a, t[1] = b, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
        }
}

/* The overshoot of the re-bake of `pattern` into the layout, and of the Lanczos resize. */
static int measure(const char *pattern, int warped, overshoot *bake, overshoot *resize)
{
    grid_layout g;
    make_layout(&g, warped);
    texopt_image src = {0}, out = {0}, small = {0};
    char err[256] = "";
    int ok = texopt_image_create(&src, SRC, SRC, 3, err, sizeof err) == TEXOPT_OK &&
             fixture_fill_pattern(&src, pattern) == 0 &&
             texopt_image_create(&out, OUT, OUT, 3, err, sizeof err) == TEXOPT_OK &&
             texopt_image_create(&small, OUT, OUT, 3, err, sizeof err) == TEXOPT_OK;
    texopt_rebake_layout layout = {
        .triangle_count = g.nt, .triangles = g.tris, .uv_in = g.uv_in_d, .uv_out = g.uv_out_d, .threads = 2};
    ok = ok && texopt_rebake_image(&src, TEXOPT_WRAP_CLAMP, TEXOPT_WRAP_CLAMP, 0, &layout, &out, NULL, NULL, err,
                                   sizeof err) == TEXOPT_OK;
    ok = ok && texopt_lanczos_resize(&src, &small, 2, err, sizeof err) == TEXOPT_OK;
    ok = ok && overshoot_measure(&src, &out, g.uv_in, g.uv_out, g.tris, g.nt, RADIUS, NULL, bake) == 0;
    ok = ok && overshoot_measure(&src, &small, g.uv_in, g.uv_in, g.tris, g.nt, RADIUS, NULL, resize) == 0;
    if (!ok)
        fprintf(stderr, "measure %s: %s\n", pattern, err);
    texopt_image_destroy(&src);
    texopt_image_destroy(&out);
    texopt_image_destroy(&small);
    return ok;
}

static void check_no_more_ringing_than_resize(const char *pattern, int warped)
{
    overshoot bake, resize;
    CHECK(measure(pattern, warped, &bake, &resize));
    printf("  %s %s: re-bake above %.1f below %.1f (%.2f%% of channels), resize above %.1f below %.1f "
           "(%.2f%%)\n",
           pattern, warped ? "warped" : "uniform", bake.above, bake.below, 100 * bake.share, resize.above, resize.below,
           100 * resize.share);
    /* The resize rings (its negative lobes): a sharp edge gives it some code values. */
    CHECK(resize.above + resize.below > 2);
    /* Half the resize's either way: the least-squares fit alone (no bounds) rang as much as
     * the resize on these edges, or more. */
    CHECK_MSG(bake.above <= 0.5 * resize.above && bake.below <= 0.5 * resize.below,
              "%s: re-bake overshoots %.1f / %.1f, resize %.1f / %.1f", pattern, bake.above, bake.below, resize.above,
              resize.below);
    CHECK(bake.texels > (size_t)(OUT * OUT) * 9 / 10);
}

TEST(sharp_emissive_shape_rings_no_more_than_a_resize_uniform)
{
    check_no_more_ringing_than_resize("play", 0);
}

TEST(sharp_emissive_shape_rings_no_more_than_a_resize_warped)
{
    check_no_more_ringing_than_resize("play", 1);
}

TEST(fine_orm_scratches_ring_no_more_than_a_resize)
{
    check_no_more_ringing_than_resize("orm", 1);
}

TEST(measure_sees_a_ring)
{
    /* The measure itself: a texel pushed past its neighbourhood counts, in code values. */
    texopt_image src = {0}, out = {0};
    CHECK(texopt_image_create(&src, 16, 16, 1, NULL, 0) == TEXOPT_OK);
    CHECK(texopt_image_create(&out, 16, 16, 1, NULL, 0) == TEXOPT_OK);
    for (int i = 0; i < 256; i++)
        src.pixels[i] = out.pixels[i] = (i % 16) < 8 ? 0.2f : 0.8f;
    out.pixels[5 * 16 + 9] = 0.9f;  /* bright side, next to the edge: 25.5 above */
    out.pixels[9 * 16 + 2] = 0.15f; /* far from the edge: 12.75 below */
    const float uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    const uint32_t tris[6] = {0, 1, 2, 0, 2, 3};
    overshoot o;
    CHECK(overshoot_measure(&src, &out, uv, uv, tris, 2, RADIUS, NULL, &o) == 0);
    CHECK_NEAR(o.above, 25.5, 1e-3);
    CHECK_NEAR(o.below, 12.75, 1e-3);
    CHECK_EQ_INT((int)o.texels, 256);
    texopt_image_destroy(&src);
    texopt_image_destroy(&out);
}
