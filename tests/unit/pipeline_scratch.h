/* pipeline_scratch.h - a scratch directory with the file names the pipeline tests use
 * (input, output, a second output, statistics), reading the statistics JSON and loading a
 * model (header only; test_pipeline.c, test_pipeline_models_slow.c and
 * pipeline_budget_checks.h). */
#ifndef TEXOPT_TEST_PIPELINE_SCRATCH_H
#define TEXOPT_TEST_PIPELINE_SCRATCH_H

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "gltf_io.h"
#include "grid_glb.h"

typedef struct scratch {
    char dir[64], in[128], out[128], again[128], stats[128];
} scratch;

/* Makes the directory and, unless pattern is NULL, writes an n x n grid with a tex x tex
 * texture of `pattern` as the input (grid_glb.h). Returns 0 on success. */
static inline int scratch_init(scratch *s, int n, int tex, const char *pattern)
{
    snprintf(s->dir, sizeof s->dir, "/tmp/texopt_pipeline_XXXXXX");
    if (!mkdtemp(s->dir))
        return -1;
    snprintf(s->in, sizeof s->in, "%s/in.glb", s->dir);
    snprintf(s->out, sizeof s->out, "%s/out.glb", s->dir);
    snprintf(s->again, sizeof s->again, "%s/again.glb", s->dir);
    snprintf(s->stats, sizeof s->stats, "%s/stats.json", s->dir);
    return pattern ? write_grid_glb(s->in, n, tex, pattern) : 0;
}

static inline void scratch_free(scratch *s)
{
    unlink(s->in);
    unlink(s->out);
    unlink(s->again);
    unlink(s->stats);
    rmdir(s->dir);
}

/* The JSON file at path, parsed (NULL when missing, larger than 1 MB or not JSON). */
static inline cJSON *read_json(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1u << 20;
    char *buf = malloc(cap);
    size_t n = buf ? fread(buf, 1, cap - 1, f) : 0;
    fclose(f);
    cJSON *root = NULL;
    if (buf && n < cap - 1) {
        buf[n] = '\0';
        root = cJSON_Parse(buf);
    }
    free(buf);
    return root;
}

static inline texopt_model *load(const char *path)
{
    texopt_model *m = NULL;
    char err[256];
    if (texopt_model_load(&m, path, NULL, err, sizeof err) != TEXOPT_OK)
        return NULL;
    return m;
}

#endif
