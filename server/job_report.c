/* job_report.c - report.html for a job with evaluate=true (see job_report.h). */
#include "job_report.h"

#include <cjson/cJSON.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

#include "fsutil.h"
#include "texopt.h"

/* The relative cost to compare at: the requested one, or for a texture-size budget the one
 * the run achieved (first texture domain, from stats.json). */
static texopt_status cost_of_run(const char *dir, const texopt_params *params, double *cost, char *err, size_t err_len)
{
    if (params->budget == TEXOPT_BUDGET_RELATIVE_COST) {
        *cost = params->relative_cost;
        return TEXOPT_OK;
    }
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/stats.json", dir);
    char *text = fs_read_small(path, 16u << 20, NULL);
    cJSON *stats = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *domains = cJSON_GetObjectItemCaseSensitive(stats, "domains");
    const cJSON *achieved = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(domains, 0), "relative_cost");
    *cost = cJSON_IsNumber(achieved) ? achieved->valuedouble : 0;
    cJSON_Delete(stats);
    if (!(*cost > 0 && *cost <= 4))
        return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "report: no achieved relative cost in %s", path);
    return TEXOPT_OK;
}

texopt_status job_write_report(const char *input, const char *dir, const char *title, const texopt_params *params,
                               const texopt_monitor *monitor, char *err, size_t err_len)
{
    double cost;
    texopt_status s = cost_of_run(dir, params, &cost, err, err_len);
    if (s != TEXOPT_OK)
        return s;
    texopt_method methods[2] = {TEXOPT_METHOD_INPUT, params->method};
    char work[PATH_MAX], report[PATH_MAX], result_glb[PATH_MAX];
    snprintf(work, sizeof work, "%s/report-work", dir);
    snprintf(result_glb, sizeof result_glb, "%s/result.glb", dir);
    /* The job's own result stands for its method: only the input layout is run here. */
    const char *given[2] = {NULL, result_glb};
    if (params->method == TEXOPT_METHOD_INPUT)
        given[0] = result_glb;
    snprintf(report, sizeof report, "%s/report.html", dir);
    if (fs_mkdir_p(work) != 0)
        return texopt_fail(err, err_len, TEXOPT_E_IO, "report: cannot create %s", work);

    texopt_compare_options opt = {0};
    opt.params = *params;
    opt.methods = methods;
    opt.method_count = params->method == TEXOPT_METHOD_INPUT ? 1 : 2;
    opt.costs = &cost;
    opt.cost_count = 1;
    opt.showcase_cost = cost;
    opt.evaluate.resolution = params->eval_resolution;
    opt.evaluate.mipmapped = params->mipmapped;
    opt.work_dir = work;
    opt.monitor = monitor;
    opt.given_outputs = given;
    texopt_compare_result result;
    s = texopt_compare(input, &opt, &result, err, err_len);
    if (s == TEXOPT_OK) {
        texopt_report_options ro = {0};
        ro.title = title;
        s = texopt_report_write_html(&result, &ro, report, err, err_len);
        texopt_compare_result_destroy(&result);
    }
    fs_remove_tree(work);
    return s;
}
