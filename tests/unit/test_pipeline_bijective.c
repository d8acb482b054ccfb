/* test_pipeline_bijective.c - `bijective` through the whole job (pipeline.c, layout/scaffold.h):
 * the statistics report the scaffold, and a layout that needs no motion is not moved by it. */
#include <cjson/cJSON.h>
#include <string.h>

#include "pipeline.h"
#include "pipeline_scratch.h"
#include "test.h"

static cJSON *first_domain(cJSON *root)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(root, "domains"), 0);
}

/* arap on a flat grid: isometric targets, so the charts keep their shape (output symmetric
 * Dirichlet 4, as without scaffold) while every chart is solved inside its scaffold. */
static void run_arap(int bijective, cJSON **stats)
{
    scratch s;
    *stats = NULL;
    CHECK(scratch_init(&s, 3, 128, "flat") == 0);
    texopt_params p = {0};
    p.method = TEXOPT_METHOD_ARAP;
    p.relative_cost = 0.5;
    p.bijective = bijective;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    *stats = read_json(s.stats);
    scratch_free(&s);
}

TEST(the_statistics_report_the_scaffold_and_it_leaves_an_isometry_alone)
{
    cJSON *on, *off;
    run_arap(1, &on);
    CHECK(on != NULL);
    run_arap(0, &off);
    CHECK(off != NULL);
    cJSON *d_on = first_domain(on), *d_off = first_domain(off);
    cJSON *sc = cJSON_GetObjectItem(cJSON_GetObjectItem(d_on, "stage2"), "scaffold");
    CHECK(sc != NULL);
    CHECK_EQ_INT(cJSON_GetObjectItem(sc, "charts")->valuedouble, cJSON_GetObjectItem(d_on, "charts")->valuedouble);
    CHECK_EQ_INT(cJSON_GetObjectItem(sc, "skipped_charts")->valuedouble, 0);
    CHECK(cJSON_GetObjectItem(sc, "rounds")->valuedouble >= 1);
    CHECK(cJSON_GetObjectItem(sc, "triangles")->valuedouble > 0);
    CHECK(cJSON_GetObjectItem(cJSON_GetObjectItem(d_off, "stage2"), "scaffold") == NULL);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(on, "params"), "bijective")));
    double sd_on =
        cJSON_GetObjectItem(cJSON_GetObjectItem(d_on, "distortion"), "symmetric_dirichlet_output")->valuedouble;
    CHECK_NEAR(sd_on, 4.0, 1e-3);
    cJSON_Delete(on);
    cJSON_Delete(off);
}
