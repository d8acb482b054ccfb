/* candidate.c - one candidate layout of a budget (candidate.h). */
#include "candidate.h"

#include "bake_pool.h"
#include "budget_layout.h"
#include "job_stats.h"

texopt_status job_run_candidate(texopt_job *job, const layout_run *how, candidate *c, double from, double to, char *err,
                                size_t err_len)
{
    c->domains = job_stats_copy_domains(&job->stats);
    if (!c->domains)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for candidate statistics");
    layout_run run = *how;
    run.with_stats = 0;
    run.domains = c->domains;
    run.out = &c->out;
    return job_run_budget(job, &run, from, to, err, err_len);
}

texopt_status job_bake_candidate_images(texopt_job *job, const texopt_params *p, candidate *c, double from, double to,
                                        char *err, size_t err_len)
{
    layout_run run = {.p = p, .plan = BAKE_ALL, .domains = c->domains, .out = &c->out};
    return job_bake_remaining_images(job, &run, from, to, err, err_len);
}

void job_candidate_free(texopt_job *job, candidate *c)
{
    job_stats_free_domains(c->domains, job->stats.domain_count);
    c->domains = NULL;
    job_output_destroy(&c->out, job->model->image_count);
}
