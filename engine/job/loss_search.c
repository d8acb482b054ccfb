/* loss_search.c - the target_loss budget of a job (loss_search.h). */
#include "loss_search.h"

#include <string.h>

#include "job_candidates.h"
#include "job_evaluate.h"
#include "job_stats.h"
#include "target_search.h"

typedef struct loss_search {
    texopt_job *job;
    texopt_params p; /* relative-cost budget; relative_cost set per step */
    double from, to; /* progress range of the search */
    int max_evaluations;
    int done;
    job_output kept;
    texopt_evaluation kept_ev;
    texopt_job_stats kept_stats; /* job->stats after the kept step, its domains copied */
    double kept_cost;            /* < 0: none yet */
} loss_search;

#define SEARCH_COST_MIN 0.01
#define SEARCH_COST_MAX 1.0
#define SEARCH_TOLERANCE 0.05
#define SEARCH_MAX_EVALUATIONS 12

/* Keeps a step's output (moved out of *out) and a copy of the statistics it recorded. */
static texopt_status keep_step(loss_search *s, job_output *out, const texopt_evaluation *ev, char *err, size_t err_len)
{
    texopt_domain_stats *domains = job_stats_copy_domains(&s->job->stats);
    if (!domains)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the search's statistics");
    int images = s->job->model->image_count;
    job_output_destroy(&s->kept, images);
    job_stats_free_domains(s->kept_stats.domains, s->kept_stats.domain_count);
    s->kept = *out;
    memset(out, 0, sizeof *out);
    s->kept_ev = *ev;
    s->kept_stats = s->job->stats;
    s->kept_stats.domains = domains;
    s->kept_cost = s->p.relative_cost;
    return TEXOPT_OK;
}

static texopt_status search_step(void *user, double relative_cost, double *q, char *err, size_t err_len)
{
    loss_search *s = user;
    double step = (s->to - s->from) / s->max_evaluations;
    double from = s->from + step * s->done;
    s->p.relative_cost = relative_cost;
    job_output out = {0};
    texopt_evaluation ev;
    texopt_status st = job_run_best_budget(s->job, &s->p, 0, &out, from, from + 0.8 * step, err, err_len);
    if (st == TEXOPT_OK) {
        job_stage(&s->job->jm, "evaluate", from + 0.8 * step, from + step);
        st = job_evaluate_output(s->job, &out, &s->p, &ev, err, err_len);
    }
    if (st == TEXOPT_OK)
        *q = ev.q;
    if (st == TEXOPT_OK && (s->kept_cost < 0 || ev.q <= s->p.target_loss))
        st = keep_step(s, &out, &ev, err, err_len);
    job_output_destroy(&out, s->job->model->image_count);
    s->done++;
    return st;
}

texopt_status job_search_target_loss(texopt_job *job, const texopt_params *p, double from, double to,
                                     texopt_params *chosen, job_output *out, texopt_evaluation *ev, char *err,
                                     size_t err_len)
{
    loss_search s = {
        .job = job, .p = *p, .from = from, .to = to, .max_evaluations = SEARCH_MAX_EVALUATIONS, .kept_cost = -1};
    s.p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    texopt_target_search res;
    texopt_status st = texopt_search_target_loss(search_step, &s, p->target_loss, SEARCH_COST_MIN, SEARCH_COST_MAX,
                                                 SEARCH_TOLERANCE, SEARCH_MAX_EVALUATIONS, &res, err, err_len);
    if (st == TEXOPT_OK && s.kept_cost != res.relative_cost)
        st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "target search: answered c_r %g but kept the step at %g",
                         res.relative_cost, s.kept_cost);
    texopt_job_stats *js = &job->stats;
    if (st == TEXOPT_OK) {
        job_stats_free_domains(js->domains, js->domain_count);
        *js = s.kept_stats;
        *out = s.kept;
        *ev = s.kept_ev;
    } else {
        job_output_destroy(&s.kept, job->model->image_count);
        job_stats_free_domains(s.kept_stats.domains, s.kept_stats.domain_count);
    }
    if (st != TEXOPT_OK)
        return st;
    js->has_search = 1;
    js->target_loss = p->target_loss;
    js->target_reached = res.reached;
    js->search_evaluations = res.evaluations;
    js->search_cost_below = res.cost_below;
    js->search_q_below = res.q_below;
    js->relative_cost = res.relative_cost;
    *chosen = s.p;
    chosen->relative_cost = res.relative_cost;
    chosen->evaluate = 1; /* the result's q is part of the answer */
    return TEXOPT_OK;
}
