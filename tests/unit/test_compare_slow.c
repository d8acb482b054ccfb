/* test_compare_slow.c - compare through the real pipeline (engine/compare/compare.h), on
 * tests/data/Fox with the cheap "input" method. (The target_loss budget is tested in
 * test_pipeline_budget, through the pipeline that runs it.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "report.h"
#include "test.h"

static void fox_path(char *path, size_t len)
{
    snprintf(path, len, "%s/Fox/Fox.glb", TEXOPT_TEST_DATA_DIR);
}

static void options_for(texopt_compare_options *opt, const texopt_method *methods, int method_count,
                        const double *costs, int cost_count)
{
    memset(opt, 0, sizeof *opt);
    opt->methods = methods;
    opt->method_count = method_count;
    opt->costs = costs;
    opt->cost_count = cost_count;
}

TEST(compare_input_method_curve)
{
    char path[1024], err[512] = "";
    fox_path(path, sizeof path);
    const texopt_method methods[] = {TEXOPT_METHOD_INPUT};
    const double costs[] = {1.0, 0.25, 0.0625};
    texopt_compare_options opt;
    options_for(&opt, methods, 1, costs, 3);
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
    /* The showcase's own evaluation is kept for the report: q is the mean of its views. */
    CHECK_EQ_INT(c->showcase_evaluation.view_count, 20);
    double sum = 0;
    for (int v = 0; v < 20; v++)
        sum += c->showcase_evaluation.view_gmsd[v];
    CHECK_NEAR(sum / 20, c->points[1].q, 1e-12);
    /* Equal-loss cost of the curve against itself: its own point. */
    CHECK_NEAR(texopt_compare_cost_at_loss(c, c->points[1].q), c->points[1].cost_achieved, 1e-9);
    char *html = NULL;
    CHECK_OK(texopt_report_html(&r, NULL, &html, err, sizeof err), err);
    CHECK(strstr(html, "data-method=\"input\"") != NULL);
    CHECK(strstr(html, "<br>GMSD ") != NULL);
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
    options_for(&opt, methods, 1, costs, 1);
    texopt_compare_result r;
    CHECK(texopt_compare(path, &opt, &r, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "cost 5") != NULL);
    const double fine[] = {0.5};
    opt.costs = fine;
    CHECK(texopt_compare("/nonexistent/model.glb", &opt, &r, err, sizeof err) != TEXOPT_OK);
}

/* A given output is measured as it is, not produced again: Fox itself standing for the arap
 * method at c_r 0.5 comes back with q 0 and the input's full cost, which no arap run at 0.5
 * could give. */
TEST(compare_measures_given_output)
{
    char path[1024], err[512] = "";
    fox_path(path, sizeof path);
    const texopt_method methods[] = {TEXOPT_METHOD_INPUT, TEXOPT_METHOD_ARAP};
    const char *given[] = {NULL, path};
    const double costs[] = {0.5};
    texopt_compare_options opt;
    options_for(&opt, methods, 2, costs, 1);
    opt.evaluate.resolution = 300;
    opt.given_outputs = given;
    texopt_compare_result r;
    CHECK_OK(texopt_compare(path, &opt, &r, err, sizeof err), err);
    const texopt_compare_point *in = &r.curves[0].points[0], *arap = &r.curves[1].points[0];
    CHECK_MSG(in->status == TEXOPT_OK && arap->status == TEXOPT_OK, "%s / %s", in->message, arap->message);
    CHECK_NEAR(in->cost_achieved, 0.5, 0.02);
    CHECK(in->q > 0);
    CHECK(arap->q == 0.0);
    CHECK_NEAR(arap->cost_achieved, 1.0, 1e-12);
    CHECK(arap->seconds_optimize == 0.0);
    CHECK(r.curves[1].showcase != NULL);
    texopt_compare_result_destroy(&r);

    const double two[] = {0.5, 0.25};
    opt.costs = two;
    opt.cost_count = 2;
    CHECK(texopt_compare(path, &opt, &r, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "given outputs") != NULL);
}
