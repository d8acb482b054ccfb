/* test_gltf_io_models_slow.c - glTF load / save / reload on whole models, with timings (the
 * driver of scripts/bench.d/io).
 *
 * Models: TEXOPT_IO_MODELS (colon-separated paths) or, by default, tests/data's spot.glb and
 * Fox.glb. For each: full load, header-only load (skip_images), save with every UV moved,
 * reload (positions identical, UVs the new ones), and the Khronos validator on the saved file
 * against the input (no errors, no new warnings). Prints one "io ..." line per model. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "gltf_io.h"
#include "test.h"

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static long long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long long)sb.st_size : -1;
}

static const char *base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

static void check_model(const char *path, const char *out)
{
    char err[512] = "";
    texopt_model *m = NULL, *hdr = NULL, *back = NULL;
    double t0 = seconds_now();
    CHECK_OK(texopt_model_load(&m, path, NULL, err, sizeof err), err);
    double t1 = seconds_now();
    texopt_load_options header_only = {0, 0, 1};
    CHECK_OK(texopt_model_load(&hdr, path, &header_only, err, sizeof err), err);
    double t2 = seconds_now();
    float *uvs = malloc(sizeof(float) * 2 * m->vertex_count);
    for (size_t i = 0; i < 2 * m->vertex_count; i++)
        uvs[i] = 0.75f - 0.5f * m->uvs[i];
    texopt_model_edit edit = {uvs, NULL, 0};
    CHECK_OK(texopt_model_save_glb(m, &edit, out, err, sizeof err), err);
    double t3 = seconds_now();
    CHECK_OK(texopt_model_load(&back, out, &header_only, err, sizeof err), err);
    CHECK_EQ_INT(back->vertex_count, m->vertex_count);
    CHECK(memcmp(back->positions, m->positions, sizeof(float) * 3 * m->vertex_count) == 0);
    CHECK(memcmp(back->uvs, uvs, sizeof(float) * 2 * m->vertex_count) == 0);
    for (int i = 0; i < m->image_count; i++) {
        CHECK_EQ_INT(hdr->images[i].width, m->images[i].width);
        CHECK_EQ_INT(back->images[i].height, m->images[i].height);
    }
    long long pixels = 0;
    for (int i = 0; i < m->image_count; i++)
        pixels += (long long)m->images[i].width * m->images[i].height;

    char cmd[2048];
    snprintf(cmd, sizeof cmd, "node '%s/tools/validate-gltf.mjs' '%s' --baseline '%s' > '%s.json' 2>&1",
             TEXOPT_SOURCE_DIR, out, path, out);
    int rc = system(cmd);
    int validator = rc == -1 ? -1 : WEXITSTATUS(rc);
    printf("io %-22s vertices %6zu triangles %6zu images %d pixels %9lld load_s %.3f headers_s %.3f "
           "save_s %.3f bytes_in %lld bytes_out %lld validator %s\n",
           base_name(path), m->vertex_count, m->triangle_count, m->image_count, pixels, t1 - t0, t2 - t1, t3 - t2,
           file_size(path), file_size(out), validator == 0 ? "ok" : "FAILED");
    CHECK_MSG(validator == 0, "validator exit %d on %s (report in %s.json)", validator, out, out);
    free(uvs);
    texopt_model_destroy(m);
    texopt_model_destroy(hdr);
    texopt_model_destroy(back);
}

TEST(models_load_save_reload_and_validate)
{
    const char *env = getenv("TEXOPT_IO_MODELS");
    char list[8192];
    if (env && *env)
        snprintf(list, sizeof list, "%s", env);
    else
        snprintf(list, sizeof list, "%s/spot/spot.glb:%s/Fox/Fox.glb", TEXOPT_TEST_DATA_DIR, TEXOPT_TEST_DATA_DIR);
    char dir[] = "/tmp/texopt_io_models_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    int n = 0;
    for (char *save = NULL, *path = strtok_r(list, ":", &save); path; path = strtok_r(NULL, ":", &save)) {
        char out[256];
        snprintf(out, sizeof out, "%s/%d.glb", dir, n++);
        check_model(path, out);
        unlink(out);
        strncat(out, ".json", sizeof out - strlen(out) - 1);
        unlink(out);
        if (test_failed_now())
            break;
    }
    rmdir(dir);
    CHECK(n > 0);
}
