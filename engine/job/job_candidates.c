/* job_candidates.c - the best layout of one budget: candidates, refinement, choice
 * (job_candidates.h). */
#include "job_candidates.h"

#include <string.h>

#include "budget_layout.h"
#include "candidate.h"
#include "job_evaluate.h"
#include "job_refine.h"
#include "job_stats.h"
#include "resize_check.h"

/* The perceptual candidates: stage 1's targets allocated to the budget (target_allocation.h) with
 * singular values capped at input density, the same capped at 1.5x it, and the targets as
 * they are (cap 0), scaled uniformly by the budget. None wins everywhere
 * (BENCHMARKS.md@9f788a8 "Quality", "A candidate denser than the input"): the uniform one on spot,
 * the dense one on Duck at c_r 0.1, 0.2 and 1 and on WaterBottle at 1, giving the
 * triangles the first one capped more texels than the input has (tewari's targets put up
 * to 1.8x on Duck's pupils' edge); cap 2 measured no better. Then the signal metrics'
 * targets as they are, the layouts of methods tewari and ssp: at the smallest budgets stage
 * 1's targets, found at one loss threshold, spread too few texels where the loss is
 * (CesiumMan at c_r 0.1: q 0.053 for the best of them before the refinement, 0.034 for
 * tewari's; WaterBottle 0.019 against ssp's 0.0138; BENCHMARKS.md@9f788a8 "The signal metrics'
 * layouts as candidates"); refine_best decides between the best of each kind. */
enum { CANDIDATE_UNIFORM, CANDIDATE_ALLOCATED, CANDIDATE_DENSE, CANDIDATE_HESSIAN, CANDIDATE_STRETCH, CANDIDATES };
static const double candidate_cap[CANDIDATES] = {0.0, 1.0, 1.5, 0.0, 0.0};
static const target_source candidate_source[CANDIDATES] = {SOURCE_STAGE1, SOURCE_STAGE1, SOURCE_STAGE1, SOURCE_HESSIAN,
                                                           SOURCE_STRETCH};
static const char *const candidate_name[CANDIDATES] = {"uniform", "allocated", "allocated_dense", "hessian",
                                                       "signal_stretch"};

/* The candidates of one budget and which were made: best[0] is stage 1's with the smallest
 * q, best[1] the metric one's (-1 when none was made). */
typedef struct candidate_set {
    candidate cand[CANDIDATES];
    int made[CANDIDATES];
    int best[2];
} candidate_set;

/* Whether the allocation capped any target of the candidate (else one with a higher cap
 * would be the same layout). */
static int allocation_capped(const candidate *c, int domain_count)
{
    for (int d = 0; d < domain_count; d++)
        if (c->domains[d].has_allocation && c->domains[d].allocation_capped_share > 0)
            return 1;
    return 0;
}

/* Whether the job makes candidate i (the dense one only when the cap at input density bound
 * a target of the allocated one, the metric ones when params.metric_candidates asks). */
static int candidate_wanted(const texopt_job *job, const candidate *cand, int i)
{
    if (i == CANDIDATE_DENSE)
        return allocation_capped(&cand[CANDIDATE_ALLOCATED], job->stats.domain_count);
    if (candidate_source[i] != SOURCE_STAGE1)
        return job->params.metric_candidates > 0;
    return 1;
}

/* How candidate i of the budget p is made. */
static layout_run candidate_run(const texopt_params *p, int i)
{
    layout_run run = {.p = p, .source = candidate_source[i], .allocating = candidate_cap[i], .plan = BAKE_EVALUATED};
    return run;
}

/* Makes the candidates of one budget in their order, evaluates them in one pass on the
 * choice's views and finds the best of each kind, a tie keeping the earlier, simpler one. */
static texopt_status run_candidates(texopt_job *job, const texopt_params *p, candidate_set *s, double from, double to,
                                    double chosen, char *err, size_t err_len)
{
    const job_output *outs[CANDIDATES];
    int n = 0;
    texopt_status st = TEXOPT_OK;
    for (int i = 0; i < CANDIDATES && st == TEXOPT_OK; i++) {
        if (!candidate_wanted(job, s->cand, i))
            continue;
        layout_run how = candidate_run(p, i);
        st = job_run_candidate(job, &how, &s->cand[i], from + (to - from) * i / CANDIDATES,
                               from + (to - from) * (i + 1) / CANDIDATES, err, err_len);
        s->made[i] = st == TEXOPT_OK;
        outs[n++] = &s->cand[i].out;
    }
    texopt_evaluation evs[CANDIDATES];
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "evaluate", to, chosen);
        job_screen screen = {CHOICE_CAMERAS, 0, NULL, NULL};
        st = job_evaluate_outputs(job, outs, n, p, &screen, evs, err, err_len);
    }
    s->best[0] = s->best[1] = -1;
    for (int i = 0, e = 0; i < CANDIDATES && st == TEXOPT_OK; i++) {
        if (!s->made[i])
            continue;
        s->cand[i].ev = evs[e++];
        int *b = &s->best[candidate_source[i] != SOURCE_STAGE1];
        if (*b < 0 || s->cand[i].ev.q < s->cand[*b].ev.q)
            *b = i;
    }
    return st;
}

/* What a candidate's layouts and bakes took (its share of the statistics' stage seconds). */
static double candidate_seconds(const candidate *c, int domain_count)
{
    double s = 0;
    for (int d = 0; d < domain_count; d++)
        s += c->domains[d].seconds_stage2 + c->domains[d].seconds_pack + c->domains[d].seconds_bake;
    return s;
}

/* The candidates' q, the choice and what it cost, in the statistics (the refinement's are
 * job_refine.h's). */
static void record_choice(texopt_job_stats *js, const texopt_evaluation *evs, const int *made, const double *seconds,
                          int best)
{
    js->has_allocation_choice = 1;
    js->q_allocated = evs[CANDIDATE_ALLOCATED].q;
    js->q_uniform = evs[CANDIDATE_UNIFORM].q;
    js->allocation_dense_made = made[CANDIDATE_DENSE];
    js->q_allocated_dense = made[CANDIDATE_DENSE] ? evs[CANDIDATE_DENSE].q : 0;
    js->metric_candidates_made = made[CANDIDATE_HESSIAN] && made[CANDIDATE_STRETCH];
    js->q_hessian = made[CANDIDATE_HESSIAN] ? evs[CANDIDATE_HESSIAN].q : 0;
    js->q_signal_stretch = made[CANDIDATE_STRETCH] ? evs[CANDIDATE_STRETCH].q : 0;
    js->allocation_chosen = candidate_name[best];
    js->seconds_choice_evaluate = evs[best].seconds;
    js->seconds_other_candidate = 0;
    for (int i = 0; i < CANDIDATES; i++)
        if (made[i] && i != best)
            js->seconds_other_candidate += seconds[i];
}

/* Refines candidate i (job_refine.h, starting from its targets' source). A metric
 * candidate gets twice the rounds: it starts nearer an optimum of its own, where the first
 * rounds' steps overshoot and only the halved ones gain (CesiumMan at c_r 0.1: the fifth
 * round, BENCHMARKS.md@9f788a8 "The signal metrics' layouts as candidates"). */
static texopt_status refine_candidate(texopt_job *job, const texopt_params *p, candidate_set *s, int i, double from,
                                      double to, refinement_record *rec, char *err, size_t err_len)
{
    texopt_params rounds = *p;
    if (candidate_source[i] != SOURCE_STAGE1 && p->refinements > 0)
        rounds.refinements = p->refinements * 2 > 20 ? 20 : p->refinements * 2;
    layout_run made_by = candidate_run(&rounds, i);
    return job_refine_kept(job, &made_by, &s->cand[i], from, to, rec, err, err_len);
}

/* Refines stage 1's best candidate (best[0]) and, when a metric candidate (best[1]) had a
 * lower q, that one too, and returns the index of the one whose refined q (on the
 * refinement's cameras, the same for both) is lower, its refinement's statistics in
 * job->stats (seconds: both). The refinement gains most on stage 1's layouts (CesiumMan at
 * c_r 0.3: 0.0084 -> 0.0059, below tewari's 0.0079, on which no round is kept), so the choice
 * before it would lose them (BENCHMARKS.md@9f788a8 "The signal metrics' layouts as candidates"). */
static texopt_status refine_best(texopt_job *job, const texopt_params *p, candidate_set *s, double from, double to,
                                 int *kept, char *err, size_t err_len)
{
    const int *best = s->best;
    int challenge = best[1] >= 0 && s->cand[best[1]].ev.q < s->cand[best[0]].ev.q;
    refinement_record rec[2] = {{0}, {0}};
    texopt_status st = TEXOPT_OK;
    if (texopt_params_refinement_rounds(p) <= 0)
        *kept = challenge ? best[1] : best[0];
    else {
        double split = challenge ? 0.5 * (from + to) : to;
        st = refine_candidate(job, p, s, best[0], from, split, &rec[0], err, err_len);
        if (st == TEXOPT_OK && challenge)
            st = refine_candidate(job, p, s, best[1], split, to, &rec[1], err, err_len);
        *kept = st == TEXOPT_OK && challenge && rec[1].q_after < rec[0].q_after ? best[1] : best[0];
    }
    job_record_refinement(&job->stats, &rec[*kept == best[1]], rec[0].seconds + rec[1].seconds);
    return st;
}

texopt_status job_measure_chosen_loss_share(texopt_job *job, const job_output *out, char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++)
        if (out->solved && out->solved[d])
            st = job_measure_loss_share(job, d, out->cut[d], out->solved[d], &job->stats.domains[d], err, err_len);
    return st;
}

/* For perceptual the candidates are held until the choice, so the winner is not rebuilt; its
 * images besides base colour are left to job_bake_remaining_images (not needed at all by the
 * target_loss search's steps), and the per-triangle loss share is measured on the winner
 * only. */
texopt_status job_run_best_budget(texopt_job *job, const texopt_params *p, int with_stats, job_output *out, double from,
                                  double to, char *err, size_t err_len)
{
    if (!job->method->chooses) {
        layout_run run = {.p = p, .with_stats = with_stats, .domains = job->stats.domains, .out = out};
        return job_run_budget(job, &run, from, to, err, err_len);
    }
    /* Progress: the candidates, their evaluation, then the refinement's rounds. */
    int refining = texopt_params_refinement_rounds(p) > 0;
    double made_by = from + (refining ? 0.6 : 0.8) * (to - from), chosen = refining ? from + 0.7 * (to - from) : to;
    candidate_set s;
    memset(&s, 0, sizeof s);
    int kept_index = -1;
    double seconds[CANDIDATES] = {0};  /* each candidate's stage 2, packing and bake */
    texopt_evaluation evs[CANDIDATES]; /* before the refinement */
    texopt_status st = run_candidates(job, p, &s, from, made_by, chosen, err, err_len);
    if (st == TEXOPT_OK) {
        for (int i = 0; i < CANDIDATES; i++) {
            evs[i] = s.cand[i].ev;
            seconds[i] = s.made[i] ? candidate_seconds(&s.cand[i], job->stats.domain_count) : 0;
            if (i != s.best[0] && i != s.best[1])
                job_candidate_free(job, &s.cand[i]);
        }
        st = refine_best(job, p, &s, chosen, to, &kept_index, err, err_len);
    }
    if (st == TEXOPT_OK) {
        texopt_job_stats *js = &job->stats;
        record_choice(js, evs, s.made, seconds, kept_index);
        candidate *kept = &s.cand[kept_index];
        job_stats_free_domains(js->domains, js->domain_count);
        js->domains = kept->domains;
        kept->domains = NULL;
        *out = kept->out;
        memset(&kept->out, 0, sizeof kept->out);
        st = job_keep_resize_if_better(job, p, out, to, err, err_len);
        if (st == TEXOPT_OK && with_stats)
            st = job_measure_chosen_loss_share(job, out, err, err_len);
    }
    for (int i = 0; i < CANDIDATES; i++)
        job_candidate_free(job, &s.cand[i]);
    return st;
}
