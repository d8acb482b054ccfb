/* test_rechart_models_slow.c - new charts (engine/param/rechart.c) with each parameterization
 * method on real models: charts made, charts that fell back to Tutte, CPU seconds, and the
 * distortion of the new layout (each chart scaled to its 3D area, so only shape counts:
 * area-weighted mean conformal distortion smax/smin and Sander's L2 stretch). Models:
 * tests/data/spot/spot.glb, or (for scripts/bench.d/rechart) the colon-separated paths in
 * TEXOPT_RECHART_MODELS. Prints one "rechart" line per domain and method (and one for the
 * input layout, measured the same way) and checks that no new triangle is flipped. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "distortion.h"
#include "gltf_io.h"
#include "mesh.h"
#include "rechart.h"
#include "test.h"
#include "vec3.h"

typedef struct layout_measure {
    double conformal, l2_stretch;
    size_t flipped;
} layout_measure;

/* mirrored_ok: the input layout's charts may be mirrored (texel v points down), so there a
 * negative Jacobian is measured as its mirror image, as distortion.c does. */
static void measure_layout(const texopt_mesh *m, const texopt_rechart *r, int mirrored_ok, layout_measure *out)
{
    double *area_3d = calloc(r->chart_count, sizeof *area_3d), *area_uv = calloc(r->chart_count, sizeof *area_uv);
    static const uint32_t corners[3] = {0, 1, 2};
    for (size_t t = 0; t < m->triangle_count; t++) {
        const double *uv = r->corner_uv + 6 * t;
        area_3d[r->chart_of[t]] += m->area_3d[t];
        area_uv[r->chart_of[t]] += 0.5 * fabs((uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[3] - uv[1]) * (uv[4] - uv[0]));
    }
    double total = 0.0, conformal = 0.0, l2 = 0.0;
    *out = (layout_measure){0};
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (m->flags[t] & TEXOPT_TRI_DEGENERATE_3D)
            continue;
        uint32_t c = r->chart_of[t];
        double P[2][2], T[2][2], J[2][2];
        const uint32_t *v = m->triangle + 3 * t;
        texopt_plane_edges(texopt_mesh_vertex_point(m, v[0]), texopt_mesh_vertex_point(m, v[1]),
                           texopt_mesh_vertex_point(m, v[2]), P);
        texopt_layout_edges(r->corner_uv + 6 * t, corners, T);
        texopt_jacobian(T, P, sqrt(area_3d[c] / area_uv[c]), J);
        if (mirrored_ok && J[0][0] * J[1][1] - J[0][1] * J[1][0] < 0.0) {
            J[1][0] = -J[1][0];
            J[1][1] = -J[1][1];
        }
        texopt_triangle_distortion d;
        texopt_triangle_distortion_of(J, &d);
        if (!isfinite(d.conformal)) {
            out->flipped++;
            continue;
        }
        total += m->area_3d[t];
        conformal += m->area_3d[t] * d.conformal;
        l2 += m->area_3d[t] * d.l2_stretch * d.l2_stretch;
    }
    out->conformal = conformal / total;
    out->l2_stretch = sqrt(l2 / total);
    free(area_3d);
    free(area_uv);
}

/* The input layout, measured the same way (each input chart scaled to its 3D area). */
static void print_input(const char *name, int d, const texopt_mesh *m)
{
    texopt_rechart input = {.triangle_count = m->triangle_count,
                            .chart_count = m->chart_count,
                            .chart_of = m->chart_of,
                            .corner_uv = malloc(6 * m->triangle_count * sizeof(double))};
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++)
                input.corner_uv[6 * t + 2 * (size_t)k + (size_t)a] =
                    m->texel[2 * (size_t)m->triangle[3 * t + (size_t)k] + (size_t)a];
    layout_measure lm;
    measure_layout(m, &input, 1, &lm);
    printf("rechart %s domain %d triangles %zu input_charts %zu method input charts %zu conformal %.4f l2_stretch %.4f "
           "collapsed %zu\n",
           name, d, m->triangle_count, m->chart_count, m->chart_count, lm.conformal, lm.l2_stretch, lm.flipped);
    free(input.corner_uv);
}

static void rechart_model(const char *path)
{
    char err[512] = "";
    texopt_model *model = NULL;
    texopt_load_options opt = {.skip_images = 1};
    CHECK_MSG(texopt_model_load(&model, path, &opt, err, sizeof err) == TEXOPT_OK, "%s: %s", path, err);
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    for (int d = 0; d < model->domain_count; d++) {
        texopt_mesh *m = NULL;
        CHECK_OK(texopt_mesh_create(&m, model, d, err, sizeof err), err);
        print_input(name, d, m);
        for (int method = 0; method < 4; method++) {
            texopt_rechart_options ro = {.method = (texopt_parameterizer)method};
            texopt_rechart *r = NULL;
            clock_t t0 = clock();
            CHECK_OK(texopt_rechart_create(&r, m, &ro, err, sizeof err), err);
            double seconds = (double)(clock() - t0) / CLOCKS_PER_SEC;
            layout_measure lm;
            measure_layout(m, r, 0, &lm);
            printf("rechart %s domain %d triangles %zu input_charts %zu method %s charts %zu fallback %zu cpu_s %.2f "
                   "conformal %.4f l2_stretch %.4f flipped %zu\n",
                   name, d, m->triangle_count, m->chart_count, texopt_parameterizer_name(ro.method), r->chart_count,
                   r->fallback_charts, seconds, lm.conformal, lm.l2_stretch, lm.flipped);
            CHECK_EQ_INT(lm.flipped, 0);
            texopt_rechart_destroy(r);
        }
        texopt_mesh_destroy(m);
    }
    texopt_model_destroy(model);
}

TEST(real_models_get_new_charts_without_flips)
{
    const char *list = getenv("TEXOPT_RECHART_MODELS");
    if (!list || !*list) {
        rechart_model(TEXOPT_TEST_DATA_DIR "/spot/spot.glb");
        return;
    }
    char *copy = strdup(list);
    CHECK(copy);
    for (char *save = NULL, *p = strtok_r(copy, ":", &save); p; p = strtok_r(NULL, ":", &save))
        rechart_model(p);
    free(copy);
}
