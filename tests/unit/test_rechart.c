/* test_rechart.c - new disk charts laid out by each parameterization method
 * (engine/param/rechart.c), on a hand-built cube, a generated closed sphere and spot
 * (tests/data). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "gltf_io.h"
#include "handmesh.h"
#include "mesh.h"
#include "rechart.h"
#include "test.h"

static texopt_mesh *cube(void)
{
    texopt_mesh *m = handmesh_alloc(8, 12);
    for (int v = 0; v < 8; v++) {
        m->position[3 * v] = (v & 1) ? 2.0 : 0.0;
        m->position[3 * v + 1] = (v & 2) ? 2.0 : 0.0;
        m->position[3 * v + 2] = (v & 4) ? 2.0 : 0.0;
        m->texel[2 * v] = v; /* the input layout does not matter here */
        m->texel[2 * v + 1] = v * v;
    }
    /* Outward, counter-clockwise faces: -z, +z, -y, +y, -x, +x. */
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = quads[f];
        uint32_t tris[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(m->triangle + 6 * f, tris, sizeof tris);
    }
    handmesh_finish(m);
    return m;
}

static double doubled_area(const double *uv)
{
    return (uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[3] - uv[1]) * (uv[4] - uv[0]);
}

static size_t corner_flips(const texopt_rechart *r)
{
    size_t flips = 0;
    for (size_t t = 0; t < r->triangle_count; t++)
        flips += !(doubled_area(r->corner_uv + 6 * t) > 0.0);
    return flips;
}

TEST(cube_faces_become_six_isometric_charts_with_every_method)
{
    texopt_mesh *m = cube();
    char err[256] = "";
    for (int method = 0; method < 4; method++) {
        texopt_rechart_options opt = {.method = (texopt_parameterizer)method};
        texopt_rechart *r = NULL;
        CHECK_OK(texopt_rechart_create(&r, m, &opt, err, sizeof err), err);
        CHECK_EQ_INT(r->chart_count, 6);
        CHECK_EQ_INT(corner_flips(r), 0);
        for (size_t t = 0; t < 12; t++) {
            CHECK_EQ_INT(r->chart_of[t], r->chart_of[t - t % 2]); /* a face's two triangles */
            /* Each face is a 2 x 2 square: LSCM and ABF keep it (area 2 per triangle); Tutte
             * and the square keep its shape up to scale. */
            double area = 0.5 * doubled_area(r->corner_uv + 6 * t);
            if (method == TEXOPT_PARAMETERIZER_LSCM || method == TEXOPT_PARAMETERIZER_ABF)
                CHECK_NEAR(area, 2.0, 1e-9);
            else
                CHECK(area > 0.0);
        }
        texopt_rechart_destroy(r);
    }
    texopt_mesh_destroy(m);
}

TEST(closed_sphere_is_cut_into_disks_without_flips)
{
    texopt_model *model = fixture_uv_sphere(24, 12, 64);
    CHECK(model != NULL);
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    for (int method = 0; method < 4; method++) {
        texopt_rechart_options opt = {.method = (texopt_parameterizer)method};
        texopt_rechart *r = NULL;
        CHECK_OK(texopt_rechart_create(&r, m, &opt, err, sizeof err), err);
        /* A closed surface cannot be one disk; the 75 degree cone needs several charts. */
        CHECK(r->chart_count >= 4);
        size_t degenerate = 0;
        for (size_t t = 0; t < m->triangle_count; t++)
            degenerate += (m->flags[t] & TEXOPT_TRI_DEGENERATE_3D) != 0;
        CHECK_EQ_INT(corner_flips(r), degenerate);
        if (method == TEXOPT_PARAMETERIZER_TUTTE)
            CHECK_EQ_INT(r->fallback_charts, 0);
        texopt_rechart_destroy(r);
    }
    /* No crease and no cone: growth alone must stop short of closing the sphere, leaving one
     * large disk and what closes it. */
    texopt_rechart_options open = {.method = TEXOPT_PARAMETERIZER_LSCM, .crease_degrees = 180, .cone_degrees = 180};
    texopt_rechart *r = NULL;
    CHECK_OK(texopt_rechart_create(&r, m, &open, err, sizeof err), err);
    CHECK(r->chart_count >= 2 && r->chart_count <= 3);
    size_t degenerate = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        degenerate += (m->flags[t] & TEXOPT_TRI_DEGENERATE_3D) != 0;
    CHECK_EQ_INT(corner_flips(r), degenerate);
    texopt_rechart_destroy(r);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

/* One face triangle reversed: its edges run the same way as its neighbours', so a region
 * holding it is no disk and is split until the parts are; nothing flips. */
TEST(inconsistent_orientation_is_split_into_disks)
{
    texopt_mesh *m = cube();
    uint32_t swap = m->triangle[3 * 4 + 1];
    m->triangle[3 * 4 + 1] = m->triangle[3 * 4 + 2];
    m->triangle[3 * 4 + 2] = swap;
    handmesh_finish(m);
    texopt_rechart_options opt = {.method = TEXOPT_PARAMETERIZER_ABF, .crease_degrees = 180, .cone_degrees = 180};
    texopt_rechart *r = NULL;
    char err[256] = "";
    CHECK_OK(texopt_rechart_create(&r, m, &opt, err, sizeof err), err);
    CHECK(r->chart_count >= 2);
    CHECK_EQ_INT(corner_flips(r), 0);
    texopt_rechart_destroy(r);
    texopt_mesh_destroy(m);
}

/* On a real scan-like mesh a breadth-first front meets itself at many vertices: growth that
 * did not refuse those pinches would leave regions to be split into ~1800 slivers. */
TEST(spot_grows_into_few_charts)
{
    texopt_model *model = NULL;
    texopt_load_options lo = {.skip_images = 1};
    char err[512] = "";
    CHECK_OK(texopt_model_load(&model, TEXOPT_TEST_DATA_DIR "/spot/spot.glb", &lo, err, sizeof err), err);
    texopt_mesh *m = NULL;
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    texopt_rechart_options opt = {.method = TEXOPT_PARAMETERIZER_ABF};
    texopt_rechart *r = NULL;
    CHECK_OK(texopt_rechart_create(&r, m, &opt, err, sizeof err), err);
    CHECK(r->chart_count < 100);
    CHECK_EQ_INT(corner_flips(r), 0);
    texopt_rechart_destroy(r);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

TEST(names_and_options_are_checked)
{
    CHECK(texopt_parameterizer_from_name("abf") == TEXOPT_PARAMETERIZER_ABF);
    CHECK(texopt_parameterizer_from_name("square") == TEXOPT_PARAMETERIZER_SQUARE);
    CHECK(texopt_parameterizer_from_name("arap") == -1);
    CHECK(strcmp(texopt_parameterizer_name(TEXOPT_PARAMETERIZER_LSCM), "lscm") == 0);
    CHECK(texopt_parameterizer_name((texopt_parameterizer)9) == NULL);
    texopt_mesh *m = cube();
    texopt_rechart *r = NULL;
    char err[256] = "";
    texopt_rechart_options opt = {.method = TEXOPT_PARAMETERIZER_LSCM, .crease_degrees = -5};
    CHECK_EQ_INT(texopt_rechart_create(&r, m, &opt, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK(r == NULL);
    texopt_mesh_destroy(m);
}

/* A flat grid whose input layout gives the left half 4 times the texel density of the right
 * (its texel areas scaled 9 times there, 3 times the linear density): one
 * chart without density_ratio, and with ratio 2 no chart holds triangles of both halves. */
TEST(density_ratio_keeps_detailed_parts_apart)
{
    texopt_model *model = fixture_grid(8, 64, "flat");
    CHECK(model != NULL);
    if (!model)
        return;
    texopt_mesh *m = NULL;
    char err[256] = "";
    CHECK_OK(texopt_mesh_create(&m, model, 0, err, sizeof err), err);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double x = 0;
        for (int k = 0; k < 3; k++)
            x += texopt_mesh_vertex_point(m, m->triangle[3 * t + (size_t)k])[0] / 3;
        m->area_texel[t] *= x < 0.5 ? 9.0 : 1.0;
    }
    texopt_rechart *plain = NULL, *even = NULL;
    texopt_rechart_options opt = {.method = TEXOPT_PARAMETERIZER_ABF};
    CHECK_OK(texopt_rechart_create(&plain, m, &opt, err, sizeof err), err);
    opt.density_ratio = 2.0;
    CHECK_OK(texopt_rechart_create(&even, m, &opt, err, sizeof err), err);
    if (plain && even) {
        CHECK_EQ_INT(plain->chart_count, 1);
        CHECK(even->chart_count >= 2);
        int *side = malloc(even->chart_count * sizeof *side);
        for (size_t c = 0; c < even->chart_count; c++)
            side[c] = -1;
        for (size_t t = 0; t < m->triangle_count; t++) {
            int left = fabs(m->area_texel[t]) > 64.0; /* 32 texels a triangle on the right */
            int *s = &side[even->chart_of[t]];
            CHECK(*s == -1 || *s == left);
            *s = left;
        }
        free(side);
    }
    texopt_rechart_destroy(plain);
    texopt_rechart_destroy(even);
    texopt_mesh_destroy(m);
    texopt_model_destroy(model);
}

/* Counts its calls; refuses every seam (rechart.h may_cross). */
static int refuse_seam(const void *context, uint32_t t, uint32_t u)
{
    (void)t;
    (void)u;
    ++*(int *)context;
    return 0;
}

/* Two flat unit quads side by side, each with its own vertices: the input layout has a
 * seam along x = 1. Without may_cross one chart grows over
 * it; refused, the quads are two charts, and only the seam was asked. */
TEST(a_refused_input_seam_splits_the_charts)
{
    texopt_mesh *m = handmesh_alloc(8, 4);
    CHECK(m != NULL);
    if (!m)
        return;
    /* vertices 0-3 the left quad, 4-7 the right; 4 and 7 lie on 1 and 2 (points are vertex ids) */
    static const double xy[8][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {1, 0}, {2, 0}, {2, 1}, {1, 1}};
    static const uint32_t point[8] = {0, 1, 2, 3, 1, 5, 6, 2};
    static const uint32_t tris[12] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    for (uint32_t v = 0; v < 8; v++) {
        m->point_of[v] = point[v];
        m->position[3 * v] = xy[v][0];
        m->position[3 * v + 1] = xy[v][1];
        m->texel[2 * v] = 10.0 * xy[v][0] + (v >= 4 ? 30.0 : 0.0);
        m->texel[2 * v + 1] = 10.0 * xy[v][1];
    }
    memcpy(m->triangle, tris, sizeof tris);
    handmesh_finish(m);
    texopt_rechart *open = NULL, *cut = NULL;
    int asked = 0;
    char err[256] = "";
    texopt_rechart_options opt = {.method = TEXOPT_PARAMETERIZER_ABF};
    CHECK_OK(texopt_rechart_create(&open, m, &opt, err, sizeof err), err);
    opt.may_cross = refuse_seam;
    opt.cross_context = &asked;
    CHECK_OK(texopt_rechart_create(&cut, m, &opt, err, sizeof err), err);
    if (open && cut) {
        CHECK_EQ_INT(open->chart_count, 1);
        CHECK_EQ_INT(cut->chart_count, 2);
        CHECK(cut->chart_of[0] == cut->chart_of[1] && cut->chart_of[2] == cut->chart_of[3]);
        CHECK(cut->chart_of[0] != cut->chart_of[2]);
        CHECK(asked >= 1 && asked <= 2); /* once from each side at most, never inside a quad */
    }
    texopt_rechart_destroy(open);
    texopt_rechart_destroy(cut);
    texopt_mesh_destroy(m);
}
