/* file_cost_checks.h - the invariant of issue 37 item 5: a job's statistics report the costs
 * and output distortion `texopt info` measures on the file it wrote (header only; test_file_costs.c and
 * test_file_costs_models_slow.c). */
#ifndef TEXOPT_TEST_FILE_COST_CHECKS_H
#define TEXOPT_TEST_FILE_COST_CHECKS_H

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "gltf_io.h"
#include "info.h"
#include "pipeline.h"
#include "pipeline_scratch.h"

/* The info document of the file at path (images not decoded), NULL on failure. */
static inline cJSON *info_of(const char *path)
{
    texopt_model *m = NULL;
    texopt_load_options o = {.skip_images = 1};
    cJSON *doc = NULL;
    if (texopt_model_load(&m, path, &o, NULL, 0) == TEXOPT_OK)
        texopt_info_json(m, &doc, NULL, 0);
    texopt_model_destroy(m);
    return doc;
}

static inline double number_at(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItem(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* 0 when the statistics' output distortion (domain a) is info's on the file (domain b) in
 * every metric's mean, else -1 with the first difference in why. */
static inline int distortion_matches(const cJSON *a, const cJSON *b, const char *method, int d, char *why,
                                     size_t why_len)
{
    const cJSON *sd = cJSON_GetObjectItem(cJSON_GetObjectItem(a, "distortion"), "output");
    const cJSON *fd = cJSON_GetObjectItem(b, "distortion");
    if (!sd)
        return 0; /* a domain laid out by no method has no output distortion */
    for (const cJSON *m = sd->child; m; m = m->next) {
        if (!cJSON_IsObject(m))
            continue;
        double x = number_at(m, "mean"), y = number_at(cJSON_GetObjectItem(fd, m->string), "mean");
        if (!(fabs(x - y) <= 1e-9 * fabs(y))) { /* summed in another order */
            snprintf(why, why_len, "%s domain %d: statistics' output %s %.17g, the file's %.17g", method, d, m->string,
                     x, y);
            return -1;
        }
    }
    return 0;
}

/* 0 when the statistics' atlas_quality (domain a) is info's on the file (domain b), else -1
 * with the difference in why. */
static inline int atlas_quality_matches(const cJSON *a, const cJSON *b, const char *method, int d, char *why,
                                        size_t why_len)
{
    const cJSON *sq = cJSON_GetObjectItem(a, "atlas_quality"), *fq = cJSON_GetObjectItem(b, "atlas_quality");
    static const char *const keys[] = {"packing_efficiency", "boundary_length", "charts"};
    for (int k = 0; k < 3; k++) {
        double x = number_at(sq, keys[k]), y = number_at(fq, keys[k]);
        if (!(fabs(x - y) <= 1e-12 * fabs(y))) { /* NaN when either is missing; JSON keeps 15 digits */
            snprintf(why, why_len, "%s domain %d: statistics' atlas_quality %s %.17g, the file's %.17g", method, d,
                     keys[k], x, y);
            return -1;
        }
    }
    return 0;
}

/* Optimises `in` with method at c_r and compares the statistics with info on the output and
 * the input. Returns 0 when they agree, else -1 with the first difference in why. */
static inline int stats_match_file(const char *in, const char *method, double relative_cost, char *why, size_t why_len)
{
    scratch s;
    if (scratch_init(&s, 0, 0, NULL) != 0) {
        snprintf(why, why_len, "no scratch directory");
        return -1;
    }
    texopt_params p = {0};
    p.method = texopt_method_from_name(method);
    p.relative_cost = relative_cost;
    p.threads = 2;
    p.refinements = -1;
    char err[512] = "";
    texopt_status st = texopt_optimize_file(in, s.out, s.stats, &p, NULL, err, sizeof err);
    cJSON *stats = st == TEXOPT_OK ? read_json(s.stats) : NULL, *out = info_of(s.out), *inp = info_of(in);
    int r = -1;
    snprintf(why, why_len, "%s: optimise or read failed: %s", method, err);
    if (stats && out && inp) {
        const cJSON *sf = cJSON_GetObjectItem(stats, "file_cost"), *of = cJSON_GetObjectItem(out, "file_cost");
        const cJSON *sd = cJSON_GetObjectItem(stats, "domains"), *od = cJSON_GetObjectItem(out, "domains"),
                    *id = cJSON_GetObjectItem(inp, "domains");
        r = 0;
        if (number_at(sf, "texture_pixels") != number_at(of, "texture_pixels") ||
            number_at(sf, "texture_bytes") != number_at(of, "texture_bytes") || !(number_at(sf, "bytes") > 0)) {
            snprintf(why, why_len, "%s: file cost %g px %g B in the statistics, %g px %g B in info", method,
                     number_at(sf, "texture_pixels"), number_at(sf, "texture_bytes"), number_at(of, "texture_pixels"),
                     number_at(of, "texture_bytes"));
            r = -1;
        }
        for (int d = 0; r == 0 && d < cJSON_GetArraySize(sd); d++) {
            const cJSON *a = cJSON_GetArrayItem(sd, d), *b = cJSON_GetArrayItem(od, d), *c = cJSON_GetArrayItem(id, d);
            double cost = number_at(a, "cost_output"), covered = number_at(b, "covered_texels");
            double rel = number_at(a, "relative_cost"), rel_file = covered / number_at(c, "covered_texels");
            double pack = number_at(a, "packing_efficiency"), pack_file = number_at(b, "packing_efficiency");
            if (cost != covered || !(fabs(rel - rel_file) <= 1e-12) || !(fabs(pack - pack_file) <= 1e-12)) {
                snprintf(why, why_len,
                         "%s domain %d: statistics cost %g c_r %.6f packing %.6f, the file %g c_r %.6f packing %.6f",
                         method, d, cost, rel, pack, covered, rel_file, pack_file);
                r = -1;
            }
            if (r == 0)
                r = distortion_matches(a, b, method, d, why, why_len);
            if (r == 0)
                r = atlas_quality_matches(a, b, method, d, why, why_len);
        }
    }
    cJSON_Delete(stats);
    cJSON_Delete(out);
    cJSON_Delete(inp);
    scratch_free(&s);
    return r;
}

static const char *const file_cost_methods[] = {"input", "perceptual", "ssp", "tewari", "arap"};

#endif
