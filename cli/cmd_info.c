/* cmd_info.c - `texopt info MODEL [--pretty]`: prints the engine's info document (info.h).
 *
 * Loads the model without decoding pixels (image headers give sizes and channels), then
 * prints one JSON object on stdout: per texture domain the counts, textures, covered texels
 * (Sun et al. 2022, eq. 20, each texel once), packing efficiency, and the flipped,
 * overlapping, degenerate and wrapped triangles. The object gains a "file" field with the
 * path given. Errors go to stderr with exit code 1; usage errors exit with 2. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "texopt.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: texopt info MODEL [--pretty]\n"
                 "\n"
                 "Prints a JSON description of MODEL (.glb or .gltf): per texture domain the\n"
                 "triangle, chart and vertex counts, the textures and their wrap modes, the texels\n"
                 "the UV layout covers (each once), packing efficiency, and how many triangles are\n"
                 "flipped, overlapping, degenerate or wrapped.\n"
                 "\n"
                 "options:\n"
                 "  --pretty     indent the JSON\n"
                 "  -h, --help   this text\n");
}

int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    int pretty = 0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "--pretty")) {
            pretty = 1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "texopt info: unknown option '%s'\n", a);
            usage(stderr);
            return EXIT_USAGE;
        } else if (!path) {
            path = a;
        } else {
            fprintf(stderr, "texopt info: one MODEL only ('%s' is extra)\n", a);
            return EXIT_USAGE;
        }
    }
    if (!path) {
        usage(stderr);
        return EXIT_USAGE;
    }
    char err[512] = "";
    texopt_model *model = NULL;
    texopt_load_options opt = {.skip_images = 1};
    texopt_status st = texopt_model_load(&model, path, &opt, err, sizeof err);
    cJSON *doc = NULL;
    if (st == TEXOPT_OK)
        st = texopt_info_json(model, &doc, err, sizeof err);
    texopt_model_destroy(model);
    if (st != TEXOPT_OK) {
        fprintf(stderr, "texopt info: %s: %s: %s\n", path, texopt_strerror(st), err);
        return EXIT_ENGINE;
    }
    /* "file" first, so a reader sees which model the numbers describe */
    cJSON_AddItemToObject(doc, "file", cJSON_CreateString(path));
    cJSON *file = cJSON_DetachItemFromObjectCaseSensitive(doc, "file");
    if (file)
        cJSON_InsertItemInArray(doc, 0, file); /* keeps the key: works on objects too */
    char *text = pretty ? cJSON_Print(doc) : cJSON_PrintUnformatted(doc);
    cJSON_Delete(doc);
    if (!text) {
        fprintf(stderr, "texopt info: %s: out of memory printing the document\n", path);
        return EXIT_ENGINE;
    }
    int ok = printf("%s\n", text) >= 0 && fflush(stdout) == 0;
    free(text);
    if (!ok) {
        fprintf(stderr, "texopt info: cannot write to standard output\n");
        return EXIT_ENGINE;
    }
    return EXIT_OK;
}
