/* pipeline_budget_checks.h - checks of the pipeline's per-budget part shared by
 * test_pipeline_budget.c (cheap methods, every build) and test_pipeline_budget_slow.c (the
 * perceptual method): one job writing several budgets equals separate runs, and the
 * target_loss budget's answer against independent runs. Header only. */
#ifndef TEXOPT_TEST_PIPELINE_BUDGET_CHECKS_H
#define TEXOPT_TEST_PIPELINE_BUDGET_CHECKS_H

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pipeline.h"
#include "pipeline_scratch.h"
#include "test.h"

static inline double number_at(cJSON *obj, const char *a, const char *b)
{
    cJSON *v = cJSON_GetObjectItem(obj, a);
    if (b)
        v = cJSON_GetObjectItem(v, b);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static inline cJSON *first_domain(cJSON *root)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(root, "domains"), 0);
}

/* Same UVs and same texels. */
static inline int same_output(const char *a, const char *b)
{
    texopt_model *x = load(a), *y = load(b);
    int same = x && y && x->vertex_count == y->vertex_count && x->image_count == y->image_count;
    for (size_t i = 0; same && i < 2 * x->vertex_count; i++)
        same = x->uvs[i] == y->uvs[i];
    for (int i = 0; same && i < x->image_count; i++) {
        const texopt_image *p = &x->images[i], *q = &y->images[i];
        same = p->width == q->width && p->height == q->height && p->channels == q->channels &&
               memcmp(p->pixels, q->pixels, sizeof(float) * p->width * p->height * p->channels) == 0;
    }
    texopt_model_destroy(x);
    texopt_model_destroy(y);
    return same;
}

/* One job at 0.7 then 0.3 against a fresh run at 0.3: same UVs and texels. */
static inline void check_job_reuse(texopt_method method)
{
    scratch s;
    CHECK(scratch_init(&s, 3, 64, "half") == 0);
    texopt_params p = {0};
    p.method = method;
    p.threads = 1;
    p.iterations = 5;
    char err[512] = "";
    texopt_job *job = NULL;
    CHECK_OK(texopt_job_create(&job, s.in, &p, NULL, err, sizeof err), err);
    /* 0.7 first, so the 0.3 output below comes after another budget on the same job. */
    texopt_job_budget b = {TEXOPT_BUDGET_RELATIVE_COST, 0.7, 0, 0, 0};
    CHECK_OK(texopt_job_write(job, &b, s.again, NULL, err, sizeof err), err);
    b.relative_cost = 0.3;
    CHECK_OK(texopt_job_write(job, &b, s.out, NULL, err, sizeof err), err);
    texopt_job_destroy(job);
    CHECK(!same_output(s.out, s.again));
    p.relative_cost = 0.3;
    CHECK_OK(texopt_optimize_file(s.in, s.again, NULL, &p, NULL, err, sizeof err), err);
    CHECK(same_output(s.out, s.again));
    texopt_job_destroy(NULL);
    scratch_free(&s);
}

/* j without its timings (every member named "seconds", at any depth). */
static inline void drop_seconds(cJSON *j)
{
    cJSON_DeleteItemFromObject(j, "seconds");
    cJSON *child;
    cJSON_ArrayForEach(child, j) drop_seconds(child);
}

/* Whether x and y are the same, numbers within relative tolerance rel (members in order). */
static inline int same_within(const cJSON *x, const cJSON *y, double rel)
{
    if (cJSON_IsNumber(x) && cJSON_IsNumber(y))
        return fabs(x->valuedouble - y->valuedouble) <= rel * fmax(fabs(x->valuedouble), fabs(y->valuedouble));
    if (!(cJSON_IsObject(x) && cJSON_IsObject(y)) && !(cJSON_IsArray(x) && cJSON_IsArray(y)))
        return cJSON_Compare(x, y, 1);
    const cJSON *a = x->child, *b = y->child;
    for (; a && b; a = a->next, b = b->next)
        if ((a->string || b->string) && (!a->string || !b->string || strcmp(a->string, b->string) != 0))
            return 0;
        else if (!same_within(a, b, rel))
            return 0;
    return !a && !b;
}

/* Whether member `name` of a and b is the same but for timings (both absent counts), numbers
 * within relative tolerance rel. */
static inline int same_but_timings(cJSON *a, cJSON *b, const char *name, double rel)
{
    cJSON *x = cJSON_GetObjectItem(a, name), *y = cJSON_GetObjectItem(b, name);
    if (!x || !y)
        return !x && !y;
    drop_seconds(x);
    drop_seconds(y);
    return same_within(x, y, rel);
}

/* Runs budget target_loss and checks the answer against independent runs at the chosen cost
 * (same file, same per-domain and candidate statistics: the search hands over the step it
 * chose rather than making it again) and at the largest cost the search found too lossy. */
static inline void check_target_loss(texopt_method method, double target)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 128, "checker") == 0);
    texopt_params p = {0};
    p.method = method;
    p.threads = 1;
    p.iterations = 5;
    p.eval_resolution = 128;
    p.budget = TEXOPT_BUDGET_TARGET_LOSS;
    p.target_loss = target;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    cJSON *search_run = read_json(s.stats), *st;
    CHECK(search_run != NULL);
    cJSON *search = cJSON_GetObjectItem(search_run, "target_search");
    CHECK(search != NULL);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(search, "reached")));
    double cost = number_at(search, "relative_cost", NULL), q = number_at(search, "q", NULL);
    double below = number_at(search, "relative_cost_below", NULL), q_below = number_at(search, "q_below", NULL);
    CHECK(q <= target);
    CHECK_NEAR(number_at(search_run, "evaluation", "q"), q, 0);
    CHECK(number_at(search, "evaluations", NULL) >= 3);
    /* The next cost down was tried and missed, within the search's 5% bracket. */
    CHECK(below > 0 && below < cost && cost / below <= 1.05 + 1e-9);
    CHECK(q_below > target);
    /* Independent runs with a relative cost give the same answers. */
    p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    p.evaluate = 1;
    p.relative_cost = below;
    CHECK_OK(texopt_optimize_file(s.in, s.again, s.stats, &p, NULL, err, sizeof err), err);
    st = read_json(s.stats);
    CHECK(number_at(st, "evaluation", "q") > target);
    cJSON_Delete(st);
    p.relative_cost = cost;
    CHECK_OK(texopt_optimize_file(s.in, s.again, s.stats, &p, NULL, err, sizeof err), err);
    cJSON *at_cost = read_json(s.stats);
    CHECK(number_at(at_cost, "evaluation", "q") <= target);
    int same_domains = same_but_timings(search_run, at_cost, "domains", 1e-12);
    /* The cost read back from the statistics is printed to 15 digits (cJSON), which can move
     * it by an ulp from the step's: a metric candidate, scaled uniformly by the budget, then
     * measures q different in the 9th digit (the same saved file). */
    int same_choice = same_but_timings(search_run, at_cost, "allocation_choice", 1e-7);
    cJSON_Delete(at_cost);
    cJSON_Delete(search_run);
    CHECK(same_domains);
    CHECK(same_choice);
    CHECK(same_output(s.out, s.again));
    scratch_free(&s);
}

#endif
