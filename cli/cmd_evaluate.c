/* cmd_evaluate.c - `texopt evaluate IN OUT.glb [--resolution N] [--threads T] [--mipmap]
 * [--texture NAME|lit] [--maps] [--json]`.
 *
 * Compares any two models with the same triangles (an input and texopt's output, or the
 * output of another tool): the whole-mesh perceptual loss q of Sun et al. 2022, section 5.1
 * (engine/evaluate/evaluate.h), and what each layout costs: covered texels, texture pixels, packing
 * efficiency, symmetric Dirichlet distortion, and the relative cost c_r = covered texels of
 * OUT / of IN. With --maps, also q of every map IN's materials bind and the lit q
 * (engine/map_check.h). Text on stdout, or one JSON object with --json. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "numbers.h"
#include "texopt.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: texopt evaluate IN OUT.glb [--resolution N] [--threads T] [--mipmap]\n"
                 "                      [--texture NAME|lit] [--maps] [--json]\n"
                 "\n"
                 "Renders IN and OUT from 20 cameras around the model and prints their whole-mesh\n"
                 "perceptual loss q (GMSD, 0 = identical; Sun et al. 2022, section 5.1) and the cost\n"
                 "of both layouts. Both models must have the same triangles.\n"
                 "\n"
                 "options:\n"
                 "  --resolution N   render side in pixels (default: 1.25 sqrt(covered texels of IN),\n"
                 "                   the input texture at about one texel per pixel)\n"
                 "  --threads T      views rendered in parallel (default 2)\n"
                 "  --mipmap         prefiltered (mip-mapped, anisotropic) lookups instead of bilinear\n"
                 "  --texture NAME   the material texture both renders show: baseColor (default),\n"
                 "                   normal, metallicRoughness, occlusion or emissive (also base,\n"
                 "                   mr, ao), or a material extension's by its key, such as\n"
                 "                   clearcoatTexture or sheenColorTexture; a data texture's\n"
                 "                   encoding is compared as an image, in the channels it is read\n"
                 "                   in (occlusion R, metallicRoughness G and B, specularTexture A).\n"
                 "                   IN must have the texture (base colour excepted).\n"
                 "                   lit: the model lit by one light per view and a grey sky from\n"
                 "                   base colour, metallic-roughness (a specular highlight),\n"
                 "                   normal, occlusion and emissive maps (engine/evaluate/lit_shade.h)\n"
                 "  --maps           also q of every texture IN's materials bind, each as\n"
                 "                   --texture shows it, and lit (when IN has a map a light\n"
                 "                   reads besides base colour)\n"
                 "  --json           print one JSON object instead of text\n"
                 "  -h, --help       this text\n");
}

static cJSON *cost_json(const texopt_cost *c)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "covered_texels", (double)c->covered_texels);
    cJSON_AddNumberToObject(o, "frame_texels", (double)c->frame_texels);
    cJSON_AddNumberToObject(o, "texture_pixels", (double)c->texture_pixels);
    cJSON_AddNumberToObject(o, "packing_efficiency", c->packing_efficiency);
    if (c->symmetric_dirichlet < 1e300)
        cJSON_AddNumberToObject(o, "symmetric_dirichlet", c->symmetric_dirichlet);
    else
        cJSON_AddNullToObject(o, "symmetric_dirichlet");
    return o;
}

static void print_json(const texopt_evaluation *ev, const texopt_evaluate_options *opt, const texopt_cost *in,
                       const texopt_cost *out, const texopt_map_q *maps)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "q", ev->q);
    cJSON_AddNumberToObject(root, "resolution", ev->resolution);
    cJSON_AddStringToObject(root, "lookup", opt->mipmapped ? "mipmapped" : "bilinear");
    cJSON_AddStringToObject(root, "texture", texopt_evaluate_measure_name(opt));
    cJSON *views = cJSON_AddArrayToObject(root, "view_gmsd");
    for (int v = 0; v < TEXOPT_VIEW_COUNT; v++)
        cJSON_AddItemToArray(views, cJSON_CreateNumber(ev->view_gmsd[v]));
    cJSON_AddNumberToObject(root, "relative_cost",
                            in->covered_texels ? (double)out->covered_texels / (double)in->covered_texels : 0);
    cJSON_AddItemToObject(root, "input", cost_json(in));
    cJSON_AddItemToObject(root, "output", cost_json(out));
    cJSON_AddNumberToObject(root, "seconds", ev->seconds);
    cJSON *q_maps = maps ? cJSON_AddObjectToObject(root, "q_maps") : NULL;
    for (int m = 0; q_maps && m < TEXOPT_MAP_MEASURES; m++)
        if (maps->measured[m])
            cJSON_AddNumberToObject(q_maps, texopt_map_measure_name(m), maps->q[m]);
    char *text = cJSON_Print(root);
    if (text)
        printf("%s\n", text);
    free(text);
    cJSON_Delete(root);
}

static void print_text(const texopt_evaluation *ev, const texopt_evaluate_options *opt, const texopt_cost *in,
                       const texopt_cost *out, const texopt_map_q *maps)
{
    printf("q (whole-mesh GMSD of %s, 20 views at %d px, %s lookups): %.6f\n", texopt_evaluate_measure_name(opt),
           ev->resolution, opt->mipmapped ? "mip-mapped" : "bilinear", ev->q);
    for (int m = 0; maps && m < TEXOPT_MAP_MEASURES; m++)
        if (maps->measured[m])
            printf("  q of %-20s %.6f\n", texopt_map_measure_name(m), maps->q[m]);
    printf("relative cost c_r: %.4f\n",
           in->covered_texels ? (double)out->covered_texels / (double)in->covered_texels : 0);
    printf("%-22s %14s %14s\n", "", "input", "output");
    printf("%-22s %14llu %14llu\n", "covered texels", (unsigned long long)in->covered_texels,
           (unsigned long long)out->covered_texels);
    printf("%-22s %14llu %14llu\n", "texture pixels", (unsigned long long)in->texture_pixels,
           (unsigned long long)out->texture_pixels);
    printf("%-22s %14.4f %14.4f\n", "packing efficiency", in->packing_efficiency, out->packing_efficiency);
    printf("%-22s %14.4f %14.4f\n", "symmetric Dirichlet", in->symmetric_dirichlet, out->symmetric_dirichlet);
    printf("evaluated in %.2f s\n", ev->seconds);
}

int cmd_evaluate(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL};
    int npaths = 0, json = 0, every_map = 0;
    texopt_evaluate_options opt = {.threads = 2};
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "--json")) {
            json = 1;
        } else if (!strcmp(a, "--maps")) {
            every_map = 1;
        } else if (!strcmp(a, "--mipmap")) {
            opt.mipmapped = 1;
        } else if (!strcmp(a, "--texture")) {
            const char *name = i + 1 < argc ? argv[i + 1] : NULL;
            if (texopt_evaluate_select_measure(&opt, name) != 0) {
                fprintf(stderr, "texopt evaluate: --texture needs baseColor, normal, metallicRoughness, "
                                "occlusion, emissive, an extension texture's key (clearcoatTexture...) or "
                                "lit\n");
                return EXIT_USAGE;
            }
            i++;
        } else if (!strcmp(a, "--resolution") || !strcmp(a, "--threads")) {
            int *dst = a[2] == 'r' ? &opt.resolution : &opt.threads;
            int hi = a[2] == 'r' ? 16384 : 64, lo = a[2] == 'r' ? 8 : 1;
            if (i + 1 >= argc || cli_parse_int(argv[i + 1], lo, hi, dst) != 0) {
                fprintf(stderr, "texopt evaluate: %s needs an integer in [%d, %d]\n", a, lo, hi);
                return EXIT_USAGE;
            }
            i++;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "texopt evaluate: unknown option '%s'\n", a);
            usage(stderr);
            return EXIT_USAGE;
        } else if (npaths < 2) {
            paths[npaths++] = a;
        } else {
            fprintf(stderr, "texopt evaluate: too many arguments\n");
            return EXIT_USAGE;
        }
    }
    if (npaths != 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    char err[512] = "";
    texopt_model *in = NULL, *out = NULL;
    texopt_status st = texopt_model_load(&in, paths[0], NULL, err, sizeof err);
    if (st == TEXOPT_OK)
        st = texopt_model_load(&out, paths[1], NULL, err, sizeof err);
    texopt_evaluation ev;
    texopt_cost cin, cout;
    if (st == TEXOPT_OK)
        st = texopt_evaluate(in, out, &opt, &ev, err, sizeof err);
    texopt_map_q maps;
    int measured[TEXOPT_MAP_MEASURES];
    if (st == TEXOPT_OK && every_map) {
        const texopt_model *shown = out;
        texopt_map_measures(in, -1, measured);
        st = texopt_map_evaluate(in, &shown, 1, &opt, measured, &maps, err, sizeof err);
    }
    if (st == TEXOPT_OK)
        st = texopt_evaluate_cost(in, &cin, err, sizeof err);
    if (st == TEXOPT_OK)
        st = texopt_evaluate_cost(out, &cout, err, sizeof err);
    if (st == TEXOPT_OK) {
        if (json)
            print_json(&ev, &opt, &cin, &cout, every_map ? &maps : NULL);
        else
            print_text(&ev, &opt, &cin, &cout, every_map ? &maps : NULL);
    } else {
        fprintf(stderr, "texopt evaluate: %s: %s\n", texopt_strerror(st), err);
    }
    texopt_model_destroy(in);
    texopt_model_destroy(out);
    return st == TEXOPT_OK ? EXIT_OK : EXIT_ENGINE;
}
