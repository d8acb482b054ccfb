/* Packing efficiency of the budget's packing on real models (slow).
 *
 * Does: per model and per texture domain, texopt_budget_fit at c_r = 1 and 0.5 on the
 * domain's own layout, as the pipeline calls it, once with the charts' angles kept (the
 * perceptual method) and once with targets that ignore rotation (the baselines: charts
 * turned to their smallest box first, chart_orient.h), then checks the result
 * independently: cost within 2% of the budget, charts apart by the gutter (rasterised),
 * every chart moved by a translation and a quarter turn only (no mirror), or with turned
 * charts rigidly (no mirror, no scale), and packing efficiency >= 0.635 (the earlier
 * packer's worst here was 0.626; issue 4's target of 0.75 is not reached by placement
 * alone, see BENCHMARKS.md@9f788a8 "Packing efficiency").
 * Prints one line per packing (efficiency, size, CPU seconds).
 * Models: spot and Fox from tests/data, or the paths in TEXOPT_PACK_MODELS (space
 * separated, e.g. the pipeline's outputs of /work/shared/assets, whose UVs are optimised
 * layouts; scripts/bench.d/pack measures through the CLI instead). Does not: run stage 2. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "budget.h"
#include "coverage.h"
#include "gltf_io.h"
#include "mesh.h"
#include "test.h"

#define GUTTER 4

/* Labels the cells touched by each chart (points every 1/3 texel) and reports whether two
 * charts come closer than the gutter: points GUTTER apart lie in cells GUTTER - 1 apart,
 * so no other chart's cell may appear within GUTTER - 2 cells. */
static int charts_keep_gutter(const texopt_mesh *m, const double *texel, int w, int h)
{
    int *label = malloc(sizeof(int) * (size_t)w * h);
    if (!label)
        return 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        label[i] = -1;
    int ok = 1;
    for (size_t t = 0; t < m->triangle_count && ok; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        const double *a = texel + 2 * v[0], *b = texel + 2 * v[1], *c = texel + 2 * v[2];
        double len = fmax(fmax(fabs(b[0] - a[0]) + fabs(b[1] - a[1]), fabs(c[0] - a[0]) + fabs(c[1] - a[1])), 1);
        int n = (int)(len * 3) + 1;
        for (int i = 0; i <= n && ok; i++)
            for (int j = 0; i + j <= n; j++) {
                double s = (double)i / n, r = (double)j / n;
                int cx = (int)floor(a[0] + s * (b[0] - a[0]) + r * (c[0] - a[0]));
                int cy = (int)floor(a[1] + s * (b[1] - a[1]) + r * (c[1] - a[1]));
                if (cx < 0 || cy < 0 || cx >= w || cy >= h) {
                    ok = 0;
                    break;
                }
                int *l = label + (size_t)cy * w + cx;
                if (*l >= 0 && *l != (int)m->chart_of[t])
                    ok = 0;
                *l = (int)m->chart_of[t];
            }
    }
    const int r = GUTTER - 2;
    for (int y = 0; y < h && ok; y++)
        for (int x = 0; x < w && ok; x++) {
            int l = label[(size_t)y * w + x];
            if (l < 0)
                continue;
            for (int dy = -r; dy <= r && ok; dy++)
                for (int dx = -r; dx <= r; dx++) {
                    int nx = x + dx, ny = y + dy;
                    if (nx >= 0 && ny >= 0 && nx < w && ny < h && label[(size_t)ny * w + nx] >= 0 &&
                        label[(size_t)ny * w + nx] != l) {
                        ok = 0;
                        break;
                    }
                }
        }
    free(label);
    return ok;
}

static void turn(int k, double x, double y, double *ox, double *oy)
{
    *ox = k == 0 ? x : k == 1 ? -y : k == 2 ? -x : y;
    *oy = k == 0 ? y : k == 1 ? x : k == 2 ? -y : -x;
}

/* Every triangle edge out = quarter turn k(chart) of scale * edge in, one k per chart. */
static int charts_only_turned(const texopt_mesh *m, const double *in, double scale, const double *out)
{
    int *k_of = malloc(sizeof(int) * (m->chart_count ? m->chart_count : 1));
    if (!k_of)
        return 0;
    for (size_t c = 0; c < m->chart_count; c++)
        k_of[c] = -1;
    int ok = 1;
    for (size_t t = 0; t < m->triangle_count && ok; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        for (int e = 1; e < 3 && ok; e++) {
            double dx = scale * (in[2 * v[e]] - in[2 * v[0]]), dy = scale * (in[2 * v[e] + 1] - in[2 * v[0] + 1]);
            double ox = out[2 * v[e]] - out[2 * v[0]], oy = out[2 * v[e] + 1] - out[2 * v[0] + 1];
            double tol = 1e-6 * (1 + fabs(dx) + fabs(dy));
            int *k = k_of + m->chart_of[t];
            for (int cand = 0; cand < 4 && *k < 0 && fabs(dx) + fabs(dy) > 1e-3; cand++) {
                double rx, ry;
                turn(cand, dx, dy, &rx, &ry);
                if (fabs(rx - ox) <= tol && fabs(ry - oy) <= tol)
                    *k = cand;
            }
            if (*k < 0)
                continue; /* decided at a longer edge */
            double rx, ry;
            turn(*k, dx, dy, &rx, &ry);
            ok = fabs(rx - ox) <= tol && fabs(ry - oy) <= tol;
        }
    }
    free(k_of);
    return ok;
}

/* Every triangle out = a rotation (no mirror) of scale * the triangle in: edge lengths times
 * scale, signed area times scale^2. */
static int charts_rigid(const texopt_mesh *m, const double *in, double scale, const double *out)
{
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        double area_in = 0, area_out = 0;
        for (int e = 0; e < 3; e++) {
            const double *p = in + 2 * v[e], *q = in + 2 * v[(e + 1) % 3];
            const double *r = out + 2 * v[e], *u = out + 2 * v[(e + 1) % 3];
            double len = scale * hypot(q[0] - p[0], q[1] - p[1]);
            if (fabs(len - hypot(u[0] - r[0], u[1] - r[1])) > 1e-6 * (1 + len))
                return 0;
            area_in += scale * scale * (p[0] * q[1] - q[0] * p[1]);
            area_out += r[0] * u[1] - u[0] * r[1];
        }
        if (fabs(area_in - area_out) > 1e-6 * (1 + fabs(area_in)))
            return 0;
    }
    return 1;
}

static double cpu_seconds(void)
{
    return (double)clock() / CLOCKS_PER_SEC;
}

/* Packs every domain of the model at c_r (charts free to turn with `turn`) and checks it;
 * returns the worst efficiency. */
static double pack_model(const char *path, double cr, int turn, int *failed)
{
    texopt_load_options lo = {0};
    lo.skip_images = 1;
    texopt_model *model = NULL;
    char err[512] = "";
    double worst = 1;
    if (texopt_model_load(&model, path, &lo, err, sizeof err) != TEXOPT_OK) {
        printf("pack %s: %s\n", path, err);
        *failed = 1;
        return 0;
    }
    for (int d = 0; d < model->domain_count; d++) {
        texopt_mesh *mesh = NULL;
        texopt_coverage in;
        if (texopt_mesh_create(&mesh, model, d, err, sizeof err) != TEXOPT_OK ||
            texopt_coverage_measure(mesh, NULL, &in, err, sizeof err) != TEXOPT_OK) {
            printf("pack %s domain %d: %s\n", path, d, err);
            *failed = 1;
            texopt_mesh_destroy(mesh);
            continue;
        }
        texopt_budget_request req = {0};
        req.kind = TEXOPT_BUDGET_RELATIVE_COST;
        req.relative_cost = cr;
        req.input_cost = (double)in.covered_texels;
        req.input_width = mesh->width;
        req.input_height = mesh->height;
        texopt_triangle_target *targets = turn ? calloc(mesh->triangle_count + 1, sizeof *targets) : NULL;
        req.targets = targets;
        double *out = malloc(sizeof(double) * 2 * mesh->vertex_count);
        texopt_budget_result res;
        double t0 = cpu_seconds();
        texopt_status st = texopt_budget_fit(mesh, mesh->texel, &req, out, &res, err, sizeof err);
        double cpu = cpu_seconds() - t0;
        if (st != TEXOPT_OK) {
            printf("pack %s domain %d c_r %.2f: %s\n", path, d, cr, err);
            *failed = 1;
        } else {
            int gutter_ok = charts_keep_gutter(mesh, out, res.width, res.height);
            int turns_ok = turn ? charts_rigid(mesh, mesh->texel, res.scale, out)
                                : charts_only_turned(mesh, mesh->texel, res.scale, out);
            int cost_ok = fabs(res.relative_cost / cr - 1) <= 0.02;
            printf("pack %-28s domain %d charts %4zu %-7s c_r %.2f reached %.4f size %5dx%-5d efficiency %.3f "
                   "packings %3d cpu %.2f s%s%s%s\n",
                   strrchr(path, '/') ? strrchr(path, '/') + 1 : path, d, mesh->chart_count, turn ? "turned" : "angles",
                   cr, res.relative_cost, res.width, res.height, res.packing_efficiency, res.packings, cpu,
                   gutter_ok ? "" : " GUTTER VIOLATED", turns_ok ? "" : " NOT RIGID", cost_ok ? "" : " COST MISSED");
            if (!gutter_ok || !turns_ok || !cost_ok)
                *failed = 1;
            if (res.packing_efficiency < worst)
                worst = res.packing_efficiency;
        }
        fflush(stdout);
        free(out);
        free(targets);
        texopt_mesh_destroy(mesh);
    }
    texopt_model_destroy(model);
    return worst;
}

TEST(models_pack_densely_with_gutters_quarter_turns_and_the_budget_cost)
{
    const char *env = getenv("TEXOPT_PACK_MODELS");
    char list[4096];
    if (env && *env)
        snprintf(list, sizeof list, "%s", env);
    else
        snprintf(list, sizeof list, "%s/spot/spot.glb %s/Fox/Fox.glb", TEXOPT_TEST_DATA_DIR, TEXOPT_TEST_DATA_DIR);
    int failed = 0;
    double worst = 1;
    const double costs[2] = {1.0, 0.5};
    char *save = NULL;
    for (char *path = strtok_r(list, " ", &save); path; path = strtok_r(NULL, " ", &save))
        for (int turn = 0; turn < 2; turn++)
            for (int i = 0; i < 2; i++)
                worst = fmin(worst, pack_model(path, costs[i], turn, &failed));
    CHECK_MSG(!failed, "a packing failed or broke a rule (see the lines above)");
    CHECK_MSG(worst >= 0.635, "worst packing efficiency %.3f", worst); /* the earlier packer: 0.626 */
}
