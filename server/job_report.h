/* job_report.h - the HTML evaluation report of a job that asked for one (evaluate=true).
 *
 * Does: compare the job's method with the input layout at the job's relative cost
 * (engine/compare/compare.h: both through the pipeline, both evaluated with the whole-mesh loss of
 * Sun et al. 2022, section 5.1) and write the self-contained report (engine/compare/report.h) as
 * report.html in the job directory. The job's method is measured on the job's own
 * result.glb, so only the input layout is run again (a resize and a bake).
 * Does not: change the job's result.glb or stats.json. */
#ifndef TEXOPT_SERVER_JOB_REPORT_H
#define TEXOPT_SERVER_JOB_REPORT_H

#include <stddef.h>

#include "texopt.h"

/* input: the job's model; dir: the job directory (holding result.glb and stats.json of the
 * finished run). */
texopt_status job_write_report(const char *input, const char *dir, const char *title, const texopt_params *params,
                               const texopt_monitor *monitor, char *err, size_t err_len);

#endif
