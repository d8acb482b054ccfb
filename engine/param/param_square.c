/* param_square.c - boundary-to-square mapping, the stretch-minimising interior map of one
 * candidate corner, and the three searches over candidates (param_square.h). */
#include "param_square.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "param_tutte.h"
#include "rng.h"

void texopt_square_params_default(texopt_square_params *params)
{
    *params = (texopt_square_params){
        .search = TEXOPT_SQUARE_STEP_SAMPLING,
        .step = 0,
        .particles = 4,
        .max_iterations = 20,
        .stall_iterations = 4,
        /* Pedersen's "good parameters" range for small swarms (the paper's [Eri10a]). */
        .inertia = 0.7,
        .local_pull = 1.5,
        .global_pull = 1.5,
        .seed = 1,
        .stretch_rounds = 5,
    };
}

typedef struct square_search {
    const texopt_param_chart *chart;
    const texopt_param_boundary *b;
    const texopt_square_params *params;
    size_t m;
    double *stretch; /* per candidate; NAN = not evaluated */
    double *uv, *trial, *divisor, *vertex_stretch;
    size_t *chord; /* 2 per chord: loop indices of an interior edge's two boundary ends */
    size_t chord_count;
    double best;
    size_t best_corner, evaluations;
} square_search;

/* Arc length along the loop from index `from` to index `to` (to >= from, may pass n). */
static double arc_between(const texopt_param_boundary *b, size_t from, size_t to)
{
    size_t n = b->count;
    double length = b->arc[n];
    return b->arc[to % n] + (double)(to / n) * length - b->arc[from % n] - (double)(from / n) * length;
}

/* Loop offsets (from `start`) of the four corners: each side ends at the vertex whose arc
 * from the previous corner is nearest to a quarter, leaving every side at least one edge. */
static void find_corners(const texopt_param_boundary *b, size_t start, size_t corner[5])
{
    size_t n = b->count;
    double quarter = 0.25 * b->arc[n];
    corner[0] = start;
    for (int s = 1; s < 4; s++) {
        size_t best = corner[s - 1] + 1, last = start + n - (size_t)(4 - s);
        for (size_t k = corner[s - 1] + 1; k <= last; k++) {
            if (fabs(arc_between(b, corner[s - 1], k) - quarter) < fabs(arc_between(b, corner[s - 1], best) - quarter))
                best = k;
            if (arc_between(b, corner[s - 1], k) > quarter)
                break;
        }
        corner[s] = best;
    }
    corner[4] = start + n;
}

/* The chords: interior edges with both ends on the boundary (an ear's base, a bridge across
 * a narrow part). 0, or -1 on no memory. */
static int find_chords(square_search *s)
{
    const texopt_param_chart *c = s->chart;
    size_t n = s->b->count, *loop = malloc((c->vertex_count ? c->vertex_count : 1) * sizeof *loop);
    s->chord = malloc((6 * c->triangle_count + 1) * sizeof *s->chord);
    if (!loop || !s->chord) {
        free(loop);
        return -1;
    }
    for (size_t k = 0; k < n; k++)
        loop[s->b->vertex[k]] = k;
    for (size_t t = 0; t < c->triangle_count; t++)
        for (int e = 0; e < 3; e++) {
            uint32_t u = c->triangle[3 * t + (size_t)e], v = c->triangle[3 * t + (size_t)(e + 1) % 3];
            if (!s->b->on_boundary[u] || !s->b->on_boundary[v])
                continue;
            size_t i = loop[u], j = loop[v];
            if ((i + 1) % n == j || (j + 1) % n == i)
                continue; /* a boundary edge */
            s->chord[2 * s->chord_count] = i;
            s->chord[2 * s->chord_count++ + 1] = j;
        }
    free(loop);
    return 0;
}

/* Whether the boundary mapping starting at `start` puts both ends of a chord on one side of
 * the square. Floater (2003): a convex-combination map onto a convex boundary is one-to-one
 * unless an interior edge joins two points of one straight side; that edge's triangles go
 * flat. Such candidates are not evaluated. (The paper assumes charts without such edges;
 * region-grown charts have many.) */
static int flattens_a_chord(const square_search *s, size_t start)
{
    size_t n = s->b->count, corner[5];
    find_corners(s->b, start, corner);
    for (size_t k = 0; k < s->chord_count; k++) {
        size_t a = (s->chord[2 * k] + n - start) % n, b = (s->chord[2 * k + 1] + n - start) % n;
        for (int side = 0; side < 4; side++) {
            size_t lo = corner[side] - start, hi = corner[side + 1] - start;
            int in_a = (a >= lo && a <= hi) || (a == 0 && hi == n), in_b = (b >= lo && b <= hi) || (b == 0 && hi == n);
            if (in_a && in_b)
                return 1;
        }
    }
    return 0;
}

static void boundary_to_square(const texopt_param_boundary *b, size_t start, double *uv)
{
    static const double square[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
    size_t corner[5];
    find_corners(b, start, corner);
    for (int s = 0; s < 4; s++) {
        double side = arc_between(b, corner[s], corner[s + 1]);
        for (size_t k = corner[s]; k < corner[s + 1]; k++) {
            double t = arc_between(b, corner[s], k) / side;
            uint32_t v = b->vertex[k % b->count];
            uv[2 * (size_t)v] = square[s][0] + t * (square[s + 1][0] - square[s][0]);
            uv[2 * (size_t)v + 1] = square[s][1] + t * (square[s + 1][1] - square[s][1]);
        }
    }
}

/* One candidate: boundary at `start`, then Yoshizawa rounds; keeps the lowest-stretch map
 * in s->uv and returns its L2 stretch (+inf when no round gave a valid map). */
static texopt_status evaluate(square_search *s, size_t start, double *out_stretch, char *err, size_t err_len)
{
    const texopt_param_chart *c = s->chart;
    size_t nv = c->vertex_count;
    double *trial = s->trial;
    double best = INFINITY;
    boundary_to_square(s->b, start, trial);
    for (size_t v = 0; v < nv; v++)
        s->divisor[v] = 1.0;
    for (int round = 0; round <= s->params->stretch_rounds; round++) {
        texopt_status st = texopt_param_embed_interior(c, s->b, s->divisor, trial, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        double l2 = INFINITY, linf;
        if (texopt_param_stretch(c, trial, &l2, &linf, s->vertex_stretch) != 0 || !(l2 < best))
            break; /* the paper's method stops when the stretch stops falling */
        best = l2;
        memcpy(s->uv, trial, 2 * nv * sizeof *trial);
        for (size_t v = 0; v < nv; v++)
            s->divisor[v] *= s->vertex_stretch[v];
    }
    *out_stretch = best;
    return TEXOPT_OK;
}

/* Evaluates candidate k once (later calls read the cache) and tracks the best. */
static texopt_status try_candidate(square_search *s, size_t k, double *keep_uv, char *err, size_t err_len)
{
    if (!isnan(s->stretch[k]))
        return TEXOPT_OK;
    texopt_status st = evaluate(s, k, &s->stretch[k], err, err_len);
    if (st != TEXOPT_OK)
        return st;
    s->evaluations++;
    if (s->stretch[k] < s->best) {
        s->best = s->stretch[k];
        s->best_corner = k;
        memcpy(keep_uv, s->uv, 2 * s->chart->vertex_count * sizeof *keep_uv);
    }
    return TEXOPT_OK;
}

static texopt_status brute_force(square_search *s, double *keep, char *err, size_t err_len)
{
    texopt_status st = TEXOPT_OK;
    for (size_t k = 0; k < s->m && st == TEXOPT_OK; k++)
        st = try_candidate(s, k, keep, err, err_len);
    return st;
}

static size_t paper_step(const square_search *s)
{
    double step = sqrt((double)s->chart->vertex_count * (double)s->m / (double)s->chart->triangle_count);
    return step < 2.0 ? 2 : (size_t)lround(step);
}

static texopt_status step_sampling(square_search *s, double *keep, char *err, size_t err_len)
{
    size_t step = s->params->step > 0 ? (size_t)s->params->step : paper_step(s);
    texopt_status st = TEXOPT_OK;
    for (size_t k = 0; k < s->m && st == TEXOPT_OK; k += step)
        st = try_candidate(s, k, keep, err, err_len);
    /* Deep check: the unchecked candidates on both sides of the best sample. */
    size_t centre = s->best_corner;
    for (size_t k = centre + 1; k < s->m && isnan(s->stretch[k]) && st == TEXOPT_OK; k++)
        st = try_candidate(s, k, keep, err, err_len);
    for (size_t k = centre; k-- > 0 && isnan(s->stretch[k]) && st == TEXOPT_OK;)
        st = try_candidate(s, k, keep, err, err_len);
    return st;
}

/* The candidate whose arc from the loop's start is nearest to x. */
static size_t nearest_candidate(const square_search *s, double x)
{
    size_t best = 0;
    for (size_t k = 1; k < s->m; k++)
        if (fabs(s->b->arc[k] - x) < fabs(s->b->arc[best] - x))
            best = k;
    return best;
}

static texopt_status particle_swarm(square_search *s, double *keep, char *err, size_t err_len)
{
    const texopt_square_params *p = s->params;
    size_t n = (size_t)p->particles;
    double range = s->b->arc[s->m - 1];
    double *x = malloc(3 * n * sizeof *x);
    if (!x)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "square: out of memory");
    double *vel = x + n, *local = x + 2 * n;
    texopt_rng rng;
    texopt_rng_seed(&rng, p->seed);
    for (size_t i = 0; i < n; i++) {
        x[i] = local[i] = range * texopt_rng_uniform(&rng);
        vel[i] = 0.0;
    }
    texopt_status st = TEXOPT_OK;
    int stall = 0;
    for (int it = 0; it < p->max_iterations && stall < p->stall_iterations && st == TEXOPT_OK; it++) {
        double before = s->best;
        for (size_t i = 0; i < n && st == TEXOPT_OK; i++) {
            size_t k = nearest_candidate(s, x[i]);
            st = try_candidate(s, k, keep, err, err_len);
            if (st == TEXOPT_OK && s->stretch[k] <= s->stretch[nearest_candidate(s, local[i])])
                local[i] = x[i];
        }
        double global = s->b->arc[s->best_corner];
        for (size_t i = 0; i < n; i++) {
            double r1 = texopt_rng_uniform(&rng), r2 = texopt_rng_uniform(&rng);
            vel[i] =
                p->inertia * vel[i] + p->local_pull * r1 * (local[i] - x[i]) + p->global_pull * r2 * (global - x[i]);
            x[i] = fmin(range, fmax(0.0, x[i] + vel[i]));
        }
        stall = s->best < before ? 0 : stall + 1;
    }
    free(x);
    return st;
}

static texopt_status check_params(const texopt_square_params *p, char *err, size_t err_len)
{
    if (!p || p->search < TEXOPT_SQUARE_BRUTE_FORCE || p->search > TEXOPT_SQUARE_PSO || p->step < 0 ||
        p->particles < 1 || p->max_iterations < 1 || p->stall_iterations < 1 || p->stretch_rounds < 0 ||
        p->stretch_rounds > 100 || !isfinite(p->inertia) || !isfinite(p->local_pull) || !isfinite(p->global_pull))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "square: parameters out of range");
    return TEXOPT_OK;
}

static texopt_status run_search(square_search *s, double *uv, char *err, size_t err_len)
{
    switch (s->params->search) {
    case TEXOPT_SQUARE_BRUTE_FORCE: return brute_force(s, uv, err, err_len);
    case TEXOPT_SQUARE_STEP_SAMPLING: return step_sampling(s, uv, err, err_len);
    case TEXOPT_SQUARE_PSO: return particle_swarm(s, uv, err, err_len);
    }
    return TEXOPT_E_INTERNAL;
}

static size_t count_candidates(const texopt_param_boundary *b)
{
    /* Half-open [0, d/4), with a rounding margin so the vertex at d/4 belongs to the next side. */
    size_t m = 0;
    while (m < b->count && b->arc[m] < (0.25 - 1e-9) * b->arc[b->count])
        m++;
    return m;
}

texopt_status texopt_param_square(const texopt_param_chart *chart, const texopt_square_params *params, double *uv,
                                  texopt_square_report *report, char *err, size_t err_len)
{
    texopt_status st = check_params(params, err, err_len);
    if (st == TEXOPT_OK && !uv)
        st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "square: NULL output");
    texopt_param_boundary *b = NULL;
    if (st == TEXOPT_OK)
        st = texopt_param_boundary_create(&b, chart, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t boundary_count = b->count;
    if (boundary_count < 4) {
        texopt_param_boundary_destroy(b);
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "square: the boundary has %zu vertices; a square needs 4", boundary_count);
    }
    size_t nv = chart->vertex_count;
    square_search s = {.chart = chart, .b = b, .params = params, .m = count_candidates(b), .best = INFINITY};
    s.stretch = malloc(s.m * sizeof *s.stretch);
    s.uv = malloc(2 * nv * sizeof *s.uv);
    s.trial = malloc(2 * nv * sizeof *s.trial);
    s.divisor = malloc(nv * sizeof *s.divisor);
    s.vertex_stretch = malloc(nv * sizeof *s.vertex_stretch);
    if (!s.stretch || !s.uv || !s.trial || !s.divisor || !s.vertex_stretch || find_chords(&s) != 0)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "square: out of memory");
    size_t admissible = 0; /* candidates flattening no chord: the others count as infinite stretch */
    for (size_t k = 0; k < s.m && st == TEXOPT_OK; k++) {
        s.stretch[k] = flattens_a_chord(&s, k) ? INFINITY : NAN;
        admissible += isnan(s.stretch[k]);
    }
    if (st == TEXOPT_OK && admissible == 0)
        st = texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED,
                         "square: every corner placement puts both ends of an interior edge on one side, "
                         "which would flatten its triangles");
    if (st == TEXOPT_OK)
        st = run_search(&s, uv, err, err_len);
    if (st == TEXOPT_OK && !isfinite(s.best)) /* the search sampled only flattening candidates */
        st = brute_force(&s, uv, err, err_len);
    if (st == TEXOPT_OK && !isfinite(s.best))
        st = texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "square: no boundary mapping gave a valid layout");
    if (st == TEXOPT_OK && report) {
        *report = (texopt_square_report){.candidates = s.m, .evaluations = s.evaluations, .corner = s.best_corner};
        texopt_param_stretch(chart, uv, &report->l2_stretch, &report->linf_stretch, NULL);
    }
    free(s.stretch);
    free(s.uv);
    free(s.trial);
    free(s.divisor);
    free(s.vertex_stretch);
    free(s.chord);
    texopt_param_boundary_destroy(b);
    return st;
}
