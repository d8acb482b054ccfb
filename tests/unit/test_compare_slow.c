/* test_compare_slow.c - compare and the whole-file target_loss search through the real
 * pipeline (engine/compare.h), on tests/data/Fox with the cheap "input" method. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "compare.h"
#include "gltf_io.h"
#include "report.h"
#include "test.h"

static void fox_path(char *path, size_t len)
{
    snprintf(path, len, "%s/Fox/Fox.glb", TEXOPT_TEST_DATA_DIR);
}

TEST(compare_input_method_curve)
{
    char path[1024], err[512] = "";
    fox_path(path, sizeof path);
    const texopt_method methods[] = {TEXOPT_METHOD_INPUT};
    const double costs[] = {1.0, 0.25, 0.0625};
    texopt_compare_options opt;
    memset(&opt, 0, sizeof opt);
    opt.methods = methods;
    opt.method_count = 1;
    opt.costs = costs;
    opt.cost_count = 3;
    opt.showcase_cost = 0.25;
    opt.evaluate.resolution = 400;
    opt.evaluate.threads = 2;
    texopt_compare_result r;
    CHECK_OK(texopt_compare(path, &opt, &r, err, sizeof err), err);
    CHECK_EQ_INT(r.curve_count, 1);
    const texopt_compare_curve *c = &r.curves[0];
    for (int i = 0; i < 3; i++)
        CHECK_MSG(c->points[i].status == TEXOPT_OK, "point %d: %s", i, c->points[i].message);
    /* The identity budget keeps the texture: nothing changes on screen. */
    CHECK(c->points[0].q == 0.0);
    CHECK_NEAR(c->points[0].cost_achieved, 1.0, 1e-12);
    /* Same layout, texture scaled by sqrt(c_r) per side: covered texels follow to within
     * the chart borders. */
    CHECK_NEAR(c->points[1].cost_achieved, 0.25, 0.02);
    CHECK_NEAR(c->points[2].cost_achieved, 0.0625, 0.01);
    CHECK(c->points[1].q > 0.005);
    CHECK(c->points[2].q > c->points[1].q);
    CHECK_EQ_INT(c->points[1].texture_pixels, 512 * 512);
    CHECK(c->showcase != NULL && c->showcase_triangle_error != NULL);
    /* Equal-loss cost of the curve against itself: its own point. */
    CHECK_NEAR(texopt_compare_cost_at_loss(c, c->points[1].q), c->points[1].cost_achieved, 1e-9);
    char *html = NULL;
    CHECK_OK(texopt_report_html(&r, NULL, &html, err, sizeof err), err);
    CHECK(strstr(html, "data-method=\"input\"") != NULL);
    free(html);
    texopt_compare_result_destroy(&r);
}

TEST(compare_refuses_bad_options)
{
    char path[1024], err[512] = "";
    fox_path(path, sizeof path);
    const texopt_method methods[] = {TEXOPT_METHOD_INPUT};
    const double costs[] = {5.0};
    texopt_compare_options opt;
    memset(&opt, 0, sizeof opt);
    opt.methods = methods;
    opt.method_count = 1;
    opt.costs = costs;
    opt.cost_count = 1;
    texopt_compare_result r;
    CHECK(texopt_compare(path, &opt, &r, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "cost 5") != NULL);
    const double fine[] = {0.5};
    opt.costs = fine;
    CHECK(texopt_compare("/nonexistent/model.glb", &opt, &r, err, sizeof err) != TEXOPT_OK);
}

TEST(target_loss_search_through_files)
{
    char path[1024], out[1100], err[512] = "";
    fox_path(path, sizeof path);
    snprintf(out, sizeof out, "%s/texopt_search_%d.glb", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());
    texopt_params p;
    memset(&p, 0, sizeof p);
    p.method = TEXOPT_METHOD_INPUT;
    p.target_loss = 0.05;
    texopt_evaluate_options eo = {.resolution = 300, .threads = 2};
    texopt_target_search s;
    CHECK_OK(texopt_search_target_loss_file(path, out, &p, &eo, &s, err, sizeof err), err);
    CHECK(s.reached);
    CHECK(s.q <= 0.05);
    CHECK(s.relative_cost < 1.0 && s.relative_cost >= 0.02);
    CHECK(s.evaluations >= 3 && s.evaluations <= 10);
    /* The file left behind is the chosen cost's output and has that loss. */
    texopt_model *in = NULL, *res = NULL;
    CHECK_OK(texopt_model_load(&in, path, NULL, err, sizeof err), err);
    texopt_status st = texopt_model_load(&res, out, NULL, err, sizeof err);
    texopt_evaluation ev;
    if (st == TEXOPT_OK)
        st = texopt_evaluate(in, res, &eo, &ev, err, sizeof err);
    texopt_model_destroy(in);
    texopt_model_destroy(res);
    remove(out);
    CHECK_OK(st, err);
    CHECK_NEAR(ev.q, s.q, 1e-12);
}
