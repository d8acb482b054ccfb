/* distortion_reduce.c - Algorithm 2 of Liu et al. 2019 on stage 2 and a fixed scaffold box;
 * see distortion_reduce.h. */
#include "distortion_reduce.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gap_layer.h"
#include "meshwise.h"
#include "scaffold.h"
#include "target.h"
#include "vec2.h"

#define HALF_PI 1.57079632679489661923
#define DEFAULT_ROUNDS 30
#define DEFAULT_ROUND_ITERATIONS 20
#define REMESH_ITERATIONS 10

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* J (row-major 2x2) of the affine map taking triangle v of layout `from` to layout `to`;
 * 0 when `from`'s triangle is degenerate. */
static int triangle_jacobian(const uint32_t *v, const double *from, const double *to, double J[4])
{
    const double *a = from + 2 * (size_t)v[0], *b = from + 2 * (size_t)v[1], *c = from + 2 * (size_t)v[2];
    if (texopt_texel_triangle_degenerate(a, b, c))
        return 0;
    double e1x = b[0] - a[0], e1y = b[1] - a[1], e2x = c[0] - a[0], e2y = c[1] - a[1];
    double det = e1x * e2y - e2x * e1y;
    double inv[4] = {e2y / det, -e2x / det, -e1y / det, e1x / det};
    const double *p = to + 2 * (size_t)v[0], *q = to + 2 * (size_t)v[1], *r = to + 2 * (size_t)v[2];
    double d[4] = {q[0] - p[0], r[0] - p[0], q[1] - p[1], r[1] - p[1]};
    J[0] = d[0] * inv[0] + d[1] * inv[2];
    J[1] = d[0] * inv[1] + d[1] * inv[3];
    J[2] = d[2] * inv[0] + d[3] * inv[2];
    J[3] = d[2] * inv[1] + d[3] * inv[3];
    return 1;
}

double texopt_distortion_relative(const texopt_mesh *mesh, const double *reference, const double *x)
{
    double sum = 0.0, area = 0.0, area_x = 0.0, J[4];
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        if (!triangle_jacobian(v, reference, x, J))
            continue;
        double f = J[0] * J[0] + J[1] * J[1] + J[2] * J[2] + J[3] * J[3], g = J[0] * J[3] - J[1] * J[2];
        if (!(g > 0.0))
            return INFINITY;
        double a = fabs(texopt_signed_area(reference + 2 * (size_t)v[0], reference + 2 * (size_t)v[1],
                                           reference + 2 * (size_t)v[2]));
        sum += a * 0.25 * f; /* the part that grows with the scale ... */
        area_x += a * g;
        area += a;
    }
    double k2 = area > 0.0 ? area_x / area : 1.0; /* the reference scaled by k to x's area */
    if (!(area > 0.0 && k2 > 0.0))
        return 1.0;
    double shrinking = 0.0; /* ... and the part that shrinks with it */
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        if (!triangle_jacobian(v, reference, x, J))
            continue;
        double f = J[0] * J[0] + J[1] * J[1] + J[2] * J[2] + J[3] * J[3], g = J[0] * J[3] - J[1] * J[2];
        double a = fabs(texopt_signed_area(reference + 2 * (size_t)v[0], reference + 2 * (size_t)v[1],
                                           reference + 2 * (size_t)v[2]));
        shrinking += a * 0.25 * f / (g * g);
    }
    return (sum / k2 + shrinking * k2) / area;
}

/* Per triangle, the Jacobian of the reference relative to the input texels as a stage-2
 * target: its polar rotation and stretch, w_stretch 1, w_rotation 0 (the symmetric
 * Dirichlet energy is blind to rotations). */
static void reference_targets(const texopt_mesh *mesh, const double *reference, texopt_triangle_target *targets)
{
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        texopt_triangle_target *g = &targets[t];
        memset(g, 0, sizeof *g);
        g->lambda1 = g->lambda2 = 1.0;
        double J[4];
        if (!triangle_jacobian(mesh->triangle + 3 * t, mesh->texel, reference, J) || !(J[0] * J[3] - J[1] * J[2] > 0))
            continue; /* J = I, no weight, as target.h gives degenerate triangles */
        double angle = atan2(J[2] - J[1], J[0] + J[3]), c = cos(angle), s = sin(angle);
        double S[4] = {c * J[0] + s * J[2], c * J[1] + s * J[3], -s * J[0] + c * J[2], -s * J[1] + c * J[3]};
        double m[3] = {S[0], 0.5 * (S[1] + S[2]), S[3]}, mu1, mu2, theta;
        texopt_sym2_eigen(m, &mu1, &mu2, &theta);
        texopt_target_set_stretch(g, theta, mu1, mu2);
        g->alpha = fmod(angle, HALF_PI);
        if (g->alpha < 0.0)
            g->alpha += HALF_PI;
        g->w_stretch = 1.0;
    }
}

/* Chart area over the bounding box's area of the layout x, of the charts not in unboxed. */
static double efficiency(const texopt_mesh *mesh, const double *x, const uint8_t *unboxed)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, area = 0.0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        if (unboxed[mesh->chart_of[t]])
            continue;
        area += fabs(texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]));
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], x[2 * (size_t)v[k] + a]);
                hi[a] = fmax(hi[a], x[2 * (size_t)v[k] + a]);
            }
    }
    double box = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    return box > 0.0 ? area / box : 0.0;
}

/* Algorithm 2's first line: sqrt of the smallest reference area over chart area, over the
 * charts not in unboxed. */
static double initial_scale(const texopt_mesh *mesh, const double *reference, const double *x, const uint8_t *unboxed)
{
    double *area = calloc(2 * (mesh->chart_count ? mesh->chart_count : 1), sizeof *area), s = INFINITY;
    if (!area)
        return 1.0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        area[2 * mesh->chart_of[t]] += fabs(texopt_signed_area(
            reference + 2 * (size_t)v[0], reference + 2 * (size_t)v[1], reference + 2 * (size_t)v[2]));
        area[2 * mesh->chart_of[t] + 1] +=
            fabs(texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]));
    }
    for (size_t c = 0; c < mesh->chart_count; c++)
        if (!unboxed[c] && area[2 * c] > 0.0 && area[2 * c + 1] > 0.0)
            s = fmin(s, area[2 * c] / area[2 * c + 1]);
    free(area);
    return isfinite(s) ? sqrt(s) : 1.0;
}

/* The bounding box of x's triangles of charts with unboxed[c] == boxed, grown by `factor`
 * about its centre, x0 y0 x1 y1. */
static void grown_box(const texopt_mesh *mesh, const double *x, const uint8_t *unboxed, int boxed, double factor,
                      double box[4])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t t = 0; t < 3 * mesh->triangle_count; t++)
        for (int a = 0; a < 2 && (unboxed[mesh->chart_of[t / 3]] == 0) == boxed; a++) {
            lo[a] = fmin(lo[a], x[2 * (size_t)mesh->triangle[t] + a]);
            hi[a] = fmax(hi[a], x[2 * (size_t)mesh->triangle[t] + a]);
        }
    for (int a = 0; a < 2; a++) {
        double centre = 0.5 * (lo[a] + hi[a]), half = 0.5 * factor * (hi[a] - lo[a]);
        box[a] = centre - half;
        box[a + 2] = centre + half;
    }
}

/* Per chart, 1 in unboxed when one box cannot hold it without overlap: a chart over itself
 * (scaffold.h) or of both orientations (a fold, mirrored halves); *count how many. */
static texopt_status find_unboxed(const texopt_mesh *mesh, const double *x, uint8_t *unboxed, size_t *count, char *err,
                                  size_t err_len)
{
    int8_t *sign = calloc(mesh->chart_count ? mesh->chart_count : 1, 1);
    texopt_status st = sign ? texopt_scaffold_overlapping_charts(mesh, x, unboxed, NULL, err, err_len)
                            : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "distortion reduction: no memory");
    for (size_t t = 0; st == TEXOPT_OK && t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        double a = texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]);
        int8_t s = a > 0.0 ? 1 : a < 0.0 ? -1 : 0, *cs = &sign[mesh->chart_of[t]];
        if (s != 0 && *cs != 0 && s != *cs)
            unboxed[mesh->chart_of[t]] = 1;
        if (*cs == 0)
            *cs = s;
    }
    *count = 0;
    for (size_t c = 0; st == TEXOPT_OK && c < mesh->chart_count; c++)
        *count += unboxed[c] != 0;
    free(sign);
    return st;
}

/* The charts in unboxed moved right of the box, a half box width clear of it. */
static void move_out_of_box(const texopt_mesh *mesh, const uint8_t *unboxed, const double box[4], double *x)
{
    double lo[4];
    grown_box(mesh, x, unboxed, 0, 1.0, lo);
    if (!isfinite(lo[0]))
        return;
    double dx = box[2] + 0.5 * (box[2] - box[0]) - lo[0];
    uint8_t *moved = calloc(mesh->vertex_count ? mesh->vertex_count : 1, 1);
    for (size_t k = 0; moved && k < 3 * mesh->triangle_count; k++) {
        uint32_t v = mesh->triangle[k];
        if (unboxed[mesh->chart_of[k / 3]] && !moved[v]) {
            moved[v] = 1;
            x[2 * (size_t)v] += dx;
        }
    }
    free(moved);
}

/* Algorithm 2 on mesh as it is (no gap layer); unboxed (chart_count bytes) gets the charts
 * left out of the box. */
static texopt_status reduce_in_box(const texopt_mesh *mesh, const double *reference, const double *start,
                                   const texopt_distortion_reduce_options *opt, double *out,
                                   texopt_distortion_reduce_report *report, uint8_t *unboxed,
                                   const texopt_monitor *monitor, char *err, size_t err_len)
{
    double t0 = now_seconds();
    texopt_distortion_reduce_options o = {0};
    if (opt)
        o = *opt;
    double delta = o.delta > 0 ? o.delta : TEXOPT_REDUCE_DELTA;
    double step = o.delta_step > 0 ? o.delta_step : TEXOPT_REDUCE_DELTA_STEP;
    double tolerance = o.tolerance > 0 ? o.tolerance : TEXOPT_REDUCE_TOLERANCE;
    int max_rounds = o.max_rounds > 0 ? o.max_rounds : DEFAULT_ROUNDS;
    size_t n = 2 * mesh->vertex_count, nt = mesh->triangle_count;
    texopt_distortion_reduce_report rep = {0};
    memcpy(out, start, n * sizeof *out);
    rep.distortion_start = rep.distortion = texopt_distortion_relative(mesh, reference, start);
    double *x = malloc((n ? n : 1) * sizeof *x), *next = malloc((n ? n : 1) * sizeof *next);
    texopt_triangle_target *targets = malloc((nt ? nt : 1) * sizeof *targets);
    texopt_status st =
        x && next && targets ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "distortion reduction: no memory");
    if (st == TEXOPT_OK)
        st = find_unboxed(mesh, start, unboxed, &rep.charts_unboxed, err, err_len);
    if (st == TEXOPT_OK && rep.charts_unboxed == mesh->chart_count)
        rep.refused = 1;
    if (st == TEXOPT_OK && !rep.refused) {
        rep.efficiency_start = rep.efficiency = efficiency(mesh, start, unboxed);
        rep.scale = initial_scale(mesh, reference, start, unboxed);
        for (size_t i = 0; i < n; i++)
            x[i] = rep.scale * start[i];
        grown_box(mesh, x, unboxed, 1, delta, rep.box);
        move_out_of_box(mesh, unboxed, rep.box, x);
        reference_targets(mesh, reference, targets);
    }
    texopt_meshwise_options mopt = {0};
    mopt.threads = o.threads;
    mopt.max_iterations = o.round_iterations > 0 ? o.round_iterations : DEFAULT_ROUND_ITERATIONS;
    double box[4];
    memcpy(box, rep.box, sizeof box);
    texopt_scaffold_options so = {1, box, unboxed, 0.0, REMESH_ITERATIONS};
    texopt_monitor quiet = {NULL, NULL, monitor ? monitor->cancel : NULL}; /* the caller's stage goes on */
    double previous = st == TEXOPT_OK ? texopt_distortion_relative(mesh, reference, x) : 0.0;
    for (int round = 0; st == TEXOPT_OK && !rep.refused && round < max_rounds; round++) {
        texopt_scaffold_report sr;
        st = texopt_scaffold_solve(mesh, targets, x, &mopt, &so, next, &sr, &quiet, err, err_len);
        /* Refused by stage 2: at the start, a reversed triangle; later, a re-mesh between
         * charts pressed together (a scaffold triangle without area), or a factorisation
         * failing on such slivers: the last round stays. */
        int stop = st == TEXOPT_E_INVALID_ARGUMENT || st == TEXOPT_E_NUMERIC;
        if (stop)
            st = TEXOPT_OK;
        if (st != TEXOPT_OK || stop || sr.charts_skipped > 0) {
            rep.refused |= round == 0;
            break;
        }
        double d = texopt_distortion_relative(mesh, reference, next), e = efficiency(mesh, next, unboxed);
        if (o.min_efficiency > 0 && e < o.min_efficiency && e < efficiency(mesh, x, unboxed))
            break;
        memcpy(x, next, n * sizeof *x);
        memcpy(rep.box, box, sizeof box);
        rep.rounds++;
        if (d - 1.0 <= tolerance || fabs(d - previous) < tolerance * previous)
            break;
        previous = d;
        double grow[2] = {0.5 * step * (box[2] - box[0]), 0.5 * step * (box[3] - box[1])};
        box[0] -= grow[0];
        box[1] -= grow[1];
        box[2] += grow[0];
        box[3] += grow[1];
    }
    if (st == TEXOPT_OK && !rep.refused) {
        memcpy(out, x, n * sizeof *out);
        rep.distortion = texopt_distortion_relative(mesh, reference, out);
        rep.efficiency = efficiency(mesh, out, unboxed);
    }
    if (st == TEXOPT_OK && rep.refused)
        grown_box(mesh, start, unboxed, 1, 1.0, rep.box);
    rep.seconds = now_seconds() - t0;
    if (st == TEXOPT_OK && report)
        *report = rep;
    free(x);
    free(next);
    free(targets);
    return st;
}

texopt_status texopt_distortion_reduce(const texopt_mesh *mesh, const double *reference, const double *start,
                                       const texopt_distortion_reduce_options *opt, double *out,
                                       texopt_distortion_reduce_report *report, const texopt_monitor *monitor,
                                       char *err, size_t err_len)
{
    uint8_t *unboxed = calloc(mesh->chart_count ? mesh->chart_count : 1, 1);
    if (!unboxed)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "distortion reduction: no memory");
    if (!opt || !(opt->gap_layer > 0)) {
        texopt_status st = reduce_in_box(mesh, reference, start, opt, out, report, unboxed, monitor, err, err_len);
        free(unboxed);
        return st;
    }
    texopt_gap_layer g;
    texopt_distortion_reduce_report rep = {0};
    texopt_status st = texopt_gap_layer_create(mesh, reference, start, opt->gap_layer, &g, err, err_len);
    double *layered =
        st == TEXOPT_OK ? malloc(2 * (g.mesh.vertex_count ? g.mesh.vertex_count : 1) * sizeof *layered) : NULL;
    if (st == TEXOPT_OK && !layered)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "distortion reduction: no memory");
    if (st == TEXOPT_OK)
        st = reduce_in_box(&g.mesh, g.reference, g.start, opt, layered, &rep, unboxed, monitor, err, err_len);
    if (st == TEXOPT_OK) { /* the layer dropped; the report of the charts alone */
        memcpy(out, layered, 2 * mesh->vertex_count * sizeof *out);
        rep.distortion_start = texopt_distortion_relative(mesh, reference, start);
        rep.distortion = texopt_distortion_relative(mesh, reference, out);
        rep.efficiency_start = efficiency(mesh, start, unboxed);
        rep.efficiency = efficiency(mesh, out, unboxed);
        rep.charts_without_gap = g.charts_without;
        if (report)
            *report = rep;
    }
    texopt_gap_layer_destroy(&g); /* zeroed when its create failed */
    free(layered);
    free(unboxed);
    return st;
}
