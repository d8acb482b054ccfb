/* compare.c - q_r-c_r curves per method through the real pipeline (Sun et al. 2022,
 * section 5.1).
 *
 * Each method is one pipeline job (pipeline.h): its targets (stage 1) are computed once and
 * every cost is one texopt_job_write into a private temporary directory, the output
 * loaded back, measured (evaluate.h) and deleted; only the showcase cost's outputs stay in
 * memory for the report. Points run one after the other: the pipeline itself uses the
 * cores.
 * Does not: draw (report.c), decide which methods exist (the pipeline refuses unknown ones). */
#include "compare.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "atomic_file.h"
#include "build_info.h"
#include "gltf_io.h"
#include "info.h"
#include "lit_shade.h"
#include "meshrender.h"
#include "pipeline.h"

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void texopt_compare_result_destroy(texopt_compare_result *r)
{
    if (!r)
        return;
    for (int c = 0; c < r->curve_count; c++) {
        texopt_model_destroy(r->curves[c].showcase);
        free(r->curves[c].showcase_triangle_error);
    }
    texopt_model_destroy(r->input);
    memset(r, 0, sizeof *r);
}

static texopt_status check_options(const texopt_compare_options *opt, char *err, size_t err_len)
{
    if (!opt || !opt->methods || !opt->costs)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare: methods and costs are required");
    if (opt->method_count < 1 || opt->method_count > TEXOPT_METHOD_COUNT)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare: %d methods (1..%d allowed)",
                           opt->method_count, TEXOPT_METHOD_COUNT);
    if (opt->cost_count < 1 || opt->cost_count > TEXOPT_COMPARE_MAX_COSTS)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare: %d costs (1..%d allowed)",
                           opt->cost_count, TEXOPT_COMPARE_MAX_COSTS);
    for (int m = 0; m < opt->method_count; m++)
        if ((unsigned)opt->methods[m] >= TEXOPT_METHOD_COUNT)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare: unknown method %d",
                               (int)opt->methods[m]);
    if (opt->given_outputs && (opt->cost_count != 1 || opt->reuse_layout))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "compare: given outputs need exactly one cost and no layout reuse");
    for (int c = 0; c < opt->cost_count; c++)
        if (!(opt->costs[c] > 0 && opt->costs[c] <= 4))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare: cost %g is outside (0, 4]",
                               opt->costs[c]);
    return TEXOPT_OK;
}

static double pick_showcase(const texopt_compare_options *opt)
{
    if (opt->showcase_cost > 0)
        return opt->showcase_cost;
    double best = opt->costs[0];
    for (int c = 1; c < opt->cost_count; c++)
        if (fabs(log(opt->costs[c] / 0.3)) < fabs(log(best / 0.3)))
            best = opt->costs[c];
    return best;
}

/* The measure q reports: opt->evaluate's texture, or lit. */
static int headline_measure(const texopt_compare_options *opt)
{
    return opt->evaluate.lit ? TEXOPT_COMPARE_LIT : opt->evaluate.texture;
}

/* q of every measure in `measures` (the headline one, headline_measure, always among them) into
 * pt->q_by_texture; the per-triangle errors, when tri_err is not NULL, and *headline are the
 * headline's. */
static texopt_status measure_textures(const texopt_model *input, const texopt_model *out,
                                      const texopt_compare_options *opt, const int *measures, double *tri_err,
                                      texopt_compare_point *pt, texopt_evaluation *headline)
{
    texopt_status st = TEXOPT_OK;
    for (int s = 0; s < TEXOPT_COMPARE_MEASURES && st == TEXOPT_OK; s++) {
        if (!measures[s])
            continue;
        texopt_evaluate_options eo = opt->evaluate;
        eo.lit = s == TEXOPT_COMPARE_LIT;
        eo.texture = eo.lit ? TEXOPT_SLOT_BASE_COLOR : s;
        eo.triangle_error = s == headline_measure(opt) ? tri_err : NULL;
        eo.monitor = opt->monitor;
        texopt_evaluation ev;
        st = texopt_evaluate(input, out, &eo, &ev, pt->message, sizeof pt->message);
        if (st == TEXOPT_OK)
            pt->q_by_texture[s] = ev.q;
        if (st == TEXOPT_OK && s == headline_measure(opt))
            *headline = ev;
    }
    return st;
}

/* Loads the output at glb, evaluates it against the input in every measure of `measures` and
 * fills pt (q, achieved cost, texture memory). With keep, the loaded model is handed to *model and
 * the per-triangle errors (headline measure) written to tri_err. *ev is the headline's
 * evaluation. */
static texopt_status measure_output(const texopt_model *input, const texopt_cost *input_cost,
                                    const texopt_compare_options *opt, const int *measures, const char *glb, int keep,
                                    texopt_compare_point *pt, texopt_model **model, double *tri_err,
                                    texopt_evaluation *ev)
{
    char *msg = pt->message;
    size_t len = sizeof pt->message;
    texopt_model *out = NULL;
    texopt_status st = texopt_model_load(&out, glb, NULL, msg, len);
    texopt_cost cost_out;
    double t0 = now_seconds();
    if (st == TEXOPT_OK)
        st = measure_textures(input, out, opt, measures, keep ? tri_err : NULL, pt, ev);
    if (st == TEXOPT_OK)
        st = texopt_evaluate_cost(out, &cost_out, msg, len);
    pt->seconds_evaluate = now_seconds() - t0;
    pt->status = st;
    if (st == TEXOPT_OK) {
        pt->q = pt->q_by_texture[headline_measure(opt)];
        pt->cost_achieved =
            input_cost->covered_texels ? (double)cost_out.covered_texels / (double)input_cost->covered_texels : 0;
        pt->texture_pixels = cost_out.texture_pixels;
        pt->packing_efficiency = cost_out.packing_efficiency;
        msg[0] = 0;
    }
    if (st == TEXOPT_OK && keep)
        *model = out;
    else
        texopt_model_destroy(out);
    return st;
}

/* The pipeline's parameters for one run of `method` at a relative cost: a layout is tuned for
 * the lookups q measures it with (job_evaluate.c renders its candidates with params.mipmapped). */
static texopt_params run_params(const texopt_compare_options *opt, texopt_method method)
{
    texopt_params p = opt->params;
    p.method = method;
    p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    p.evaluate = 0;
    p.mipmapped = opt->evaluate.mipmapped != 0;
    /* A JPEG input's outputs are measured as re-baked: the q of a layout, as the statistics'
     * and the target_loss search's q are, not that of quality-98 JPEG noise, which `input`
     * at c_r 1 (its bytes kept) would not pay. */
    p.lossless_textures = 1;
    return p;
}

/* Runs the pipeline with `method` at relative cost `cost` from source to glb. */
static texopt_status optimise(const char *source, const char *glb, const texopt_compare_options *opt,
                              texopt_method method, double cost, texopt_compare_point *pt)
{
    texopt_params p = run_params(opt, method);
    p.relative_cost = cost;
    double t0 = now_seconds();
    texopt_status st = texopt_optimize_file(source, glb, NULL, &p, opt->monitor, pt->message, sizeof pt->message);
    pt->seconds_optimize += now_seconds() - t0;
    pt->status = st;
    return st;
}

static void point_init(texopt_compare_point *pt, double cost)
{
    memset(pt, 0, sizeof *pt);
    pt->cost_requested = cost;
    pt->q = NAN;
    for (int s = 0; s < TEXOPT_COMPARE_MEASURES; s++)
        pt->q_by_texture[s] = NAN;
}

typedef struct run_ctx {
    const char *input_path;
    const texopt_model *input;
    const texopt_cost *input_cost;
    const texopt_compare_options *opt;
    const int *measures; /* texopt_compare_result.texture_measured */
    double showcase_cost;
    const char *tmp_glb, *layout_glb;
} run_ctx;

/* Measures point c of the curve from glb, keeping the output when it is the showcase. */
static texopt_status measure_point(const run_ctx *x, texopt_compare_curve *curve, int c, const char *glb, char *err,
                                   size_t err_len)
{
    texopt_compare_point *pt = &curve->points[c];
    int keep = fabs(pt->cost_requested - x->showcase_cost) < 1e-12 && !curve->showcase;
    double *tri_err = NULL;
    if (keep && !(tri_err = calloc(x->input->triangle_count ? x->input->triangle_count : 1, sizeof *tri_err)))
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for triangle errors");
    texopt_evaluation ev;
    texopt_status st =
        measure_output(x->input, x->input_cost, x->opt, x->measures, glb, keep, pt, &curve->showcase, tri_err, &ev);
    if (keep && st == TEXOPT_OK) {
        curve->showcase_triangle_error = tri_err;
        curve->showcase_evaluation = ev;
    } else
        free(tri_err);
    return TEXOPT_OK;
}

/* A point's own failure is recorded in it; only cancellation and memory stop the comparison. */
static texopt_status fatal(const texopt_compare_point *pt, char *err, size_t err_len)
{
    if (pt->status == TEXOPT_E_CANCELED || pt->status == TEXOPT_E_NOMEM)
        return texopt_fail(err, err_len, pt->status, "%s", pt->message);
    return TEXOPT_OK;
}

/* Every cost through the pipeline's per-budget part: the job computes the method's targets
 * (stage 1 for perceptual) once, then writes one output per cost. A job that cannot be
 * created marks every point failed with its message. */
static texopt_status run_curve_full(const run_ctx *x, texopt_compare_curve *curve, char *err, size_t err_len)
{
    texopt_params p = run_params(x->opt, curve->method);
    texopt_job *job = NULL;
    texopt_compare_point *first = &curve->points[0];
    double t0 = now_seconds();
    first->status = texopt_job_create(&job, x->input_path, &p, x->opt->monitor, first->message, sizeof first->message);
    double seconds_prepare = now_seconds() - t0;
    if (first->status != TEXOPT_OK) {
        for (int c = 1; c < curve->point_count; c++) {
            curve->points[c].status = first->status;
            memcpy(curve->points[c].message, first->message, sizeof first->message);
        }
        return fatal(first, err, err_len);
    }
    texopt_status st = TEXOPT_OK;
    for (int c = 0; c < curve->point_count && st == TEXOPT_OK; c++) {
        texopt_compare_point *pt = &curve->points[c];
        texopt_job_budget b = {TEXOPT_BUDGET_RELATIVE_COST, pt->cost_requested, 0, 0, 0};
        /* The shared part (load, targets) is counted in the first point only. */
        t0 = now_seconds();
        pt->status = texopt_job_write(job, &b, x->tmp_glb, NULL, pt->message, sizeof pt->message);
        pt->seconds_optimize = (c == 0 ? seconds_prepare : 0) + now_seconds() - t0;
        if (pt->status == TEXOPT_OK)
            st = measure_point(x, curve, c, x->tmp_glb, err, err_len);
        unlink(x->tmp_glb);
        if (st == TEXOPT_OK)
            st = fatal(pt, err, err_len);
    }
    texopt_job_destroy(job);
    return st;
}

/* The layout once, at the largest cost; the other costs resample its re-baked textures
 * (method "input" applied to that output): filtered twice, chart gutters scaled rather than
 * re-padded, and the layout allocated for the largest budget rather than each one (which
 * measurably raises q: see compare.h). */
static texopt_status run_curve_reusing_layout(const run_ctx *x, texopt_compare_curve *curve, char *err, size_t err_len)
{
    int top = 0;
    for (int c = 1; c < curve->point_count; c++)
        if (curve->points[c].cost_requested > curve->points[top].cost_requested)
            top = c;
    texopt_compare_point *tp = &curve->points[top];
    double top_cost = tp->cost_requested;
    texopt_status st = TEXOPT_OK;
    if (optimise(x->input_path, x->layout_glb, x->opt, curve->method, top_cost, tp) != TEXOPT_OK) {
        for (int c = 0; c < curve->point_count; c++)
            if (c != top) {
                curve->points[c].status = tp->status;
                memcpy(curve->points[c].message, tp->message, sizeof tp->message); /* c != top */
            }
        unlink(x->layout_glb);
        return fatal(tp, err, err_len);
    }
    for (int c = 0; c < curve->point_count && st == TEXOPT_OK; c++) {
        texopt_compare_point *pt = &curve->points[c];
        if (c == top) {
            st = measure_point(x, curve, c, x->layout_glb, err, err_len);
        } else {
            if (optimise(x->layout_glb, x->tmp_glb, x->opt, TEXOPT_METHOD_INPUT, pt->cost_requested / top_cost, pt) ==
                TEXOPT_OK)
                st = measure_point(x, curve, c, x->tmp_glb, err, err_len);
            unlink(x->tmp_glb);
        }
        if (st == TEXOPT_OK)
            st = fatal(pt, err, err_len);
    }
    unlink(x->layout_glb);
    return st;
}

static void report_progress(const texopt_compare_options *opt, int done, int total)
{
    texopt_progress p = {.stage = "compare",
                         .stage_fraction = (double)done / total,
                         .fraction = (double)done / total,
                         .eta_seconds = -1};
    texopt_monitor_report(opt->monitor, &p);
}

static void mark_measured_textures(const texopt_model *input, const texopt_compare_options *opt, int *measured)
{
    for (int s = 0; s < TEXOPT_TEXTURE_KEY_COUNT; s++)
        measured[s] = s == headline_measure(opt) || (opt->every_texture && texopt_meshrender_has_texture(input, s));
    /* Without a map that lighting reads besides base colour, lit would be base colour's q
     * through a shading both renders share: nothing new, unless asked for. */
    measured[TEXOPT_COMPARE_LIT] =
        headline_measure(opt) == TEXOPT_COMPARE_LIT || (opt->every_texture && texopt_lit_has_maps(input));
}

static texopt_status make_work_dir(const texopt_compare_options *opt, char *dir, size_t len, char *err, size_t err_len)
{
    const char *base = opt->work_dir ? opt->work_dir : getenv("TMPDIR");
    if (!base || !base[0])
        base = "/tmp";
    if ((size_t)snprintf(dir, len, "%s/texopt-compare-XXXXXX", base) >= len)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "work directory path too long");
    if (!mkdtemp(dir))
        return texopt_fail(err, err_len, TEXOPT_E_IO, "cannot create a directory under %s", base);
    return TEXOPT_OK;
}

texopt_status texopt_compare(const char *input_path, const texopt_compare_options *opt, texopt_compare_result *out,
                             char *err, size_t err_len)
{
    if (!input_path || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare: missing input or result");
    memset(out, 0, sizeof *out);
    texopt_status st = check_options(opt, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    texopt_compare_result r;
    memset(&r, 0, sizeof r);
    r.showcase_cost = pick_showcase(opt);
    st = texopt_model_load(&r.input, input_path, NULL, err, err_len);
    if (st == TEXOPT_OK)
        st = opt->evaluate.lit ? texopt_evaluate_check_lit(r.input, err, err_len)
                               : texopt_evaluate_check_texture(r.input, opt->evaluate.texture, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_evaluate_cost(r.input, &r.input_cost, err, err_len);
    r.resolution = opt->evaluate.resolution;
    r.mipmapped = opt->evaluate.mipmapped != 0;
    r.measure = headline_measure(opt);
    if (st == TEXOPT_OK)
        mark_measured_textures(r.input, opt, r.texture_measured);
    if (st == TEXOPT_OK && r.resolution == 0)
        st = texopt_evaluate_default_resolution(r.input, &r.resolution, err, err_len);
    char dir[1024] = "", tmp_glb[1100];
    if (st == TEXOPT_OK)
        st = make_work_dir(opt, dir, sizeof dir, err, err_len);
    if (st != TEXOPT_OK) {
        texopt_compare_result_destroy(&r);
        return st;
    }
    char layout_glb[1100];
    snprintf(tmp_glb, sizeof tmp_glb, "%s/run.glb", dir);
    snprintf(layout_glb, sizeof layout_glb, "%s/layout.glb", dir);
    texopt_compare_options o = *opt;
    o.evaluate.resolution = r.resolution;
    run_ctx x = {input_path, r.input, &r.input_cost, &o, r.texture_measured, r.showcase_cost, tmp_glb, layout_glb};
    r.curve_count = opt->method_count;
    for (int m = 0; m < opt->method_count && st == TEXOPT_OK; m++) {
        texopt_compare_curve *curve = &r.curves[m];
        curve->method = opt->methods[m];
        curve->point_count = opt->cost_count;
        for (int c = 0; c < opt->cost_count; c++)
            point_init(&curve->points[c], opt->costs[c]);
        const char *given = opt->given_outputs ? opt->given_outputs[m] : NULL;
        if (given) {
            st = measure_point(&x, curve, 0, given, err, err_len);
            if (st == TEXOPT_OK)
                st = fatal(&curve->points[0], err, err_len);
        } else if (!opt->reuse_layout || curve->method == TEXOPT_METHOD_INPUT)
            st = run_curve_full(&x, curve, err, err_len);
        else
            st = run_curve_reusing_layout(&x, curve, err, err_len);
        report_progress(opt, m + 1, opt->method_count);
    }
    rmdir(dir);
    if (st != TEXOPT_OK) {
        texopt_compare_result_destroy(&r);
        return st;
    }
    *out = r;
    return TEXOPT_OK;
}

const char *texopt_compare_measure_name(int m)
{
    return m == TEXOPT_COMPARE_LIT ? "lit" : texopt_texture_key_name(m);
}

/* "q_by_texture": {texture name: q} when more than the headline measure was measured. */
static void add_q_by_texture(cJSON *o, const texopt_compare_point *pt, const int *measures)
{
    int n = 0;
    for (int s = 0; s < TEXOPT_COMPARE_MEASURES; s++)
        n += measures[s] != 0;
    if (n < 2)
        return;
    cJSON *by = cJSON_AddObjectToObject(o, "q_by_texture");
    for (int s = 0; by && s < TEXOPT_COMPARE_MEASURES; s++)
        if (measures[s])
            cJSON_AddNumberToObject(by, texopt_compare_measure_name(s), pt->q_by_texture[s]);
}

static cJSON *point_json(const texopt_compare_point *pt, const int *measures)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "cost_requested", pt->cost_requested);
    if (pt->status == TEXOPT_OK) {
        cJSON_AddNumberToObject(o, "cost_achieved", pt->cost_achieved);
        cJSON_AddNumberToObject(o, "q", pt->q);
        cJSON_AddNumberToObject(o, "texture_pixels", (double)pt->texture_pixels);
        cJSON_AddNumberToObject(o, "packing_efficiency", pt->packing_efficiency);
        cJSON_AddNumberToObject(o, "seconds_optimize", pt->seconds_optimize);
        cJSON_AddNumberToObject(o, "seconds_evaluate", pt->seconds_evaluate);
        add_q_by_texture(o, pt, measures);
    } else {
        cJSON_AddStringToObject(o, "error", texopt_strerror(pt->status));
        cJSON_AddStringToObject(o, "message", pt->message);
    }
    return o;
}

texopt_status texopt_compare_write_json(const texopt_compare_result *r, const char *path, char *err, size_t err_len)
{
    if (!r || !path)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "compare json: missing argument");
    cJSON *root = cJSON_CreateObject();
    if (!root)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for JSON");
    texopt_build_info_add_json(root);
    cJSON_AddNumberToObject(root, "resolution", r->resolution);
    cJSON_AddStringToObject(root, "lookup", r->mipmapped ? "mipmapped" : "bilinear");
    cJSON_AddStringToObject(root, "texture", texopt_compare_measure_name(r->measure));
    cJSON_AddNumberToObject(root, "input_covered_texels", (double)r->input_cost.covered_texels);
    cJSON_AddNumberToObject(root, "input_texture_pixels", (double)r->input_cost.texture_pixels);
    cJSON *curves = cJSON_AddObjectToObject(root, "curves");
    for (int c = 0; c < r->curve_count; c++) {
        cJSON *arr = cJSON_AddArrayToObject(curves, texopt_method_name(r->curves[c].method));
        for (int i = 0; i < r->curves[c].point_count; i++)
            cJSON_AddItemToArray(arr, point_json(&r->curves[c].points[i], r->texture_measured));
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for JSON");
    texopt_status st = texopt_write_file_atomic(path, text, strlen(text), err, err_len);
    free(text);
    return st;
}

double texopt_compare_cost_at_loss(const texopt_compare_curve *curve, double q_goal)
{
    double c[TEXOPT_COMPARE_MAX_COSTS], q[TEXOPT_COMPARE_MAX_COSTS];
    int n = 0;
    for (int i = 0; i < curve->point_count; i++) {
        const texopt_compare_point *pt = &curve->points[i];
        if (pt->status != TEXOPT_OK || !(pt->cost_achieved > 0) || !isfinite(pt->q))
            continue;
        int k = n++;
        while (k > 0 && c[k - 1] > pt->cost_achieved) {
            c[k] = c[k - 1];
            q[k] = q[k - 1];
            k--;
        }
        c[k] = pt->cost_achieved;
        q[k] = pt->q;
    }
    if (n == 0)
        return -1;
    if (q[0] <= q_goal)
        return c[0]; /* already there at the cheapest point measured */
    for (int i = 1; i < n; i++)
        if (q[i] <= q_goal) {
            double t = (q[i - 1] - q_goal) / (q[i - 1] - q[i]);
            return exp(log(c[i - 1]) + t * (log(c[i]) - log(c[i - 1])));
        }
    return -1;
}
