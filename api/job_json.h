/* job_json.h - the job resource as clients see it (GET /v1/jobs/{id}, list items, events).
 *
 * Does: render a job_record as JSON: id, state, stage, progress, eta_seconds, running
 * statistics, times (RFC 3339), attempts, params, the problem when failed, and links.
 * Does not: expose server paths or the idempotency key. */
#ifndef TEXOPT_API_JOB_JSON_H
#define TEXOPT_API_JOB_JSON_H

#include <cjson/cJSON.h>

#include "store.h"

/* A new JSON object for the job (caller frees with cJSON_Delete); NULL on allocation failure. */
cJSON *api_job_to_json(const job_record *job);

/* The same, printed unformatted (caller frees). */
char *api_job_text(const job_record *job);

#endif
