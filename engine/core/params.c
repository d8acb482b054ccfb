/* params.c - defaults and range checks of texopt_params. */
#include "params.h"

#include <math.h>
#include <string.h>

static const char *const method_names[TEXOPT_METHOD_COUNT] = {
    [TEXOPT_METHOD_PERCEPTUAL] = "perceptual", [TEXOPT_METHOD_INPUT] = "input", [TEXOPT_METHOD_SSP] = "ssp",
    [TEXOPT_METHOD_TEWARI] = "tewari",         [TEXOPT_METHOD_ARAP] = "arap",   [TEXOPT_METHOD_PAPER] = "paper",
};

const char *texopt_method_name(texopt_method method)
{
    if ((unsigned)method >= TEXOPT_METHOD_COUNT)
        return "unknown";
    return method_names[method];
}

texopt_method texopt_method_from_name(const char *name)
{
    for (int m = 0; m < TEXOPT_METHOD_COUNT; m++)
        if (name && strcmp(name, method_names[m]) == 0)
            return (texopt_method)m;
    return TEXOPT_METHOD_COUNT;
}

const char *texopt_charts_name(texopt_charts charts)
{
    return charts == TEXOPT_CHARTS_NEW ? "new" : "keep";
}

int texopt_charts_from_name(const char *name)
{
    for (int c = 0; c < TEXOPT_CHARTS_COUNT; c++)
        if (name && strcmp(name, texopt_charts_name((texopt_charts)c)) == 0)
            return c;
    return -1;
}

static const char *const parameterizer_names[TEXOPT_PARAMETERIZER_COUNT] = {[TEXOPT_PARAMETERIZER_ABF] = "abf",
                                                                            [TEXOPT_PARAMETERIZER_LSCM] = "lscm",
                                                                            [TEXOPT_PARAMETERIZER_TUTTE] = "tutte",
                                                                            [TEXOPT_PARAMETERIZER_SQUARE] = "square"};

const char *texopt_parameterizer_name(texopt_parameterizer p)
{
    return (unsigned)p < TEXOPT_PARAMETERIZER_COUNT ? parameterizer_names[p] : NULL;
}

int texopt_parameterizer_from_name(const char *name)
{
    for (int i = 0; name && i < TEXOPT_PARAMETERIZER_COUNT; i++)
        if (strcmp(name, parameterizer_names[i]) == 0)
            return i;
    return -1;
}

const char *texopt_refine_measure_name(int refine_lit)
{
    return refine_lit >= 0 ? "lit" : "baseColor";
}

/* Which of a two-way setting's values (0 or 1) name_of names `name`; -1 for neither. */
static int two_way_from_name(const char *name, const char *(*name_of)(int))
{
    for (int v = 0; v <= 1; v++)
        if (name && strcmp(name, name_of(v)) == 0)
            return v;
    return -1;
}

int texopt_refine_measure_from_name(const char *name)
{
    if (name && strcmp(name, "lit") == 0)
        return 1;
    return name && strcmp(name, "baseColor") == 0 ? 0 : -1;
}

int texopt_refine_lit_of(int measure)
{
    return measure > 0 ? 1 : -1;
}

const char *texopt_lookup_name(int mipmapped)
{
    return mipmapped ? "mipmapped" : "bilinear";
}

int texopt_lookup_from_name(const char *name)
{
    return two_way_from_name(name, texopt_lookup_name);
}

const char *texopt_packing_name(int refine)
{
    return refine ? "refine" : "plain";
}

int texopt_packing_from_name(const char *name)
{
    return two_way_from_name(name, texopt_packing_name);
}

void texopt_params_resolve(texopt_params *p)
{
    if (p->relative_cost == 0)
        p->relative_cost = 1.0;
    if (p->epsilon == 0)
        p->epsilon = p->method == TEXOPT_METHOD_PAPER ? TEXOPT_PAPER_EPSILON : TEXOPT_DEFAULT_EPSILON;
    if (p->iterations == 0)
        p->iterations = 100;
    if (p->lambda_min == 0)
        p->lambda_min = 0.1;
    if (p->refinements == 0)
        p->refinements = TEXOPT_DEFAULT_REFINEMENTS;
    if (p->hessian_floor == 0)
        p->hessian_floor = TEXOPT_DEFAULT_HESSIAN_FLOOR;
    if (p->metric_candidates == 0)
        p->metric_candidates = 1;
    if (p->resize_check == 0)
        p->resize_check = 1;
    if (p->refine_lit == 0)
        p->refine_lit = 1;
    /* Stage 2's barrier keeps triangles from flipping, not a chart from running over itself.
     * New charts do so where the input's did not: their free boundaries (abf, lscm) meet
     * targets restated from another layout, and a chart over itself shows one part's texels
     * on another (docs/benchmarks.md "New charts over themselves"). */
    if (p->charts == TEXOPT_CHARTS_NEW)
        p->bijective = 1;
    if (p->packing_efficiency > 0)
        p->packing_refine = 1;
    else if (p->packing_refine)
        p->packing_efficiency = TEXOPT_DEFAULT_PACKING_EFFICIENCY;
}

int texopt_params_refinement_rounds(const texopt_params *p)
{
    return p->refinements > 0 ? p->refinements : 0;
}

void texopt_params_set_refinement_rounds(texopt_params *p, int rounds)
{
    p->refinements = rounds == 0 ? -1 : rounds;
}

double texopt_params_hessian_floor(const texopt_params *p)
{
    return p->hessian_floor > 0 ? p->hessian_floor : 0;
}

void texopt_params_set_hessian_floor(texopt_params *p, double factor)
{
    p->hessian_floor = factor == 0 ? -1 : factor;
}

texopt_status texopt_params_validate(const texopt_params *p, char *err, size_t err_len)
{
    if ((unsigned)p->method >= TEXOPT_METHOD_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "method: unknown value %d", (int)p->method);
    if ((unsigned)p->budget >= TEXOPT_BUDGET_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "budget: unknown value %d", (int)p->budget);
    if (!(p->relative_cost > 0 && p->relative_cost <= 4))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "relative_cost: %g is outside (0, 4]",
                           p->relative_cost);
    if (p->budget == TEXOPT_BUDGET_TEXTURE_SIZE &&
        (p->texture_width < 1 || p->texture_height < 1 || p->texture_width > 16384 || p->texture_height > 16384))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "texture_size: %dx%d is outside 1x1 .. 16384x16384",
                           p->texture_width, p->texture_height);
    if (p->budget == TEXOPT_BUDGET_TARGET_LOSS && !(p->target_loss > 0 && p->target_loss < 1))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "target_loss: %g is outside (0, 1)",
                           p->target_loss);
    if (!(p->epsilon > 0 && p->epsilon < 1))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "epsilon: %g is outside (0, 1)", p->epsilon);
    if (p->iterations < 1 || p->iterations > 10000)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "iterations: %d is outside 1 .. 10000",
                           p->iterations);
    if (!(p->lambda_min > 0 && p->lambda_min < 1))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "lambda_min: %g is outside (0, 1)", p->lambda_min);
    if (p->threads < 0 || p->threads > 1024)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "threads: %d is outside 0 .. 1024", p->threads);
    if (p->eval_resolution < 0 || p->eval_resolution > 8192)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "eval_resolution: %d is outside 0 .. 8192",
                           p->eval_resolution);
    if (p->refinements < -1 || p->refinements > 20)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "refinements: %d is outside -1 .. 20",
                           p->refinements);
    if (!(p->packing_efficiency >= 0 && p->packing_efficiency < 1))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "packing_efficiency: %g is outside [0, 1)",
                           p->packing_efficiency);
    if (!(p->hessian_floor == -1 || (p->hessian_floor > 0 && p->hessian_floor <= 1)))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "hessian_floor: %g is neither -1 nor in (0, 1]",
                           p->hessian_floor);
    if (p->metric_candidates != -1 && p->metric_candidates != 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "metric_candidates: %d is neither -1 nor 1",
                           p->metric_candidates);
    if (p->resize_check != -1 && p->resize_check != 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "resize_check: %d is neither -1 nor 1",
                           p->resize_check);
    if (p->refine_lit != -1 && p->refine_lit != 1)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "refine_lit: %d is neither -1 nor 1",
                           p->refine_lit);
    if ((unsigned)p->charts >= TEXOPT_CHARTS_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "charts: unknown value %d", (int)p->charts);
    if ((unsigned)p->parameterizer >= TEXOPT_PARAMETERIZER_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "parameterizer: unknown value %d",
                           (int)p->parameterizer);
    if (!isfinite(p->relative_cost) || !isfinite(p->epsilon))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "parameters must be finite");
    return TEXOPT_OK;
}
