/* cmd_optimize.c - `texopt optimize IN -o OUT.glb [options]`: the whole job on one model.
 *
 * Parses the options into texopt_params, runs texopt_optimize_file (engine/job/pipeline.h) and
 * shows progress on stderr: a redrawn bar (stage, percent, ETA) on a terminal, one plain line
 * per stage and per 10% otherwise, nothing with --quiet. SIGINT/SIGTERM raise the engine's
 * cancel flag; the job stops at its next checkpoint and the command exits 3. Implements no
 * part of Sun et al. 2022 itself; it is the asset-pipeline front end of the engine. */
#include <errno.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cancel.h"
#include "commands.h"
#include "numbers.h"
#include "texopt.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: texopt optimize IN -o OUT.glb [options]\n"
                 "\n"
                 "Computes a new UV layout of IN (.glb or .gltf) that spends texels where the rendered\n"
                 "look needs them, re-bakes its textures and writes OUT.glb.\n"
                 "\n"
                 "options:\n"
                 "  -o, --output PATH        output .glb (required)\n"
                 "  --method M               perceptual (default); input (same layout, textures\n"
                 "                           resized to the budget with Lanczos-3, as image\n"
                 "                           tools do); ssp, tewari, arap (the\n"
                 "                           paper's baselines: metric targets, same stage 2);\n"
                 "                           paper (Sun et al. 2022 as written: one layout,\n"
                 "                           plain Bayesian optimisation, epsilon 0.01)\n"
                 "  --relative-cost C        covered texels of the output / of the input, (0, 4]\n"
                 "                           (default 1)\n"
                 "  --texture-size WxH       output texture size instead of a relative cost\n"
                 "  --target-loss Q          the smallest relative cost (searched in [0.01, 1]) whose\n"
                 "                           whole-mesh loss q against the input is at most Q, (0, 1);\n"
                 "                           q and the search are in the statistics\n"
                 "  --epsilon E              perceptual loss threshold of stage 1 (default 0.03;\n"
                 "                           paper: 0.01)\n"
                 "  --iterations N           most Bayesian-optimisation polish iterations per triangle\n"
                 "                           (default 100; the polish stops once it stops paying;\n"
                 "                           paper: exactly N after its initial samples)\n"
                 "  --lambda-min L           smallest per-axis scale stage 1 may choose (default 0.1)\n"
                 "  --threads T              worker threads (default: every core)\n"
                 "  --seed S                 random seed, 0 to 2^53 (default 0)\n"
                 "  --refinements N          perceptual: most closed-loop refinement rounds of the\n"
                 "                           kept layout by its on-screen error, 0-20 (default 4;\n"
                 "                           0: none)\n"
                 "  --refine-by M            perceptual: what the refinement's screen shows, lit\n"
                 "                           (default: every map under a light, when the material\n"
                 "                           has more than base colour; slower) or baseColor\n"
                 "  --hessian-floor K        perceptual: raise stage 1's targets to K times the\n"
                 "                           Hessian metric's singular values, [0, 1] (default\n"
                 "                           0.5; 0: no floor)\n"
                 "  --metric-candidates B    perceptual: yes (default) or no: the tewari and ssp\n"
                 "                           layouts are candidates beside stage 1's\n"
                 "  --resize-check B         perceptual: yes (default) or no: a domain whose layout\n"
                 "                           does not beat the input layout resized (or re-baked)\n"
                 "                           at the same pixels writes that instead\n"
                 "  --bijective              stage 2 with scaffold triangles: no chart overlaps itself\n"
                 "  --packing P              plain (default) or refine: charts deformed toward\n"
                 "                           axis-aligned shapes before packing (Liu et al. 2019),\n"
                 "                           the tighter packing kept\n"
                 "  --packing-efficiency E   packing refine with the bound E, [0, 1): its\n"
                 "                           decompositions must reach E and its distortion\n"
                 "                           reduction may not lower a packing below it\n"
                 "                           (default with refine: 0.8, the paper's)\n"
                 "  --charts C               keep (default: the input's charts) or new (cut new disk\n"
                 "                           charts and lay them out anew, re-baked from the input)\n"
                 "  --parameterizer P        with --charts new: abf (default), lscm, tutte or square\n"
                 "  --stats PATH             write the job statistics as JSON\n"
                 "  --evaluate               measure the whole-mesh perceptual loss q of the result\n"
                 "                           against the input (into the statistics)\n"
                 "  --mipmap                 tune the layout for, and measure q with, prefiltered\n"
                 "                           (mip-mapped) lookups, as real-time renderers draw\n"
                 "                           (default: bilinear, the paper's)\n"
                 "  --quiet                  no progress on stderr\n"
                 "  -h, --help               this text\n"
                 "\n"
                 "exit codes: 0 success, 1 the engine refused or failed, 2 usage error, 3 canceled\n");
}

typedef struct progress_view {
    int tty;
    const char *last_stage;
    int last_decile;
    int drew;
} progress_view;

static void show_progress(void *user, const texopt_progress *p)
{
    progress_view *v = user;
    int percent = (int)(p->fraction * 100.0 + 0.5);
    if (v->tty) {
        char eta[32] = "";
        if (p->eta_seconds >= 0)
            snprintf(eta, sizeof eta, " ETA %4.0fs", p->eta_seconds);
        int filled = (int)(p->fraction * 30.0);
        char bar[31];
        for (int i = 0; i < 30; i++)
            bar[i] = i < filled ? '#' : '.';
        bar[30] = '\0';
        fprintf(stderr, "\r%-7s [%s] %3d%%%s   ", p->stage, bar, percent, eta);
        v->drew = 1;
        return;
    }
    int decile = percent / 10;
    if (v->last_stage && strcmp(v->last_stage, p->stage) == 0 && decile == v->last_decile)
        return;
    v->last_stage = p->stage;
    v->last_decile = decile;
    if (p->eta_seconds >= 0)
        fprintf(stderr, "texopt: %s %d%% (ETA %.0f s)\n", p->stage, percent, p->eta_seconds);
    else
        fprintf(stderr, "texopt: %s %d%%\n", p->stage, percent);
}

static int parse_double(const char *s, double *out)
{
    return cli_parse_double(s, -HUGE_VAL, HUGE_VAL, out) == 0;
}

static int parse_long(const char *s, long long *out)
{
    char *end;
    errno = 0;
    *out = strtoll(s, &end, 10);
    return errno == 0 && end != s && *end == '\0';
}

static int parse_size(const char *s, int *w, int *h)
{
    char tail;
    return sscanf(s, "%dx%d%c", w, h, &tail) == 2 && *w > 0 && *h > 0;
}

typedef struct optimize_args {
    const char *input, *output, *stats;
    int quiet;
    texopt_params params;
} optimize_args;

/* Returns -1 on success (continue), else the exit code to return. */
static int parse_option(optimize_args *a, const char *opt, const char *val)
{
    double d;
    long long n;
    uint64_t seed;
    if (strcmp(opt, "-o") == 0 || strcmp(opt, "--output") == 0)
        a->output = val;
    else if (strcmp(opt, "--stats") == 0)
        a->stats = val;
    else if (strcmp(opt, "--method") == 0) {
        a->params.method = texopt_method_from_name(val);
        if (a->params.method == TEXOPT_METHOD_COUNT) {
            fprintf(stderr, "texopt optimize: unknown method '%s'\n", val);
            return EXIT_USAGE;
        }
    } else if (strcmp(opt, "--relative-cost") == 0 && parse_double(val, &d)) {
        a->params.budget = TEXOPT_BUDGET_RELATIVE_COST;
        a->params.relative_cost = d;
        if (!(d > 0)) {
            fprintf(stderr, "texopt optimize: --relative-cost must be > 0\n");
            return EXIT_USAGE;
        }
    } else if (strcmp(opt, "--texture-size") == 0 &&
               parse_size(val, &a->params.texture_width, &a->params.texture_height))
        a->params.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    else if (strcmp(opt, "--target-loss") == 0 && parse_double(val, &d)) {
        a->params.budget = TEXOPT_BUDGET_TARGET_LOSS;
        a->params.target_loss = d;
    } else if (strcmp(opt, "--epsilon") == 0 && parse_double(val, &d) && d > 0)
        a->params.epsilon = d;
    else if (strcmp(opt, "--lambda-min") == 0 && parse_double(val, &d) && d > 0)
        a->params.lambda_min = d;
    else if (strcmp(opt, "--iterations") == 0 && parse_long(val, &n) && n > 0 && n < 1000000)
        a->params.iterations = (int)n;
    else if (strcmp(opt, "--threads") == 0 && parse_long(val, &n) && n > 0 && n < 100000)
        a->params.threads = (int)n;
    else if (strcmp(opt, "--seed") == 0 && cli_parse_seed(val, &seed) == 0)
        a->params.seed = seed;
    else if (strcmp(opt, "--refinements") == 0 && parse_long(val, &n) && n >= 0 && n <= 20)
        texopt_params_set_refinement_rounds(&a->params, (int)n);
    else if (strcmp(opt, "--refine-by") == 0 && texopt_refine_measure_from_name(val) >= 0)
        a->params.refine_lit = texopt_refine_lit_of(texopt_refine_measure_from_name(val));
    else if (strcmp(opt, "--packing-efficiency") == 0 && parse_double(val, &d) && d >= 0 && d < 1)
        a->params.packing_efficiency = d;
    else if (strcmp(opt, "--packing") == 0 && texopt_packing_from_name(val) >= 0)
        a->params.packing_refine = texopt_packing_from_name(val);
    else if (strcmp(opt, "--hessian-floor") == 0 && parse_double(val, &d) && d >= 0 && d <= 1)
        texopt_params_set_hessian_floor(&a->params, d);
    else if (strcmp(opt, "--metric-candidates") == 0 && (strcmp(val, "yes") == 0 || strcmp(val, "no") == 0))
        a->params.metric_candidates = strcmp(val, "yes") == 0 ? 1 : -1;
    else if (strcmp(opt, "--resize-check") == 0 && (strcmp(val, "yes") == 0 || strcmp(val, "no") == 0))
        a->params.resize_check = strcmp(val, "yes") == 0 ? 1 : -1;
    else if (strcmp(opt, "--charts") == 0 && texopt_charts_from_name(val) >= 0)
        a->params.charts = (texopt_charts)texopt_charts_from_name(val);
    else if (strcmp(opt, "--parameterizer") == 0 && texopt_parameterizer_from_name(val) >= 0)
        a->params.parameterizer = (texopt_parameterizer)texopt_parameterizer_from_name(val);
    else {
        fprintf(stderr, "texopt optimize: bad option or value: %s %s\n", opt, val);
        return EXIT_USAGE;
    }
    return -1;
}

static int parse_args(int argc, char **argv, optimize_args *a)
{
    int budget_options = 0;
    for (int i = 0; i < argc; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            usage(stdout);
            return EXIT_OK;
        }
        if (strcmp(arg, "--quiet") == 0) {
            a->quiet = 1;
            continue;
        }
        if (strcmp(arg, "--evaluate") == 0) {
            a->params.evaluate = 1;
            continue;
        }
        if (strcmp(arg, "--mipmap") == 0) {
            a->params.mipmapped = 1;
            continue;
        }
        if (strcmp(arg, "--bijective") == 0) {
            a->params.bijective = 1;
            continue;
        }
        if (arg[0] == '-' && arg[1] != '\0') {
            if (i + 1 >= argc) {
                fprintf(stderr, "texopt optimize: %s needs a value\n", arg);
                return EXIT_USAGE;
            }
            budget_options += strcmp(arg, "--relative-cost") == 0 || strcmp(arg, "--texture-size") == 0 ||
                              strcmp(arg, "--target-loss") == 0;
            int rc = parse_option(a, arg, argv[++i]);
            if (rc >= 0)
                return rc;
            continue;
        }
        if (a->input) {
            fprintf(stderr, "texopt optimize: more than one input (%s, %s)\n", a->input, arg);
            return EXIT_USAGE;
        }
        a->input = arg;
    }
    if (budget_options > 1) {
        fprintf(stderr, "texopt optimize: give one of --relative-cost, --texture-size, --target-loss\n");
        return EXIT_USAGE;
    }
    if (!a->input || !a->output) {
        usage(stderr);
        return EXIT_USAGE;
    }
    return -1;
}

int cmd_optimize(int argc, char **argv)
{
    optimize_args a;
    memset(&a, 0, sizeof a);
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0)
        return rc;
    texopt_params check = a.params;
    texopt_params_resolve(&check);
    char err[1024] = "";
    if (texopt_params_validate(&check, err, sizeof err) != TEXOPT_OK) {
        fprintf(stderr, "texopt optimize: %s\n", err);
        return EXIT_USAGE;
    }
    const atomic_int *cancel = cli_cancel_on_signals();
    progress_view view = {isatty(STDERR_FILENO), NULL, -1, 0};
    texopt_monitor monitor = {a.quiet ? NULL : show_progress, &view, cancel};
    texopt_status st = texopt_optimize_file(a.input, a.output, a.stats, &a.params, &monitor, err, sizeof err);
    if (view.drew)
        fputc('\n', stderr);
    if (st == TEXOPT_E_CANCELED) {
        fprintf(stderr, "texopt optimize: canceled\n");
        return EXIT_CANCELED;
    }
    if (st != TEXOPT_OK) {
        fprintf(stderr, "texopt optimize: %s: %s\n", texopt_strerror(st), err);
        return EXIT_ENGINE;
    }
    if (!a.quiet)
        fprintf(stderr, "texopt: wrote %s%s%s\n", a.output, a.stats ? " and " : "", a.stats ? a.stats : "");
    return EXIT_OK;
}
