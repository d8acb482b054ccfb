/* job_refine.c - closed-loop refinement of a kept candidate layout (job_refine.h). */
#include "job_refine.h"

#include <stdlib.h>
#include <string.h>

#include "budget_layout.h"
#include "domain_rechart.h"
#include "job_evaluate.h"
#include "job_stats.h"
#include "lit_shade.h"
#include "target_allocation.h"

/* The closed-loop refinement's step (target_allocation.h texopt_reallocate_by_error), the best of
 * those measured on Fox, spot and Duck (BENCHMARKS.md@9f788a8 "Quality"): area steps of (e_t /
 * e_mean)^0.5 within [0.5, 2] per round, singular values up to twice input density. */
static const texopt_reallocate_options refinement_step = {0.5, 0.5, 2.0, 2.0, NULL};

/* Per domain, room for one target per triangle in out[d] (zeros: a kept domain has none). */
static texopt_status alloc_domain_targets(const texopt_job *job, texopt_triangle_target **out, char *err,
                                          size_t err_len)
{
    for (int d = 0; d < job->model->domain_count; d++) {
        size_t n = job->domains[d].mesh->triangle_count;
        if (!(out[d] = calloc(n ? n : 1, sizeof *out[d])))
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the refined targets");
    }
    return TEXOPT_OK;
}

/* Per domain, the targets the kept candidate was solved from: stage 1's or a signal
 * metric's as they are (uniform, cap 0), or stage 1's allocated (target_allocation.h) with the
 * candidate's cap at the cost it reached. */
static texopt_status kept_targets(const texopt_job *job, const layout_run *made_by, const texopt_domain_stats *ds,
                                  texopt_triangle_target **out, char *err, size_t err_len)
{
    double cap = made_by->allocating;
    texopt_status st = alloc_domain_targets(job, out, err, err_len);
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++) {
        const job_domain *jd = &job->domains[d];
        if (jd->kept)
            continue;
        double area = ds[d].relative_cost * (double)jd->input_coverage.covered_texels;
        texopt_allocate_options o = job_domain_allocation(jd, cap);
        if (cap > 0 && area > 0)
            st = texopt_allocate_targets(job_layout_mesh(jd), jd->targets, area, &o, out[d], NULL, err, err_len);
        else
            memcpy(out[d], job_source_targets(jd, made_by->source), jd->mesh->triangle_count * sizeof *out[d]);
    }
    return st;
}

/* A refinement in progress: the best targets and their errors, the next round's, the step. */
typedef struct refinement {
    texopt_triangle_target **best, **next; /* per domain */
    double *error, *next_error;            /* per model triangle: best's, next's */
    double *scratch;                       /* room for as many */
    texopt_reallocate_options step;
} refinement;

/* Moves each domain's targets (r->best into r->next) towards the triangles the screen shows
 * wrong (r->error), rescaled to the texel area the kept layout reached (also for the uniform
 * candidate, whose targets stage 2 then solves at their final size: rescaling them to their
 * own total area instead measured worse on Fox at c_r 0.7 and 1 and no better on spot). */
static texopt_status reallocate_domains(const texopt_job *job, target_source source, const texopt_domain_stats *ds,
                                        refinement *r, char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++) {
        const job_domain *jd = &job->domains[d];
        const texopt_mesh *mesh = job_layout_mesh(jd);
        if (jd->kept || mesh->triangle_count == 0)
            continue;
        /* A metric candidate's targets keep their own total area: its layout was solved at
         * that size and scaled by the budget, as its method does, and solving them at the
         * budget's size instead gives another layout (CesiumMan at c_r 0.3: no round kept). */
        double area = source == SOURCE_STAGE1 ? ds[d].relative_cost * (double)jd->input_coverage.covered_texels
                                              : texopt_targets_area(mesh, r->best[d], jd->paid);
        if (!(area > 0))
            continue;
        for (size_t t = 0; t < mesh->triangle_count; t++)
            r->scratch[t] = r->error[mesh->model_triangle[t]];
        texopt_reallocate_options o = r->step;
        o.paid = jd->paid;
        st = texopt_reallocate_by_error(mesh, r->best[d], r->scratch, area, &o, r->next[d], NULL, err, err_len);
    }
    return st;
}

/* Per domain, a copy of `from` (the next round's targets start as the kept ones: a domain
 * the reallocation skips keeps them). */
static texopt_status copy_targets(const texopt_job *job, texopt_triangle_target *const *from,
                                  texopt_triangle_target **out, char *err, size_t err_len)
{
    texopt_status st = alloc_domain_targets(job, out, err, err_len);
    for (int d = 0; d < job->model->domain_count && st == TEXOPT_OK; d++)
        memcpy(out[d], from[d], job->domains[d].mesh->triangle_count * sizeof *out[d]);
    return st;
}

static void free_targets(texopt_triangle_target **targets, int n)
{
    for (int d = 0; targets && d < n; d++)
        free(targets[d]);
    free(targets);
}

/* One round of the refinement: the layout of r->next as a candidate, with its loss and
 * per-triangle errors (into r->next_error) on screen (the refinement's cameras against the
 * input's kept views, lit or of base colour). */
static texopt_status refinement_trial(texopt_job *job, const layout_run *made_by, const refinement *r,
                                      const job_screen *screen, candidate *trial, double from, double to, char *err,
                                      size_t err_len)
{
    layout_run round = {.p = made_by->p,
                        .source = made_by->source,
                        .refined = r->next,
                        .plan = screen->lit ? BAKE_ALL : BAKE_EVALUATED};
    texopt_status st = job_run_candidate(job, &round, trial, from, from + 0.8 * (to - from), err, err_len);
    const job_output *shown = &trial->out;
    if (st == TEXOPT_OK) {
        job_stage(&job->jm, "evaluate", from + 0.8 * (to - from), to);
        job_screen errors = *screen;
        errors.triangle_error = r->next_error;
        st = job_evaluate_outputs(job, &shown, 1, made_by->p, &errors, &trial->ev, err, err_len);
    }
    return st;
}

/* The refinement takes each triangle's on-screen error as evaluate.h triangle_error_edges
 * sees it (value and gradient both wrong, as GMSD sees an edge; base-colour q 0.85-0.96x that
 * of the plain luma difference on seven sample models and level on Duck,
 * BENCHMARKS.md@9f788a8 "The refinement steered by edges"). Errors and q are measured on the
 * choice's views (CHOICE_CAMERAS), not on those that define the reported q: the layout is not
 * tuned on the views it is graded on. Unless p->refine_lit asks for base colour, and when the
 * material has maps a light reads besides base colour, the screen is lit (with the luma
 * difference per triangle, the measure it was tuned with; evaluate.h `lit`: every map under
 * one light), else base colour's: what the light shows of the normal and roughness maps is
 * what a viewer sees, and base colour's error alone moves texels away from it, at the cost of
 * base colour's q and about twice the rounds' time (docs/benchmarks.md "The refinement judged
 * lit by default"). Lit rounds read the input's views
 * shaded once (texopt_evaluate_reference_create) and bake every map (BAKE_ALL), the kept
 * layout's too, so that every layout is judged with the same bake. The rounds tried and kept, the measure, the 12-view q before
 * and after and their time go to *rec (for the statistics' allocation_choice.refinement);
 * kept->ev stays the choice's. */
texopt_status job_refine_kept(texopt_job *job, const layout_run *made_by, candidate *kept, double from, double to,
                              refinement_record *rec, char *err, size_t err_len)
{
    const texopt_params *p = made_by->p;
    int rounds = texopt_params_refinement_rounds(p), nd = job->model->domain_count;
    memset(rec, 0, sizeof *rec);
    if (rounds <= 0)
        return TEXOPT_OK;
    double t0 = job_now_seconds();
    size_t tc = job->model->triangle_count ? job->model->triangle_count : 1, nda = (size_t)(nd > 0 ? nd : 1);
    refinement r = {calloc(nda, sizeof *r.best),       calloc(nda, sizeof *r.next),    malloc(tc * sizeof *r.error),
                    malloc(tc * sizeof *r.next_error), malloc(tc * sizeof *r.scratch), refinement_step};
    texopt_status st = r.best && r.next && r.error && r.next_error && r.scratch
                           ? kept_targets(job, made_by, kept->domains, r.best, err, err_len)
                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the refinement");
    if (st == TEXOPT_OK)
        st = copy_targets(job, r.best, r.next, err, err_len);
    int lit = rec->lit = p->refine_lit >= 0 && texopt_lit_has_maps(job->model);
    const job_output *shown = &kept->out;
    texopt_evaluation best_ev;
    double span = (to - from) / (rounds + 1);
    texopt_evaluate_reference *views = NULL;
    if (st == TEXOPT_OK && lit)
        st = job_bake_candidate_images(job, p, kept, from, from + 0.5 * span, err, err_len);
    if (st == TEXOPT_OK)
        job_stage(&job->jm, "evaluate", from + (lit ? 0.5 * span : 0), from + span);
    if (st == TEXOPT_OK && lit) {
        texopt_evaluate_options opt = job_evaluation_options(p, CHOICE_CAMERAS, lit, &job->jm);
        st = texopt_evaluate_reference_create(job->model, &opt, &views, err, err_len);
    }
    job_screen screen = {CHOICE_CAMERAS, lit, views, r.error}; /* a round's errors: r.next_error */
    if (st == TEXOPT_OK) {
        st = job_evaluate_outputs(job, &shown, 1, p, &screen, &best_ev, err, err_len);
        rec->q_before = best_ev.q;
    }
    for (int k = 0; k < rounds && st == TEXOPT_OK; k++) {
        candidate trial = {0};
        st = reallocate_domains(job, made_by->source, kept->domains, &r, err, err_len);
        if (st == TEXOPT_OK)
            st = refinement_trial(job, made_by, &r, &screen, &trial, from + span * (k + 1), from + span * (k + 2), err,
                                  err_len);
        if (st == TEXOPT_OK && trial.ev.q < best_ev.q) {
            job_stats_free_domains(kept->domains, nd);
            job_output_destroy(&kept->out, job->model->image_count);
            *kept = trial;
            memset(&trial, 0, sizeof trial);
            best_ev = kept->ev;
            texopt_triangle_target **t = r.best;
            r.best = r.next;
            r.next = t;
            double *e = r.error;
            r.error = r.next_error;
            r.next_error = e;
            rec->kept++;
        } else
            r.step.gamma *= 0.5;
        job_stats_free_domains(trial.domains, nd);
        job_output_destroy(&trial.out, job->model->image_count);
        rec->rounds = k + 1;
    }
    if (st == TEXOPT_OK)
        rec->q_after = best_ev.q; /* the kept layout's; unchanged when no round was kept */
    rec->seconds = job_now_seconds() - t0;
    texopt_evaluate_reference_destroy(views);
    free_targets(r.best, nd);
    free_targets(r.next, nd);
    free(r.error);
    free(r.next_error);
    free(r.scratch);
    return st;
}

void job_record_refinement(texopt_job_stats *js, const refinement_record *r, double seconds)
{
    js->refinement_rounds = r->rounds;
    js->refinement_kept = r->kept;
    js->refinement_lit = r->lit;
    js->q_refinement_before = r->q_before;
    js->q_refinement_after = r->q_after;
    js->seconds_refinement = seconds;
}
