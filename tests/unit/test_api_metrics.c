/* test_api_metrics.c - the Prometheus text: gauges, request counters by route and status,
 * upload bytes, and cumulative stage-duration histograms ending in +Inf. */
#include <stdlib.h>
#include <string.h>

#include "metrics.h"
#include "test.h"

TEST(metrics_render_counters_and_cumulative_histograms)
{
    service_metrics *m = metrics_create();
    CHECK(m != NULL);
    metrics_count_request(m, "/v1/jobs", 202);
    metrics_count_request(m, "/v1/jobs", 202);
    metrics_count_request(m, "/v1/jobs/{id}", 404);
    metrics_add_upload_bytes(m, 1000);
    metrics_add_upload_bytes(m, 24);
    metrics_observe_stage(m, "stage1", 0.3);  /* bucket le=0.5 */
    metrics_observe_stage(m, "stage1", 7.0);  /* bucket le=10 */
    metrics_observe_stage(m, "stage1", 5000); /* only +Inf */
    metrics_observe_stage(m, "mystery", 0.001);
    int counts[JOB_STATE_COUNT] = {2, 1, 5, 0, 3};
    char *text = metrics_render(m, counts, 2, 16, 1, 1);
    CHECK(text != NULL);
    const char *expected[] = {
        "# TYPE texopt_jobs gauge\n",
        "texopt_jobs{state=\"queued\"} 2\n",
        "texopt_jobs{state=\"succeeded\"} 5\n",
        "texopt_jobs{state=\"canceled\"} 3\n",
        "texopt_queue_depth 2\n",
        "texopt_queue_limit 16\n",
        "texopt_workers_busy 1\n",
        "# TYPE texopt_upload_bytes_total counter\ntexopt_upload_bytes_total 1024\n",
        "texopt_http_requests_total{route=\"/v1/jobs\",status=\"202\"} 2\n",
        "texopt_http_requests_total{route=\"/v1/jobs/{id}\",status=\"404\"} 1\n",
        "# TYPE texopt_stage_duration_seconds histogram\n",
        "texopt_stage_duration_seconds_bucket{stage=\"stage1\",le=\"0.1\"} 0\n",
        "texopt_stage_duration_seconds_bucket{stage=\"stage1\",le=\"0.5\"} 1\n",
        "texopt_stage_duration_seconds_bucket{stage=\"stage1\",le=\"5\"} 1\n",
        "texopt_stage_duration_seconds_bucket{stage=\"stage1\",le=\"10\"} 2\n",
        "texopt_stage_duration_seconds_bucket{stage=\"stage1\",le=\"1800\"} 2\n",
        "texopt_stage_duration_seconds_bucket{stage=\"stage1\",le=\"+Inf\"} 3\n",
        "texopt_stage_duration_seconds_sum{stage=\"stage1\"} 5007.300000\n",
        "texopt_stage_duration_seconds_count{stage=\"stage1\"} 3\n",
        "texopt_stage_duration_seconds_count{stage=\"other\"} 1\n",
    };
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++)
        CHECK_MSG(strstr(text, expected[i]) != NULL, "missing line: %s", expected[i]);
    free(text);
    metrics_destroy(m);
}
