/* job_json.c - the public JSON form of a job (see job_json.h). */
#include "job_json.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "params_json.h"
#include "problem.h"

static void add_time(cJSON *o, const char *key, int64_t ms)
{
    if (ms <= 0) {
        cJSON_AddNullToObject(o, key);
        return;
    }
    time_t seconds = (time_t)(ms / 1000);
    struct tm tm;
    gmtime_r(&seconds, &tm);
    char text[40];
    size_t n = strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf(text + n, sizeof text - n, ".%03dZ", (int)(ms % 1000));
    cJSON_AddStringToObject(o, key, text);
}

/* report only once it exists (a job made with evaluate=true that succeeded). */
static void add_links(cJSON *o, const char *id, int has_report)
{
    cJSON *links = cJSON_AddObjectToObject(o, "links");
    static const char *const names[] = {"self", "events", "result", "stats", "report"};
    static const char *const suffixes[] = {"", "/events", "/result", "/stats", "/report"};
    size_t n = sizeof names / sizeof names[0] - (has_report ? 0 : 1);
    for (size_t i = 0; i < n; i++) {
        char href[96];
        snprintf(href, sizeof href, "/v1/jobs/%s%s", id, suffixes[i]);
        cJSON_AddStringToObject(links, names[i], href);
    }
}

cJSON *api_job_to_json(const job_record *job)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "id", job->id);
    cJSON_AddStringToObject(o, "state", job_state_name(job->state));
    if (job->stage[0])
        cJSON_AddStringToObject(o, "stage", job->stage);
    else
        cJSON_AddNullToObject(o, "stage");
    cJSON_AddNumberToObject(o, "progress", job->progress);
    if (job->eta_seconds >= 0 && !job_state_finished(job->state))
        cJSON_AddNumberToObject(o, "eta_seconds", job->eta_seconds);
    else
        cJSON_AddNullToObject(o, "eta_seconds");
    cJSON *stats = cJSON_AddObjectToObject(o, "running_stats");
    cJSON_AddNumberToObject(stats, "mean_loss", job->mean_loss);
    cJSON_AddNumberToObject(stats, "mean_area_scale", job->mean_area_scale);
    cJSON_AddBoolToObject(o, "cancel_requested", job->cancel_requested != 0);
    cJSON_AddNumberToObject(o, "attempts", job->attempts);
    add_time(o, "created_at", job->created_ms);
    add_time(o, "started_at", job->started_ms);
    add_time(o, "finished_at", job->finished_ms);
    cJSON *model = cJSON_AddObjectToObject(o, "model");
    cJSON_AddStringToObject(model, "name", job->model_name);
    cJSON_AddNumberToObject(model, "upload_bytes", (double)job->upload_bytes);
    cJSON_AddItemToObject(o, "params", api_params_to_json(&job->params));
    if (job->state == JOB_FAILED)
        job_problem_add_json(o, &job->problem);
    add_links(o, job->id, job->has_report);
    return o;
}

char *api_job_text(const job_record *job)
{
    cJSON *o = api_job_to_json(job);
    if (!o)
        return NULL;
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}
