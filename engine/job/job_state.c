/* job_state.c - what a job holds, and one run of its budget's layout (job_state.h). */
#include "job_state.h"

#include <unistd.h>

const texopt_texel_share *job_sharing(const job_domain *jd)
{
    return jd->share && jd->share->secondary_count > 0 ? jd->share : NULL;
}

const texopt_triangle_target *job_source_targets(const job_domain *jd, target_source source)
{
    if (source == SOURCE_HESSIAN && jd->hessian)
        return jd->hessian;
    if (source == SOURCE_STRETCH && jd->stretch)
        return jd->stretch;
    return jd->targets;
}

const texopt_triangle_target *job_run_targets(const layout_run *run, const job_domain *jd, int d)
{
    return run->refined && run->refined[d] ? run->refined[d] : job_source_targets(jd, run->source);
}

int job_worker_threads(const texopt_params *params)
{
    if (params->threads > 0)
        return params->threads;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}
