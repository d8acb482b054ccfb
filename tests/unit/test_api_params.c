/* test_api_params.c - job params from JSON: defaults, every key, budget inference, unknown
 * keys and wrong types refused by name, and the JSON round trip. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "params_json.h"
#include "test.h"

static texopt_status parse(const char *text, texopt_params *p, char *err)
{
    return api_params_from_text(text, strlen(text), p, err, 256);
}

TEST(empty_object_gives_paper_defaults)
{
    texopt_params p;
    char err[256] = "";
    CHECK_OK(parse("{}", &p, err), err);
    CHECK_EQ_INT(p.method, TEXOPT_METHOD_PERCEPTUAL);
    CHECK_EQ_INT(p.budget, TEXOPT_BUDGET_RELATIVE_COST);
    CHECK_NEAR(p.relative_cost, 1.0, 0);
    CHECK_NEAR(p.epsilon, 0.03, 0);
    CHECK_EQ_INT(p.iterations, 100);
    CHECK_NEAR(p.lambda_min, 0.1, 0);
    CHECK_EQ_INT(p.evaluate, 0);
    CHECK_EQ_INT(p.refinements, 4);
    CHECK_EQ_INT(p.refine_lit, 1); /* lit */
    CHECK_EQ_INT(p.mipmapped, 0);
    CHECK_NEAR(p.packing_efficiency, 0, 0);
    CHECK_EQ_INT(p.bijective, 0);
    CHECK_EQ_INT(p.packing_refine, 0);
    CHECK_NEAR(p.hessian_floor, TEXOPT_DEFAULT_HESSIAN_FLOOR, 0);
    CHECK_EQ_INT(p.metric_candidates, 1);
    CHECK_EQ_INT(p.resize_check, 1);
}

TEST(every_key_is_read)
{
    texopt_params p;
    char err[256] = "";
    CHECK_OK(parse("{\"method\":\"arap\",\"relative_cost\":0.25,\"epsilon\":0.02,\"iterations\":7,"
                   "\"lambda_min\":0.3,\"threads\":3,\"seed\":123456789012,\"evaluate\":true,"
                   "\"eval_resolution\":256,\"refinements\":5,\"refine_by\":\"lit\",\"lookup\":\"mipmapped\","
                   "\"packing_efficiency\":0.75,\"bijective\":true,\"packing\":\"refine\",\"hessian_floor\":0.25,"
                   "\"metric_candidates\":false,\"resize_check\":false}",
                   &p, err),
             err);
    CHECK_EQ_INT(p.method, TEXOPT_METHOD_ARAP);
    CHECK_NEAR(p.relative_cost, 0.25, 0);
    CHECK_NEAR(p.epsilon, 0.02, 0);
    CHECK_EQ_INT(p.iterations, 7);
    CHECK_NEAR(p.lambda_min, 0.3, 0);
    CHECK_EQ_INT(p.threads, 3);
    CHECK(p.seed == 123456789012ull);
    CHECK_EQ_INT(p.evaluate, 1);
    CHECK_EQ_INT(p.eval_resolution, 256);
    CHECK_EQ_INT(p.refinements, 5);
    CHECK_EQ_INT(p.refine_lit, 1);
    CHECK_EQ_INT(p.mipmapped, 1);
    CHECK_NEAR(p.packing_efficiency, 0.75, 0);
    CHECK_EQ_INT(p.bijective, 1);
    CHECK_EQ_INT(p.packing_refine, 1);
    CHECK_NEAR(p.hessian_floor, 0.25, 0);
    CHECK_EQ_INT(p.metric_candidates, -1);
    CHECK_EQ_INT(p.resize_check, -1);
    CHECK_OK(parse("{\"refinements\":0,\"hessian_floor\":0}", &p, err), err);
    CHECK_EQ_INT(p.refinements, -1);    /* none, not the engine's default */
    CHECK_NEAR(p.hessian_floor, -1, 0); /* none, likewise */
}

TEST(budget_is_inferred_from_its_value)
{
    texopt_params p;
    char err[256] = "";
    CHECK_OK(parse("{\"texture_width\":512,\"texture_height\":256}", &p, err), err);
    CHECK_EQ_INT(p.budget, TEXOPT_BUDGET_TEXTURE_SIZE);
    CHECK_EQ_INT(p.texture_width, 512);
    CHECK_EQ_INT(p.texture_height, 256);
    CHECK_OK(parse("{\"target_loss\":0.05}", &p, err), err);
    CHECK_EQ_INT(p.budget, TEXOPT_BUDGET_TARGET_LOSS);
    CHECK_NEAR(p.target_loss, 0.05, 0);
    CHECK_OK(parse("{\"budget\":\"texture_size\",\"texture_width\":64,\"texture_height\":64}", &p, err), err);
    CHECK_EQ_INT(p.budget, TEXOPT_BUDGET_TEXTURE_SIZE);
}

static void check_refused(const char *text, const char *needle)
{
    texopt_params p;
    char err[256] = "";
    texopt_status s = parse(text, &p, err);
    CHECK_MSG(s == TEXOPT_E_INVALID_ARGUMENT, "%s was accepted", text);
    CHECK_MSG(strstr(err, needle) != NULL, "%s: message '%s' does not contain '%s'", text, err, needle);
}

TEST(bad_params_are_refused_by_name)
{
    check_refused("{\"iteration\":5}", "unknown key 'iteration'");
    check_refused("{\"method\":\"fast\"}", "unknown method 'fast'");
    check_refused("{\"method\":3}", "params.method");
    check_refused("{\"iterations\":2.5}", "params.iterations: must be an integer");
    check_refused("{\"iterations\":0}", "params.iterations");
    check_refused("{\"iterations\":10001}", "params.iterations");
    check_refused("{\"iterations\":\"7\"}", "params.iterations: must be a finite number");
    check_refused("{\"relative_cost\":4.5}", "relative_cost");
    check_refused("{\"relative_cost\":0}", "params.relative_cost");
    check_refused("{\"epsilon\":1}", "epsilon");
    check_refused("{\"evaluate\":1}", "params.evaluate");
    check_refused("{\"bijective\":\"yes\"}", "params.bijective");
    check_refused("{\"texture_width\":64}", "texture_height");
    check_refused("{\"relative_cost\":0.5,\"target_loss\":0.1}", "only one of");
    check_refused("{\"budget\":\"target_loss\"}", "needs the target_loss");
    check_refused("{\"budget\":\"relative_cost\",\"target_loss\":0.1}", "does not match");
    check_refused("{\"seed\":-1}", "params.seed");
    check_refused("{\"refinements\":21}", "params.refinements");
    check_refused("{\"refinements\":-1}", "params.refinements");
    check_refused("{\"refine_by\":\"shiny\"}", "params.refine_by");
    check_refused("{\"refine_by\":1}", "params.refine_by");
    check_refused("{\"lookup\":\"trilinear\"}", "params.lookup");
    check_refused("{\"lookup\":true}", "params.lookup");
    check_refused("{\"packing\":\"tight\"}", "params.packing");
    check_refused("{\"packing_efficiency\":1}", "packing_efficiency");
    check_refused("{\"packing_efficiency\":-0.1}", "packing_efficiency");
    check_refused("{\"hessian_floor\":1.5}", "params.hessian_floor");
    check_refused("{\"hessian_floor\":-1}", "params.hessian_floor");
    check_refused("{\"metric_candidates\":\"no\"}", "params.metric_candidates");
    check_refused("{\"resize_check\":0}", "params.resize_check");
    check_refused("[1,2]", "must be a JSON object");
    check_refused("{\"method\":\"input\",", "not valid JSON");
}

TEST(trailing_text_duplicate_keys_and_deep_nesting_are_refused)
{
    check_refused("{\"method\":\"input\"} x", "text after the JSON object");
    check_refused("{\"method\":\"input\"}{}", "text after the JSON object");
    check_refused("{\"method\":\"input\",\"method\":\"arap\"}", "key 'method' given twice");
    check_refused("{\"seed\":1,\"iterations\":3,\"seed\":2}", "key 'seed' given twice");
    texopt_params p;
    char err[256];
    CHECK_OK(parse("{\"method\":\"input\"} \n\t ", &p, err), err);
    /* Deeper than cJSON's own limit of 1000, which it reaches by recursing. */
    enum { DEPTH = 5000 };
    char *deep = malloc(2 * DEPTH + 16);
    CHECK(deep);
    size_t n = 0;
    n += (size_t)sprintf(deep, "{\"seed\":");
    for (int i = 0; i < DEPTH; i++)
        deep[n++] = '[';
    for (int i = 0; i < DEPTH; i++)
        deep[n++] = ']';
    deep[n++] = '}';
    texopt_status s = api_params_from_text(deep, n, &p, err, sizeof err);
    free(deep);
    CHECK(s == TEXOPT_E_INVALID_ARGUMENT);
    CHECK_MSG(strstr(err, "nests deeper than") != NULL, "%s", err);
}

TEST(query_text_becomes_typed_values)
{
    cJSON *o = cJSON_CreateObject();
    CHECK(api_params_add_text(o, "method", "input") == 0);
    CHECK(api_params_add_text(o, "iterations", "12") == 0);
    CHECK(api_params_add_text(o, "evaluate", "true") == 0);
    texopt_params p;
    char err[256] = "";
    texopt_status s = api_params_from_json(o, &p, err, sizeof err);
    cJSON_Delete(o);
    CHECK_OK(s, err);
    CHECK_EQ_INT(p.method, TEXOPT_METHOD_INPUT);
    CHECK_EQ_INT(p.iterations, 12);
    CHECK_EQ_INT(p.evaluate, 1);
}

TEST(params_survive_a_json_round_trip)
{
    texopt_params p, q;
    char err[256] = "";
    CHECK_OK(parse("{\"method\":\"tewari\",\"texture_width\":300,\"texture_height\":200,\"epsilon\":0.03,"
                   "\"iterations\":9,\"seed\":77,\"evaluate\":true,\"packing_efficiency\":0.8}",
                   &p, err),
             err);
    for (int refinements = -1; refinements <= 3; refinements += 4) {
        p.refinements = refinements; /* none, and some */
        p.refine_lit = refinements > 0 ? 1 : -1;
        p.mipmapped = refinements > 0;
        p.hessian_floor = refinements > 0 ? 0.3 : -1;
        p.metric_candidates = refinements > 0 ? 1 : -1;
        p.resize_check = refinements > 0 ? -1 : 1;
        cJSON *o = api_params_to_json(&p);
        CHECK(o != NULL);
        texopt_status s = api_params_from_json(o, &q, err, sizeof err);
        cJSON_Delete(o);
        CHECK_OK(s, err);
        CHECK(memcmp(&p, &q, sizeof p) == 0);
    }
}
