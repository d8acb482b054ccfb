/* triopt.c - the triangle-wise stage of Sun et al. 2022 (section 4.1.2, eqs. 14 and 17):
 * a Bayesian optimisation of each triangle's Jacobian over the one-ring perceptual loss,
 * run over all cores.
 *
 * DESIGN. The caller's thread starts `threads` POSIX threads. Each owns a loss evaluator
 * (triloss: raster, references, bake and GMSD buffers) and a BO workspace, created once and
 * reused for every triangle it takes. Threads take the next triangle index from an atomic
 * counter and write only out[t], computed from (seed, t) alone, so the schedule never shows
 * in the output. One mutex guards the running statistics, the progress callback and the
 * first error. The cancel flag is read before each triangle.
 *
 * Not here: the loss itself (triloss.c), the optimiser (bayesopt.c), what the mesh-wise
 * stage does with the targets (meshwise.c). */
#include "triopt.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bayesopt.h"
#include "parallel.h"
#include "rng.h"
#include "triloss.h"

#define TRIOPT_DIM 4
#define QUARTER_TURN 1.57079632679489661923 /* pi / 2 */
#define TRIOPT_ERR_LEN 256
/* Objective values within this of the lower bound count as reaching it (GMSD of a flat
 * region is 0 up to float rounding, and -log(eps - E) moves by E / eps). */
#define TRIOPT_BOUND_TOLERANCE 1e-6
/* Evaluations of the searches kept for the polish's surrogate (a non-flat triangle makes
 * 20-70 with the default plan). */
#define TRIOPT_HISTORY 128
/* Default polish stop: polish_patience evaluations in a row that gain less than this share
 * of f (BENCHMARKS.md@9f788a8, "Stage 1"). */
#define TRIOPT_POLISH_STOP 0.001
#define TRIOPT_POLISH_PATIENCE 1

typedef struct resolved_options {
    double epsilon, lambda_min;
    int iterations, threads, viewport, weight_samples, initial_design;
    int lower_bound_stop;
    int plain;
    int paper_window;
    int isotropic_steps;
    int anisotropic_steps;
    int anisotropic_passes;
    int anisotropic_directions;
    double polish_stop;
    int polish_patience;
    uint32_t stride;
    uint64_t seed;
    int max_evaluations;
    const double *signal_weights;
} resolved_options;

typedef struct stage_shared {
    const texopt_model *model;
    const texopt_mesh *mesh;
    resolved_options opt;
    texopt_triangle_target *out;
    const texopt_monitor *monitor;
    atomic_size_t next;
    atomic_int stop;
    size_t total; /* triangles to optimise */
    double start_seconds;

    pthread_mutex_t lock; /* guards everything below */
    size_t done;
    double sum_loss, sum_area_scale;
    double cpu_seconds;        /* summed thread CPU time of the workers */
    size_t close_up_triangles; /* summed over the workers when they end */
    size_t report_every;
    texopt_status status;
    size_t failed_triangle;
    char err[TRIOPT_ERR_LEN];
} stage_shared;

typedef struct worker {
    stage_shared *sh;
    texopt_triloss *loss;
    texopt_bo *bo;
    size_t close_up_triangles;
} worker;

/* State of one triangle's search, seen by the objective. */
typedef struct triangle_search {
    texopt_triloss *loss;
    double epsilon, lambda_min, area;
    double cut_loss; /* E at which the running evaluation may stop: it cannot matter above */
    int evaluations;
    double best_f, best_loss, best_x[TRIOPT_DIM];
    int history_count; /* evaluated points and their f, for the polish */
    double history_x[TRIOPT_HISTORY * TRIOPT_DIM], history_f[TRIOPT_HISTORY];
    texopt_status status;
    char err[TRIOPT_ERR_LEN];
} triangle_search;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* splitmix64 finaliser: a well-spread 64-bit seed per (seed, triangle, stream). */
static uint64_t mix_seed(uint64_t seed, uint64_t triangle, uint64_t stream)
{
    uint64_t z = seed ^ (triangle * 0x9E3779B97F4A7C15ull) ^ (stream * 0xD1B54A32D192ED03ull);
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* The unit box's upper face x = 1 maps to pi/2, which the paper's domain [0, pi/2) names 0:
 * a quarter turn of the texel grid maps the grid onto itself (the 90-degree symmetry). */
static double wrap_quarter(double angle)
{
    return angle >= QUARTER_TURN ? angle - QUARTER_TURN : angle;
}

static void params_from_unit(const double *x, double lambda_min, double p[4])
{
    p[0] = x[0] * QUARTER_TURN;
    p[1] = lambda_min + (1.0 - lambda_min) * x[1];
    p[2] = lambda_min + (1.0 - lambda_min) * x[2];
    p[3] = x[3] * QUARTER_TURN;
}

static double objective_value(double area_scale, double area, double loss, double epsilon)
{
    return area_scale * area - log(epsilon - loss);
}

static void remember(triangle_search *s, const double *x, double f)
{
    if (s->history_count == TRIOPT_HISTORY)
        return;
    memcpy(s->history_x + (size_t)s->history_count * TRIOPT_DIM, x, TRIOPT_DIM * sizeof *x);
    s->history_f[s->history_count++] = f;
}

static double search_objective(void *user, const double *x)
{
    triangle_search *s = user;
    if (s->status != TEXOPT_OK)
        return INFINITY;
    double p[4], J[4], e = 0.0;
    params_from_unit(x, s->lambda_min, p);
    texopt_jacobian_from_params(p[0], p[1], p[2], p[3], J);
    s->evaluations++;
    s->status = texopt_triloss_eval(s->loss, J, s->cut_loss, &e, s->err, sizeof s->err);
    if (s->status != TEXOPT_OK)
        return INFINITY;
    double f = e < s->epsilon ? objective_value(p[1] * p[2], s->area, e, s->epsilon) : INFINITY;
    if (e >= s->cut_loss && s->cut_loss < s->epsilon)
        return f; /* E may be only a lower bound: not a record, not for the polish */
    remember(s, x, f);
    if (!isfinite(f))
        return INFINITY;
    /* Strictly smaller only: the first of equal optima wins, as in the BO's own record. */
    if (f < s->best_f) {
        s->best_f = f;
        s->best_loss = e;
        memcpy(s->best_x, x, sizeof s->best_x);
    }
    return f;
}

/* f at x when it might beat `must_beat`; otherwise (its area term alone, with E = 0,
 * already exceeds must_beat) that lower bound, without evaluating E. The callers compare
 * the value with must_beat only, so their decisions and the best point are the same as
 * with the exact value: only the evaluation is saved. */
static double search_objective_below(triangle_search *s, const double *x, double must_beat)
{
    double p[4];
    params_from_unit(x, s->lambda_min, p);
    double floor_f = objective_value(p[1] * p[2], s->area, 0.0, s->epsilon);
    if (floor_f > must_beat)
        return floor_f;
    /* f >= must_beat once E >= eps - exp(area term - must_beat): the evaluation may stop
     * there (triloss solves the leading signal first). Nudged up so that a cut f exceeds
     * must_beat strictly, as the exact one would. */
    double cut = s->epsilon - exp(floor_f + log(s->epsilon) - must_beat);
    for (double step = fmax(cut * 1e-15, 1e-18);
         cut < s->epsilon && !(objective_value(p[1] * p[2], s->area, cut, s->epsilon) > must_beat); step *= 2.0)
        cut += step;
    s->cut_loss = cut < s->epsilon ? cut : s->epsilon;
    double f = search_objective(s, x);
    s->cut_loss = s->epsilon;
    return f;
}

static double variance(const double *v, int n)
{
    double mean = 0.0, var = 0.0;
    for (int i = 0; i < n; i++)
        mean += v[i];
    mean /= n;
    for (int i = 0; i < n; i++)
        var += (v[i] - mean) * (v[i] - mean);
    return var / n;
}

/* A random permutation of 0..n-1 into perm (Fisher-Yates). */
static void shuffle(texopt_rng *rng, int *perm, int n)
{
    for (int k = 0; k < n; k++)
        perm[k] = k;
    for (int k = n - 1; k > 0; k--) {
        int j = (int)texopt_rng_below(rng, (uint32_t)k + 1);
        int tmp = perm[k];
        perm[k] = perm[j];
        perm[j] = tmp;
    }
}

/* Eq. 17: how much E moves when only the rotation, or only the stretch, changes. The
 * stretch samples form a Latin hypercube: each of lambda1, lambda2, beta uniform and
 * stratified into n strata, which ranks the triangles' w_stretch closer to a dense
 * estimate than independent draws at the same cost (BENCHMARKS.md@9f788a8, "Stage 1"). */
static texopt_status sensitivity_weights(worker *w, uint32_t t, texopt_triangle_target *o, char *err, size_t err_len)
{
    const resolved_options *opt = &w->sh->opt;
    int n = opt->weight_samples;
    if (n <= 0)
        return TEXOPT_OK;
    double values[64];
    if (n > 64)
        n = 64;
    texopt_rng rng;
    texopt_rng_seed(&rng, mix_seed(opt->seed, t, 2));
    double J[4];
    for (int k = 0; k < n; k++) {
        double alpha = (k + texopt_rng_uniform(&rng)) / n * QUARTER_TURN;
        texopt_jacobian_from_params(alpha, o->lambda1, o->lambda2, o->beta, J);
        texopt_status st = texopt_triloss_eval(w->loss, J, INFINITY, &values[k], err, err_len);
        if (st != TEXOPT_OK)
            return st;
    }
    o->w_rotation = variance(values, n);
    int strata[3][64];
    for (int d = 0; d < 3; d++)
        shuffle(&rng, strata[d], n);
    double span = 1.0 - opt->lambda_min;
    for (int k = 0; k < n; k++) {
        double l1 = opt->lambda_min + span * (strata[0][k] + texopt_rng_uniform(&rng)) / n;
        double l2 = opt->lambda_min + span * (strata[1][k] + texopt_rng_uniform(&rng)) / n;
        double beta = (strata[2][k] + texopt_rng_uniform(&rng)) / n * QUARTER_TURN;
        texopt_jacobian_from_params(o->alpha, l1, l2, beta, J);
        texopt_status st = texopt_triloss_eval(w->loss, J, INFINITY, &values[k], err, err_len);
        if (st != TEXOPT_OK)
            return st;
    }
    o->w_stretch = variance(values, n);
    o->evaluations += 2 * n;
    return TEXOPT_OK;
}

/* The smallest isotropic shrink: when even lambda_min I loses nothing, no J can beat it
 * (it reaches the objective's lower bound) and E is 0 all over the box, so the weights of
 * eq. 17 are 0 without sampling them. Returns 1 for such a flat triangle. */
static int flat_at_smallest_area(triangle_search *s, double lower_bound)
{
    static const double smallest[TRIOPT_DIM] = {0, 0, 0, 0};
    double f = search_objective(s, smallest);
    return s->status == TEXOPT_OK && f <= lower_bound;
}

static void set_coordinates(double x[TRIOPT_DIM], unsigned coords, double value)
{
    for (int i = 0; i < TRIOPT_DIM; i++)
        if (coords & 1u << i)
            x[i] = value;
}

/* Golden-section search of f along the unit coordinates in the bit mask `coords`, all set
 * to the same value in [a, b], the others as in x: `evaluations` >= 2 points; the best one
 * lands in s->best_x. Equal values (both infeasible) move right: infeasibility sits at
 * small shrinks. */
static void golden_section(triangle_search *s, double x[TRIOPT_DIM], unsigned coords, double a, double b,
                           int evaluations)
{
    const double g = 0.6180339887498949;
    double c = b - g * (b - a), d = a + g * (b - a);
    set_coordinates(x, coords, c);
    double fc = search_objective(s, x);
    set_coordinates(x, coords, d);
    double fd = search_objective_below(s, x, fc);
    for (int k = 2; k < evaluations && s->status == TEXOPT_OK; k++) {
        if (fc < fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            set_coordinates(x, coords, c);
            fc = search_objective_below(s, x, fd);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            set_coordinates(x, coords, d);
            fd = search_objective_below(s, x, fc);
        }
    }
}

/* Golden-section search of f over isotropic shrinks J = lambda I, x = (0, u, u, 0): E grows
 * as lambda falls, so f is +INFINITY below the feasibility boundary and unimodal above it
 * in practice. */
static void isotropic_search(triangle_search *s, int evaluations)
{
    double x[TRIOPT_DIM] = {0, 0, 0, 0};
    golden_section(s, x, 1u << 1 | 1u << 2, 0.0, 1.0, evaluations);
}

/* The best squeeze probed so far in one anisotropic refinement: the point it started from
 * (its coordinates as the probe saw them), the squeezed axis and orientation, and f. */
typedef struct squeeze {
    double start[TRIOPT_DIM];
    int axis; /* 0: nothing beat the refinement's starting f */
    double beta, f;
} squeeze;

/* Probes squeezing `axis` of `start` to 0.6 of its unit coordinate at orientation `beta`
 * (unit coordinate, in steps of 1/directions; may leave [0, 1)) and keeps it in *best when
 * it lowers f. An orientation outside [0, 1) is the same J with beta wrapped by a quarter
 * turn and lambda1, lambda2 exchanged: V(b + pi/2) diag(l2, l1) V(b + pi/2)^T =
 * V(b) diag(l1, l2) V(b)^T, so the probe neighbours its orientation on either side. */
static void probe_squeeze(triangle_search *s, const double start[TRIOPT_DIM], int axis, double beta, squeeze *best)
{
    double from[TRIOPT_DIM];
    memcpy(from, start, sizeof from);
    if (beta < 0.0 || beta >= 1.0) {
        beta -= floor(beta);
        axis = 3 - axis;
        from[1] = start[2];
        from[2] = start[1];
    }
    double x[TRIOPT_DIM];
    memcpy(x, from, sizeof x);
    x[3] = beta;
    x[axis] = 0.6 * from[axis];
    double f = search_objective_below(s, x, best->f);
    if (f < best->f) {
        memcpy(best->start, from, sizeof best->start);
        best->axis = axis;
        best->beta = beta;
        best->f = f;
    }
}

/* Both axes at orientation beta. */
static void probe_both_axes(triangle_search *s, const double start[TRIOPT_DIM], double beta, squeeze *best)
{
    for (int axis = 1; axis <= 2 && s->status == TEXOPT_OK; axis++)
        probe_squeeze(s, start, axis, beta, best);
}

/* Where to squeeze an isotropic start (lambda1 = lambda2): both axes at every other of the
 * `directions` orientations, then the two orientations next to the best probe (coarse to
 * fine: directions + 2 probes for the resolution of 2 x directions). */
static void probe_every_orientation(triangle_search *s, const double start[TRIOPT_DIM], int directions, squeeze *best)
{
    int step = directions >= 4 && directions % 2 == 0 ? 2 : 1;
    for (int k = 0; k < directions && s->status == TEXOPT_OK; k += step)
        probe_both_axes(s, start, (double)k / directions, best);
    if (step == 1 || best->axis == 0)
        return;
    squeeze coarse = *best;
    for (int side = -1; side <= 1 && s->status == TEXOPT_OK; side += 2)
        probe_squeeze(s, coarse.start, coarse.axis, coarse.beta + (double)side / directions, best);
}

/* Anisotropic refinement of the best point so far: probes squeezing lambda1 or lambda2 to
 * 0.6 of its unit coordinate at orientations beta = k pi / (2 directions) (2: the texel
 * axes and diagonals, where paper Fig. 7 puts grid-aligned detail; more: edges at any
 * angle); the best probe that improves f is refined by a golden-section search of the
 * squeezed coordinate over [0, its start] with `golden_steps` points. The first refinement
 * probes every orientation (coarse to fine); a later one starts from an anisotropic point
 * whose orientation already fits the texture, so it probes only that orientation and its
 * two neighbours (6 probes instead of 2 x directions: BENCHMARKS.md@9f788a8, "Stage 1"). */
static void anisotropic_search(triangle_search *s, int directions, int golden_steps, int first)
{
    if (!isfinite(s->best_f) || golden_steps < 2)
        return;
    double start[TRIOPT_DIM];
    memcpy(start, s->best_x, sizeof start);
    squeeze best = {.axis = 0, .f = s->best_f};
    if (first) {
        probe_every_orientation(s, start, directions, &best);
    } else {
        probe_both_axes(s, start, start[3], &best);
        for (int side = -1; side <= 1 && s->status == TEXOPT_OK; side += 2)
            probe_both_axes(s, start, start[3] + (double)side / directions, &best);
    }
    if (best.axis == 0)
        return;
    double x[TRIOPT_DIM];
    memcpy(x, best.start, sizeof x);
    x[3] = best.beta;
    golden_section(s, x, 1u << best.axis, 0.0, best.start[best.axis], golden_steps);
}

/* The paper's plan: J = I (E = 0, always feasible), the Latin-hypercube design, then
 * `iterations` model-guided evaluations. */
static texopt_status plain_bayesian_optimisation(worker *w, triangle_search *s, uint32_t t, char *err, size_t err_len)
{
    const resolved_options *opt = &w->sh->opt;
    static const double identity[TRIOPT_DIM] = {0, 1, 1, 0};
    texopt_bo_options bo = {.iterations = opt->iterations,
                            .initial_design = opt->initial_design,
                            .initial_points = identity,
                            .initial_point_count = 1,
                            .seed = mix_seed(opt->seed, t, 1)};
    return texopt_bo_minimize(w->bo, &bo, search_objective, s, NULL, NULL, NULL, err, err_len);
}

/* Bayesian optimisation after the searches: its surrogate starts from every point they
 * evaluated (no new design: they already cover the region that matters), and it stops when
 * polish_patience evaluations in a row lower the best f by less than polish_stop of it, so
 * `iterations` is a budget spent only while it pays. Also stops at the objective's lower
 * bound. */
static texopt_status polish(worker *w, triangle_search *s, uint32_t t, double lower_bound, char *err, size_t err_len)
{
    const resolved_options *opt = &w->sh->opt;
    int known = s->history_count;
    double x[TRIOPT_HISTORY * TRIOPT_DIM], f[TRIOPT_HISTORY];
    memcpy(x, s->history_x, (size_t)known * TRIOPT_DIM * sizeof *x);
    memcpy(f, s->history_f, (size_t)known * sizeof *f);
    texopt_bo_options bo = {.iterations = opt->iterations,
                            .initial_design = opt->initial_design > 0 ? opt->initial_design : -1,
                            .initial_points = x,
                            .initial_values = f,
                            .initial_point_count = known,
                            .stall_tolerance = opt->polish_stop > 0 ? opt->polish_stop : 0.0,
                            .stall_patience = opt->polish_stop > 0 ? opt->polish_patience : 0,
                            .seed = mix_seed(opt->seed, t, 1),
                            .has_target = opt->lower_bound_stop,
                            .target = lower_bound};
    return texopt_bo_minimize(w->bo, &bo, search_objective, s, NULL, NULL, NULL, err, err_len);
}

static void store_optimum(const triangle_search *s, double lambda_min, texopt_triangle_target *o)
{
    double p[4];
    params_from_unit(s->best_x, lambda_min, p);
    o->alpha = wrap_quarter(p[0]);
    o->lambda1 = p[1];
    o->lambda2 = p[2];
    o->beta = wrap_quarter(p[3]);
    o->loss = s->best_loss;
    o->w_rotation = o->w_stretch = 0.0;
    o->evaluations = s->evaluations;
}

static texopt_status optimise_triangle(worker *w, uint32_t t, texopt_triangle_target *o, char *err, size_t err_len)
{
    const stage_shared *sh = w->sh;
    const resolved_options *opt = &sh->opt;
    texopt_status st = texopt_triloss_prepare(w->loss, t, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    w->close_up_triangles += texopt_triloss_close_up_count(w->loss) > 0;
    triangle_search s = {.loss = w->loss,
                         .epsilon = opt->epsilon,
                         .cut_loss = opt->epsilon,
                         .lambda_min = opt->lambda_min,
                         .area = fabs(sh->mesh->area_texel[t]),
                         .best_f = INFINITY,
                         .status = TEXOPT_OK};
    double lm = opt->lambda_min;
    double lower_bound = objective_value(lm * lm, s.area, 0.0, opt->epsilon) + TRIOPT_BOUND_TOLERANCE;
    int flat = 0;
    if (!opt->plain) {
        flat = flat_at_smallest_area(&s, lower_bound);
        if (!flat && opt->isotropic_steps > 0)
            isotropic_search(&s, opt->isotropic_steps);
        /* Detail across every axis may forbid all isotropic shrinks; the anisotropic
         * refinement then starts from J = I (E = 0, always feasible). */
        if (!flat && !isfinite(s.best_f) && s.status == TEXOPT_OK) {
            static const double identity[TRIOPT_DIM] = {0, 1, 1, 0};
            search_objective(&s, identity);
        }
        for (int pass = 0; !flat && pass < opt->anisotropic_passes && s.status == TEXOPT_OK; pass++) {
            double before = s.best_f;
            anisotropic_search(&s, opt->anisotropic_directions, opt->anisotropic_steps, pass == 0);
            if (!(s.best_f < before))
                break;
        }
    }
    if (!flat && s.status == TEXOPT_OK && opt->iterations > 0)
        st = opt->plain ? plain_bayesian_optimisation(w, &s, t, err, err_len)
                        : polish(w, &s, t, lower_bound, err, err_len);
    if (st == TEXOPT_OK && s.status != TEXOPT_OK) {
        snprintf(err, err_len, "%s", s.err);
        st = s.status;
    }
    if (st == TEXOPT_OK && !isfinite(s.best_f))
        st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL,
                         "triopt: triangle %u has no feasible sample although J = I is", t);
    if (st != TEXOPT_OK)
        return st;
    store_optimum(&s, lm, o);
    if (flat)
        return TEXOPT_OK;
    if (!opt->paper_window)
        texopt_triloss_keep_deciding(w->loss);
    return sensitivity_weights(w, t, o, err, err_len);
}

static int triangle_selected(const stage_shared *sh, size_t t)
{
    if (sh->mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV))
        return 0;
    return t % sh->opt.stride == 0;
}

static void identity_target(texopt_triangle_target *o)
{
    memset(o, 0, sizeof *o);
    o->lambda1 = o->lambda2 = 1.0;
}

static void record_failure(stage_shared *sh, size_t t, texopt_status st, const char *msg)
{
    pthread_mutex_lock(&sh->lock);
    /* Keep the failure of the lowest triangle index: the same message whatever the schedule
     * (among the triangles that ran). */
    if (sh->status == TEXOPT_OK || t < sh->failed_triangle) {
        sh->status = st;
        sh->failed_triangle = t;
        snprintf(sh->err, sizeof sh->err, "triangle %zu: %s", t, msg);
    }
    pthread_mutex_unlock(&sh->lock);
    atomic_store(&sh->stop, 1);
}

static void record_done(stage_shared *sh, const texopt_triangle_target *o)
{
    pthread_mutex_lock(&sh->lock);
    sh->done++;
    sh->sum_loss += o->loss;
    sh->sum_area_scale += o->lambda1 * o->lambda2;
    if (sh->monitor && (sh->done % sh->report_every == 0 || sh->done == sh->total)) {
        double fraction = (double)sh->done / (double)sh->total;
        double elapsed = now_seconds() - sh->start_seconds;
        texopt_progress p = {.stage = "stage1",
                             .stage_fraction = fraction,
                             .fraction = fraction,
                             .mean_loss = sh->sum_loss / (double)sh->done,
                             .mean_area_scale = sh->sum_area_scale / (double)sh->done,
                             .eta_seconds = elapsed * (1.0 - fraction) / fraction};
        texopt_monitor_report(sh->monitor, &p);
    }
    pthread_mutex_unlock(&sh->lock);
}

static double thread_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *worker_main(void *arg)
{
    worker *w = arg;
    stage_shared *sh = w->sh;
    char err[TRIOPT_ERR_LEN];
    double cpu_start = thread_cpu_seconds();
    for (;;) {
        if (atomic_load(&sh->stop))
            break;
        if (texopt_monitor_canceled(sh->monitor)) {
            record_failure(sh, 0, TEXOPT_E_CANCELED, "stage 1 canceled");
            break;
        }
        size_t t = atomic_fetch_add(&sh->next, 1);
        if (t >= sh->mesh->triangle_count)
            break;
        texopt_triangle_target *o = &sh->out[t];
        identity_target(o);
        if (!triangle_selected(sh, t))
            continue;
        err[0] = '\0';
        texopt_status st = optimise_triangle(w, (uint32_t)t, o, err, sizeof err);
        if (st != TEXOPT_OK) {
            record_failure(sh, t, st, err);
            break;
        }
        record_done(sh, o);
    }
    double cpu = thread_cpu_seconds() - cpu_start;
    pthread_mutex_lock(&sh->lock);
    sh->cpu_seconds += cpu;
    sh->close_up_triangles += w->close_up_triangles;
    pthread_mutex_unlock(&sh->lock);
    return NULL;
}

static texopt_status resolve_options(const texopt_triopt_options *in, const texopt_mesh *mesh, resolved_options *o,
                                     char *err, size_t err_len)
{
    texopt_triopt_options d = {0};
    if (!in)
        in = &d;
    o->epsilon = in->epsilon != 0.0 ? in->epsilon : 0.01;
    o->iterations = in->iterations != 0 ? in->iterations : 100;
    o->lambda_min = in->lambda_min != 0.0 ? in->lambda_min : 0.1;
    o->viewport = in->viewport != 0 ? in->viewport : 64;
    o->weight_samples = in->weight_samples != 0 ? in->weight_samples : 4;
    o->initial_design = in->initial_design;
    o->lower_bound_stop = !in->no_lower_bound_stop && !in->plain;
    o->plain = in->plain != 0;
    o->paper_window = in->paper_window != 0;
    o->isotropic_steps = in->isotropic_steps != 0 ? in->isotropic_steps : 8;
    if (o->isotropic_steps == 1)
        o->isotropic_steps = 2;
    o->anisotropic_steps = in->anisotropic_steps != 0 ? in->anisotropic_steps : 8;
    o->anisotropic_directions = in->anisotropic_directions > 0 ? in->anisotropic_directions : 8;
    if (o->anisotropic_directions > 32)
        o->anisotropic_directions = 32;
    o->anisotropic_passes = in->anisotropic_passes != 0 ? in->anisotropic_passes : 3;
    if (o->anisotropic_steps < 0 || o->anisotropic_passes < 0)
        o->anisotropic_steps = o->anisotropic_passes = 0;
    o->polish_stop = in->polish_stop != 0.0 ? in->polish_stop : TRIOPT_POLISH_STOP;
    o->polish_patience = in->polish_patience > 0 ? in->polish_patience : TRIOPT_POLISH_PATIENCE;
    o->stride = in->stride > 1 ? in->stride : 1;
    o->seed = in->seed;
    o->signal_weights = in->signal_weights;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    o->threads = in->threads > 0 ? in->threads : (cores > 0 ? (int)cores : 1);
    if (!(o->epsilon > 0.0 && o->epsilon <= 1.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triopt: epsilon %g outside (0, 1]", o->epsilon);
    if (o->iterations < -1 || o->iterations > 10000 || (o->iterations < 0 && o->plain))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "triopt: iterations %d outside [-1, 10000] (-1 only without plain)", o->iterations);
    if (!(o->lambda_min > 0.0 && o->lambda_min < 1.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triopt: lambda_min %g outside (0, 1)",
                           o->lambda_min);
    if (o->viewport < 8 || o->viewport > 1024)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triopt: viewport %d outside [8, 1024]",
                           o->viewport);
    if (o->weight_samples > 64)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triopt: weight_samples %d above 64",
                           o->weight_samples);
    if (o->threads > 256)
        o->threads = 256;
    if ((size_t)o->threads > mesh->triangle_count)
        o->threads = mesh->triangle_count > 0 ? (int)mesh->triangle_count : 1;
    int design = o->initial_design > 0 ? o->initial_design : (o->initial_design < 0 ? 0 : 2 * TRIOPT_DIM + 2);
    o->max_evaluations = TRIOPT_HISTORY + design + (o->iterations > 0 ? o->iterations : 0);
    return TEXOPT_OK;
}

static void destroy_workers(worker *workers, int count)
{
    if (!workers)
        return;
    for (int i = 0; i < count; i++) {
        texopt_triloss_destroy(workers[i].loss);
        texopt_bo_destroy(workers[i].bo);
    }
    free(workers);
}

static texopt_status create_workers(stage_shared *sh, worker **out, char *err, size_t err_len)
{
    int n = sh->opt.threads;
    worker *workers = calloc((size_t)n, sizeof *workers);
    if (!workers)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triopt: no memory for %d workers", n);
    for (int i = 0; i < n; i++) {
        workers[i].sh = sh;
        texopt_status st = texopt_triloss_create(&workers[i].loss, sh->model, sh->mesh, sh->opt.viewport, err, err_len);
        if (st == TEXOPT_OK) {
            texopt_triloss_weigh_signals(workers[i].loss, sh->opt.signal_weights);
            if (sh->opt.paper_window)
                texopt_triloss_use_paper_window(workers[i].loss);
            workers[i].bo = texopt_bo_create(TRIOPT_DIM, sh->opt.max_evaluations);
            if (!workers[i].bo)
                st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triopt: no memory for the optimiser");
        }
        if (st != TEXOPT_OK) {
            destroy_workers(workers, n);
            return st;
        }
    }
    *out = workers;
    return TEXOPT_OK;
}

/* Means over the optimised triangles in index order, so they do not depend on the schedule. */
static void fill_report(const stage_shared *sh, texopt_triopt_report *report)
{
    memset(report, 0, sizeof *report);
    for (size_t t = 0; t < sh->mesh->triangle_count; t++) {
        const texopt_triangle_target *o = &sh->out[t];
        if (!triangle_selected(sh, t)) {
            report->skipped++;
            continue;
        }
        report->optimised++;
        report->evaluations += o->evaluations;
        report->mean_loss += o->loss;
        report->mean_area_scale += o->lambda1 * o->lambda2;
        report->mean_objective +=
            objective_value(o->lambda1 * o->lambda2, fabs(sh->mesh->area_texel[t]), o->loss, sh->opt.epsilon);
    }
    if (report->optimised > 0) {
        report->mean_loss /= (double)report->optimised;
        report->mean_area_scale /= (double)report->optimised;
        report->mean_objective /= (double)report->optimised;
    }
    report->seconds = now_seconds() - sh->start_seconds;
    report->cpu_seconds = sh->cpu_seconds;
    report->close_up_triangles = sh->close_up_triangles;
}

static size_t count_selected(const stage_shared *sh)
{
    size_t n = 0;
    for (size_t t = 0; t < sh->mesh->triangle_count; t++)
        n += triangle_selected(sh, t) != 0;
    return n;
}

texopt_status texopt_triopt_run(const texopt_model *model, const texopt_mesh *mesh, const texopt_triopt_options *opt,
                                texopt_triangle_target *out, texopt_triopt_report *report,
                                const texopt_monitor *monitor, char *err, size_t err_len)
{
    if (!model || !mesh || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "triopt: NULL model, mesh or output");
    stage_shared *sh = calloc(1, sizeof *sh);
    if (!sh)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "triopt: out of memory");
    texopt_status st = resolve_options(opt, mesh, &sh->opt, err, err_len);
    if (st != TEXOPT_OK) {
        free(sh);
        return st;
    }
    sh->model = model;
    sh->mesh = mesh;
    sh->out = out;
    sh->monitor = monitor;
    sh->start_seconds = now_seconds();
    sh->total = count_selected(sh);
    sh->report_every = sh->total / 200 > 0 ? sh->total / 200 : 1;
    atomic_init(&sh->next, 0);
    atomic_init(&sh->stop, 0);
    pthread_mutex_init(&sh->lock, NULL);

    worker *workers = NULL;
    st = create_workers(sh, &workers, err, err_len);
    if (st == TEXOPT_OK) {
        texopt_parallel_run(worker_main, workers, sizeof *workers, sh->opt.threads);
        st = sh->status;
        if (st != TEXOPT_OK)
            texopt_fail(err, err_len, st, "triopt: %s", sh->err);
        else if (report)
            fill_report(sh, report);
    }
    destroy_workers(workers, sh->opt.threads);
    pthread_mutex_destroy(&sh->lock);
    free(sh);
    return st;
}
