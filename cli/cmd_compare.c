/* cmd_compare.c - `texopt compare IN [--methods a,b] [--costs x,y] [-o report.html]
 * [--json curves.json]`: the q_r-c_r curves of several layout methods on one model.
 *
 * Runs every method through the pipeline at every relative cost, evaluates each output
 * against IN (engine/compare/compare.h, Sun et al. 2022 section 5.1), prints a table of q, and
 * writes the curves as JSON and the self-contained HTML report (engine/compare/report.h). Ctrl-C
 * stops at the next checkpoint (exit 3). */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cancel.h"
#include "commands.h"
#include "numbers.h"
#include "texopt.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: texopt compare IN [options]\n"
                 "\n"
                 "Runs several layout methods on IN at several relative costs, measures each output's\n"
                 "whole-mesh loss q against IN, and prints the q_r-c_r table.\n"
                 "\n"
                 "options:\n"
                 "  --methods LIST      comma-separated: input,ssp,tewari,arap,perceptual\n"
                 "                      (default: all five)\n"
                 "  --costs LIST        comma-separated relative costs in (0, 4]\n"
                 "                      (default 0.1,0.2,0.3,0.5,0.7,1.0)\n"
                 "  --showcase C        the cost whose outputs the report shows (default: closest to 0.3)\n"
                 "  -o, --report PATH   write the self-contained HTML report\n"
                 "  --json PATH         write the curves as JSON\n"
                 "  --resolution N      evaluation render side (default: 1.25 sqrt(covered texels))\n"
                 "  --mipmap            prefiltered (mip-mapped) lookups, not bilinear: q measures\n"
                 "                      with them and perceptual tunes its layout for them\n"
                 "  --texture NAME      what q measures, as texopt evaluate --texture: a texture\n"
                 "                      (default baseColor; an extension's by its key) or lit (every\n"
                 "                      core map under one light); the methods still lay out by\n"
                 "                      their own rules\n"
                 "  --every-texture     also measure q on every other texture IN has (normal,\n"
                 "                      metallicRoughness, ..., clearcoatTexture, ...) and, when IN\n"
                 "                      has a map besides base colour, lit (texopt evaluate\n"
                 "                      --texture lit): printed as one table each and in the JSON\n"
                 "                      as q_by_texture\n"
                 "  --iterations N      most stage-1 polish iterations per triangle (default 100)\n"
                 "  --epsilon E         perceptual loss threshold of stage 1 (default 0.03)\n"
                 "  --lambda-min L      smallest per-axis scale stage 1 may choose, in (0, 1)\n"
                 "                      (default 0.1)\n"
                 "  --seed S            random seed, 0 to 2^53 (default 0)\n"
                 "  --refinements N     perceptual: most closed-loop refinement rounds, 0-20\n"
                 "                      (default 4; 0 = none), as in texopt optimize\n"
                 "  --refine-by M       perceptual: lit (default) or baseColor, as in texopt optimize\n"
                 "  --threads T         worker threads (default: every core)\n"
                 "  --reuse-layout      each layout method once, at the largest cost; smaller costs by\n"
                 "                      resampling its re-baked textures (much faster, but measurably\n"
                 "                      pessimistic for the layout methods; default: one pipeline run\n"
                 "                      per method and cost)\n"
                 "  --quiet             no progress on stderr\n"
                 "  -h, --help          this text\n");
}

static int parse_methods(const char *list, texopt_method *out, int *n)
{
    char buf[256];
    if (strlen(list) >= sizeof buf)
        return -1;
    strcpy(buf, list);
    *n = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        texopt_method m = texopt_method_from_name(tok);
        if (m == TEXOPT_METHOD_COUNT || *n >= TEXOPT_METHOD_COUNT)
            return -1;
        for (int i = 0; i < *n; i++)
            if (out[i] == m)
                return -1;
        out[(*n)++] = m;
    }
    return *n > 0 ? 0 : -1;
}

static int parse_costs(const char *list, double *out, int *n)
{
    *n = 0;
    const char *p = list;
    while (*p) {
        char *end = NULL;
        double c = strtod(p, &end);
        if (end == p || !(c > 0 && c <= 4) || *n >= TEXOPT_COMPARE_MAX_COSTS)
            return -1;
        out[(*n)++] = c;
        if (*end == ',')
            end++;
        else if (*end)
            return -1;
        p = end;
    }
    return *n > 0 ? 0 : -1;
}

static void show_progress(void *user, const texopt_progress *p)
{
    (void)user;
    if (strcmp(p->stage, "compare") == 0)
        fprintf(stderr, "compare: %3.0f%% of the methods done\n", 100.0 * p->stage_fraction);
}

/* q of one measure: the headline table, or with --every-texture one more per texture. */
static void print_measure_table(const texopt_compare_result *r, int measure, const double *costs, int cost_count)
{
    int several = 0;
    for (int s = 0; s < TEXOPT_COMPARE_MEASURES; s++)
        several += r->texture_measured[s] != 0;
    if (several > 1)
        printf("%sq on %s:\n", measure == r->measure ? "" : "\n", texopt_compare_measure_name(measure));
    printf("%-11s", "method");
    for (int c = 0; c < cost_count; c++)
        printf("  c_r=%-6.2f", costs[c]);
    printf("\n");
    for (int m = 0; m < r->curve_count; m++) {
        printf("%-11s", texopt_method_name(r->curves[m].method));
        for (int c = 0; c < r->curves[m].point_count; c++) {
            const texopt_compare_point *p = &r->curves[m].points[c];
            if (p->status == TEXOPT_OK)
                printf("  %-10.5f", p->q_by_texture[measure]);
            else
                printf("  %-10s", "failed");
        }
        printf("\n");
    }
}

static void print_table(const texopt_compare_result *r, const double *costs, int cost_count)
{
    print_measure_table(r, r->measure, costs, cost_count);
    for (int s = 0; s < TEXOPT_COMPARE_MEASURES; s++)
        if (r->texture_measured[s] && s != r->measure)
            print_measure_table(r, s, costs, cost_count);
    for (int m = 0; m < r->curve_count; m++)
        for (int c = 0; c < r->curves[m].point_count; c++) {
            const texopt_compare_point *p = &r->curves[m].points[c];
            if (p->status != TEXOPT_OK) {
                fprintf(stderr, "%s at c_r %.2f: %s: %s\n", texopt_method_name(r->curves[m].method), p->cost_requested,
                        texopt_strerror(p->status), p->message);
            }
        }
}

/* A number strictly between 0 and 1 (epsilon, lambda_min); 1 on success. */
static int parse_open_unit(const char *v, double *out)
{
    return v && cli_parse_double(v, 0, 1, out) == 0 && *out > 0 && *out < 1;
}

int cmd_compare(int argc, char **argv)
{
    texopt_method methods[TEXOPT_METHOD_COUNT] = {TEXOPT_METHOD_INPUT, TEXOPT_METHOD_SSP, TEXOPT_METHOD_TEWARI,
                                                  TEXOPT_METHOD_ARAP, TEXOPT_METHOD_PERCEPTUAL};
    int method_count = 5;
    double costs[TEXOPT_COMPARE_MAX_COSTS] = {0.1, 0.2, 0.3, 0.5, 0.7, 1.0};
    int cost_count = 6, quiet = 0;
    const char *input = NULL, *report = NULL, *json = NULL;
    texopt_compare_options opt;
    memset(&opt, 0, sizeof opt);
    opt.evaluate.threads = 2;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0, takes = 1;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return EXIT_OK;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
            takes = 0;
        } else if (!strcmp(a, "--mipmap")) {
            opt.evaluate.mipmapped = 1;
            takes = 0;
        } else if (!strcmp(a, "--every-texture")) {
            opt.every_texture = 1;
            takes = 0;
        } else if (!strcmp(a, "--reuse-layout")) {
            opt.reuse_layout = 1;
            takes = 0;
        } else if (!strcmp(a, "--methods")) {
            bad = !v || parse_methods(v, methods, &method_count) != 0;
        } else if (!strcmp(a, "--costs")) {
            bad = !v || parse_costs(v, costs, &cost_count) != 0;
        } else if (!strcmp(a, "--showcase")) {
            int n = 0;
            double c[TEXOPT_COMPARE_MAX_COSTS];
            bad = !v || parse_costs(v, c, &n) != 0 || n != 1;
            if (!bad)
                opt.showcase_cost = c[0];
        } else if (!strcmp(a, "-o") || !strcmp(a, "--report")) {
            bad = !v;
            report = v;
        } else if (!strcmp(a, "--json")) {
            bad = !v;
            json = v;
        } else if (!strcmp(a, "--resolution")) {
            bad = !v || cli_parse_int(v, 8, 16384, &opt.evaluate.resolution) != 0;
        } else if (!strcmp(a, "--texture")) {
            bad = texopt_evaluate_select_measure(&opt.evaluate, v) != 0;
        } else if (!strcmp(a, "--iterations")) {
            bad = !v || cli_parse_int(v, 1, 100000, &opt.params.iterations) != 0;
        } else if (!strcmp(a, "--epsilon")) {
            bad = !parse_open_unit(v, &opt.params.epsilon);
        } else if (!strcmp(a, "--lambda-min")) {
            bad = !parse_open_unit(v, &opt.params.lambda_min);
        } else if (!strcmp(a, "--seed")) {
            bad = !v || cli_parse_seed(v, &opt.params.seed) != 0;
        } else if (!strcmp(a, "--refinements")) {
            int rounds = 0;
            bad = !v || cli_parse_int(v, 0, 20, &rounds) != 0;
            if (!bad)
                texopt_params_set_refinement_rounds(&opt.params, rounds);
        } else if (!strcmp(a, "--refine-by")) {
            int measure = texopt_refine_measure_from_name(v);
            opt.params.refine_lit = texopt_refine_lit_of(measure);
            bad = measure < 0;
        } else if (!strcmp(a, "--threads")) {
            bad = !v || cli_parse_int(v, 1, 256, &opt.params.threads) != 0;
            if (!bad)
                opt.evaluate.threads = opt.params.threads;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "texopt compare: unknown option '%s'\n", a);
            return EXIT_USAGE;
        } else if (!input) {
            input = a;
            takes = 0;
        } else {
            fprintf(stderr, "texopt compare: more than one input\n");
            return EXIT_USAGE;
        }
        if (bad) {
            fprintf(stderr, "texopt compare: bad or missing value for %s\n", a);
            return EXIT_USAGE;
        }
        i += takes;
    }
    if (!input) {
        usage(stderr);
        return EXIT_USAGE;
    }
    opt.methods = methods;
    opt.method_count = method_count;
    opt.costs = costs;
    opt.cost_count = cost_count;
    texopt_monitor monitor = {quiet ? NULL : show_progress, NULL, cli_cancel_on_signals()};
    opt.monitor = &monitor;

    char err[512] = "";
    texopt_compare_result r;
    texopt_status st = texopt_compare(input, &opt, &r, err, sizeof err);
    if (st == TEXOPT_OK) {
        print_table(&r, costs, cost_count);
        if (json)
            st = texopt_compare_write_json(&r, json, err, sizeof err);
        if (st == TEXOPT_OK && report) {
            const char *base = strrchr(input, '/');
            texopt_report_options ro = {.title = base ? base + 1 : input};
            st = texopt_report_write_html(&r, &ro, report, err, sizeof err);
        }
        texopt_compare_result_destroy(&r);
    }
    if (st != TEXOPT_OK) {
        fprintf(stderr, "texopt compare: %s: %s\n", texopt_strerror(st), err);
        return st == TEXOPT_E_CANCELED ? EXIT_CANCELED : EXIT_ENGINE;
    }
    return EXIT_OK;
}
