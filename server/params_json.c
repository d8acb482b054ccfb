/* params_json.c - job parameters from and to JSON (see params_json.h). Unknown keys are an
 * error rather than ignored: a typo ("iteration") must not silently run the default. */
#include "params_json.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "texopt.h"

static const char *const budget_names[TEXOPT_BUDGET_COUNT] = {
    [TEXOPT_BUDGET_RELATIVE_COST] = "relative_cost",
    [TEXOPT_BUDGET_TEXTURE_SIZE] = "texture_size",
    [TEXOPT_BUDGET_TARGET_LOSS] = "target_loss",
};

static const char *const known_keys[] = {
    "method",
    "budget",
    "relative_cost",
    "texture_width",
    "texture_height",
    "target_loss",
    "epsilon",
    "iterations",
    "lambda_min",
    "threads",
    "seed",
    "evaluate",
    "eval_resolution",
    "refinements",
    "refine_by",
    "lookup",
    "packing_efficiency",
    "bijective",
    "packing",
    "hessian_floor",
    "metric_candidates",
    "resize_check",
    "charts",
    "parameterizer",
};

static int is_known_key(const char *key)
{
    for (size_t i = 0; i < sizeof known_keys / sizeof known_keys[0]; i++)
        if (strcmp(key, known_keys[i]) == 0)
            return 1;
    return 0;
}

static texopt_status bad(char *err, size_t err_len, const char *key, const char *what)
{
    return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params.%s: %s", key, what);
}

static texopt_status get_number(const cJSON *obj, const char *key, double *out, int *present, char *err, size_t err_len)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    *present = v != NULL;
    if (!v)
        return TEXOPT_OK;
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return bad(err, err_len, key, "must be a finite number");
    *out = v->valuedouble;
    return TEXOPT_OK;
}

static texopt_status get_integer(const cJSON *obj, const char *key, double lo, double hi, double *out, int *present,
                                 char *err, size_t err_len)
{
    texopt_status s = get_number(obj, key, out, present, err, err_len);
    if (s != TEXOPT_OK || !*present)
        return s;
    if (*out != floor(*out))
        return bad(err, err_len, key, "must be an integer");
    if (*out < lo || *out > hi)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params.%s: %.17g is outside %.17g .. %.17g", key,
                           *out, lo, hi);
    return TEXOPT_OK;
}

static texopt_status read_method(const cJSON *obj, texopt_params *p, char *err, size_t err_len)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, "method");
    if (!v)
        return TEXOPT_OK;
    if (!cJSON_IsString(v))
        return bad(err, err_len, "method", "must be a string");
    texopt_method m = texopt_method_from_name(v->valuestring);
    if (m == TEXOPT_METHOD_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "params.method: unknown method '%.64s' (perceptual, input, ssp, tewari, arap)",
                           v->valuestring);
    p->method = m;
    return TEXOPT_OK;
}

/* A key whose string value names one of two settings (from_name: -1 for an unknown name)
 * into *out; `choices` is how the refusal lists them. */
static texopt_status read_named(const cJSON *obj, const char *key, int (*from_name)(const char *), const char *choices,
                                int *out, char *err, size_t err_len)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v)
        return TEXOPT_OK;
    int value = cJSON_IsString(v) ? from_name(v->valuestring) : -1;
    if (value < 0)
        return bad(err, err_len, key, choices);
    *out = value;
    return TEXOPT_OK;
}

/* The budget kind: explicit, or the one whose value key is present; mixing kinds is an error
 * because the engine would silently ignore one of them. */
static texopt_status read_budget(const cJSON *obj, texopt_params *p, char *err, size_t err_len)
{
    double cost = 0, width = 0, height = 0, loss = 0;
    int has_cost, has_width, has_height, has_loss;
    texopt_status s;
    if ((s = get_number(obj, "relative_cost", &cost, &has_cost, err, err_len)) != TEXOPT_OK ||
        (s = get_integer(obj, "texture_width", 1, 16384, &width, &has_width, err, err_len)) != TEXOPT_OK ||
        (s = get_integer(obj, "texture_height", 1, 16384, &height, &has_height, err, err_len)) != TEXOPT_OK ||
        (s = get_number(obj, "target_loss", &loss, &has_loss, err, err_len)) != TEXOPT_OK)
        return s;
    if (has_width != has_height)
        return bad(err, err_len, has_width ? "texture_height" : "texture_width",
                   "texture_width and texture_height go together");
    int kinds = has_cost + has_width + has_loss;
    texopt_budget budget = has_width  ? TEXOPT_BUDGET_TEXTURE_SIZE
                           : has_loss ? TEXOPT_BUDGET_TARGET_LOSS
                                      : TEXOPT_BUDGET_RELATIVE_COST;
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, "budget");
    if (v) {
        if (!cJSON_IsString(v))
            return bad(err, err_len, "budget", "must be a string");
        int found = -1;
        for (int b = 0; b < TEXOPT_BUDGET_COUNT; b++)
            if (strcmp(v->valuestring, budget_names[b]) == 0)
                found = b;
        if (found < 0)
            return bad(err, err_len, "budget", "must be relative_cost, texture_size or target_loss");
        if (kinds == 1 && (texopt_budget)found != budget)
            return bad(err, err_len, "budget", "does not match the budget value given");
        if (found == TEXOPT_BUDGET_TEXTURE_SIZE && !has_width)
            return bad(err, err_len, "budget", "texture_size needs texture_width and texture_height");
        if (found == TEXOPT_BUDGET_TARGET_LOSS && !has_loss)
            return bad(err, err_len, "budget", "target_loss needs the target_loss value");
        budget = (texopt_budget)found;
    }
    if (kinds > 1)
        return bad(err, err_len, "budget", "give only one of relative_cost, texture_width/height, target_loss");
    p->budget = budget;
    if (has_cost) {
        if (cost == 0)
            return bad(err, err_len, "relative_cost", "must be greater than 0");
        p->relative_cost = cost;
    }
    p->texture_width = (int)width;
    p->texture_height = (int)height;
    p->target_loss = loss;
    return TEXOPT_OK;
}

static texopt_status read_rest(const cJSON *obj, texopt_params *p, char *err, size_t err_len)
{
    double v;
    int present;
    texopt_status s;
    if ((s = get_number(obj, "epsilon", &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present && v == 0)
        return bad(err, err_len, "epsilon", "must be greater than 0");
    if (present)
        p->epsilon = v;
    if ((s = get_number(obj, "lambda_min", &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present && v == 0)
        return bad(err, err_len, "lambda_min", "must be greater than 0");
    if (present)
        p->lambda_min = v;
    if ((s = get_integer(obj, "iterations", 1, 10000, &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present)
        p->iterations = (int)v;
    if ((s = get_integer(obj, "threads", 0, 1024, &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present)
        p->threads = (int)v;
    if ((s = get_integer(obj, "seed", 0, 9007199254740992.0, &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present)
        p->seed = (uint64_t)v;
    if ((s = get_integer(obj, "eval_resolution", 0, 8192, &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present)
        p->eval_resolution = (int)v;
    if ((s = get_integer(obj, "refinements", 0, 20, &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present)
        texopt_params_set_refinement_rounds(p, (int)v);
    int refine_measure = -1;
    if ((s = read_named(obj, "refine_by", texopt_refine_measure_from_name, "must be \"baseColor\" or \"lit\"",
                        &refine_measure, err, err_len)) != TEXOPT_OK ||
        (s = read_named(obj, "lookup", texopt_lookup_from_name, "must be \"bilinear\" or \"mipmapped\"", &p->mipmapped,
                        err, err_len)) != TEXOPT_OK ||
        (s = read_named(obj, "packing", texopt_packing_from_name, "must be \"plain\" or \"refine\"", &p->packing_refine,
                        err, err_len)) != TEXOPT_OK)
        return s;
    if (refine_measure >= 0)
        p->refine_lit = texopt_refine_lit_of(refine_measure);
    int charts = p->charts, parameterizer = p->parameterizer;
    if ((s = read_named(obj, "charts", texopt_charts_from_name, "must be \"keep\" or \"new\"", &charts, err,
                        err_len)) != TEXOPT_OK ||
        (s = read_named(obj, "parameterizer", texopt_parameterizer_from_name,
                        "must be \"abf\", \"lscm\", \"tutte\" or \"square\"", &parameterizer, err, err_len)) !=
            TEXOPT_OK)
        return s;
    p->charts = (texopt_charts)charts;
    p->parameterizer = (texopt_parameterizer)parameterizer;
    if ((s = get_number(obj, "packing_efficiency", &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present)
        p->packing_efficiency = v;
    const cJSON *e = cJSON_GetObjectItemCaseSensitive(obj, "evaluate");
    if (e && !cJSON_IsBool(e))
        return bad(err, err_len, "evaluate", "must be true or false");
    p->evaluate = e ? cJSON_IsTrue(e) : 0;
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(obj, "bijective");
    if (b && !cJSON_IsBool(b))
        return bad(err, err_len, "bijective", "must be true or false");
    p->bijective = b ? cJSON_IsTrue(b) : 0;
    if ((s = get_number(obj, "hessian_floor", &v, &present, err, err_len)) != TEXOPT_OK)
        return s;
    if (present && !(v >= 0 && v <= 1))
        return bad(err, err_len, "hessian_floor", "must be in [0, 1]");
    if (present)
        texopt_params_set_hessian_floor(p, v);
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(obj, "metric_candidates");
    if (m && !cJSON_IsBool(m))
        return bad(err, err_len, "metric_candidates", "must be true or false");
    if (m)
        p->metric_candidates = cJSON_IsTrue(m) ? 1 : -1;
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(obj, "resize_check");
    if (r && !cJSON_IsBool(r))
        return bad(err, err_len, "resize_check", "must be true or false");
    if (r)
        p->resize_check = cJSON_IsTrue(r) ? 1 : -1;
    return TEXOPT_OK;
}

texopt_status api_params_from_json(const cJSON *obj, texopt_params *out, char *err, size_t err_len)
{
    texopt_params p;
    memset(&p, 0, sizeof p);
    if (obj && !cJSON_IsObject(obj))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params: must be a JSON object");
    if (obj) {
        for (const cJSON *item = obj->child; item; item = item->next) {
            if (!item->string || !is_known_key(item->string))
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params: unknown key '%.64s'",
                                   item->string ? item->string : "");
            /* cJSON keeps both copies of a key and reads the first: which one the client
             * meant is unknown, so neither is taken. */
            for (const cJSON *later = item->next; later; later = later->next)
                if (later->string && strcmp(later->string, item->string) == 0)
                    return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params: key '%s' given twice",
                                       item->string);
        }
    }
    texopt_status s;
    if (obj &&
        ((s = read_method(obj, &p, err, err_len)) != TEXOPT_OK ||
         (s = read_budget(obj, &p, err, err_len)) != TEXOPT_OK || (s = read_rest(obj, &p, err, err_len)) != TEXOPT_OK))
        return s;
    texopt_params_resolve(&p);
    if ((s = texopt_params_validate(&p, err, err_len)) != TEXOPT_OK)
        return s;
    *out = p;
    return TEXOPT_OK;
}

texopt_status api_params_from_text(const char *text, size_t len, texopt_params *out, char *err, size_t err_len)
{
    char why[128];
    if (texopt_json_check_depth(text, len, TEXOPT_JSON_MAX_DEPTH, why, sizeof why) != TEXOPT_OK)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params: %s", why);
    const char *end = NULL;
    cJSON *obj = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!obj) {
        size_t at = end && end >= text ? (size_t)(end - text) : 0;
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params: not valid JSON (near byte %zu)", at);
    }
    size_t used = (size_t)(end - text);
    while (used < len && isspace((unsigned char)text[used]))
        used++;
    if (used < len) {
        cJSON_Delete(obj);
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "params: text after the JSON object (at byte %zu)",
                           used);
    }
    texopt_status s = api_params_from_json(obj, out, err, err_len);
    cJSON_Delete(obj);
    return s;
}

int api_params_add_text(cJSON *obj, const char *key, const char *text)
{
    cJSON *value;
    char *end = NULL;
    double number = text && *text ? strtod(text, &end) : 0;
    if (text && *text && end && *end == '\0')
        value = cJSON_CreateNumber(number);
    else if (text && strcmp(text, "true") == 0)
        value = cJSON_CreateTrue();
    else if (text && strcmp(text, "false") == 0)
        value = cJSON_CreateFalse();
    else
        value = cJSON_CreateString(text ? text : "");
    if (!value)
        return -1;
    cJSON_DeleteItemFromObjectCaseSensitive(obj, key);
    return cJSON_AddItemToObject(obj, key, value) ? 0 : -1;
}

cJSON *api_params_to_json(const texopt_params *p)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "method", texopt_method_name(p->method));
    cJSON_AddStringToObject(o, "budget",
                            (unsigned)p->budget < TEXOPT_BUDGET_COUNT ? budget_names[p->budget] : "unknown");
    if (p->budget == TEXOPT_BUDGET_RELATIVE_COST)
        cJSON_AddNumberToObject(o, "relative_cost", p->relative_cost);
    if (p->budget == TEXOPT_BUDGET_TEXTURE_SIZE) {
        cJSON_AddNumberToObject(o, "texture_width", p->texture_width);
        cJSON_AddNumberToObject(o, "texture_height", p->texture_height);
    }
    if (p->budget == TEXOPT_BUDGET_TARGET_LOSS)
        cJSON_AddNumberToObject(o, "target_loss", p->target_loss);
    cJSON_AddNumberToObject(o, "epsilon", p->epsilon);
    cJSON_AddNumberToObject(o, "iterations", p->iterations);
    cJSON_AddNumberToObject(o, "lambda_min", p->lambda_min);
    cJSON_AddNumberToObject(o, "threads", p->threads);
    cJSON_AddNumberToObject(o, "seed", (double)p->seed);
    cJSON_AddBoolToObject(o, "evaluate", p->evaluate != 0);
    cJSON_AddNumberToObject(o, "eval_resolution", p->eval_resolution);
    cJSON_AddNumberToObject(o, "refinements", texopt_params_refinement_rounds(p));
    cJSON_AddStringToObject(o, "refine_by", texopt_refine_measure_name(p->refine_lit));
    cJSON_AddStringToObject(o, "lookup", texopt_lookup_name(p->mipmapped));
    cJSON_AddNumberToObject(o, "packing_efficiency", p->packing_efficiency);
    cJSON_AddBoolToObject(o, "bijective", p->bijective != 0);
    cJSON_AddStringToObject(o, "packing", texopt_packing_name(p->packing_refine));
    cJSON_AddNumberToObject(o, "hessian_floor", texopt_params_hessian_floor(p));
    cJSON_AddBoolToObject(o, "metric_candidates", p->metric_candidates > 0);
    cJSON_AddBoolToObject(o, "resize_check", p->resize_check > 0);
    cJSON_AddStringToObject(o, "charts", texopt_charts_name(p->charts));
    cJSON_AddStringToObject(o, "parameterizer", texopt_parameterizer_name(p->parameterizer));
    return o;
}
