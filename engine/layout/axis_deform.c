/* axis_deform.c - angle-driven deformation toward an axis-aligned chart (Liu et al. 2019, 3.1.2).
 *
 * One problem struct holds the rest shapes, the loop and its tracked polar angles; energy()
 * gives E_d + lambda E_align and its gradient at any positions, with each boundary edge's
 * angle continued from its value at the last accepted positions (a step that turns an edge
 * by more than a quarter turn is refused, so the continuation is unambiguous). The paper
 * uses L-BFGS under the fold-over constraint; here the constraint is the line search's
 * bound (the first step length at which a determinant reaches zero, times 0.8). */
#include "axis_deform.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define GAMMA 0.3         /* angle vs length in E_edge (paper) */
#define ANGLE_DONE 0.1    /* epsilon_a (paper) */
#define MAX_ROUNDS 10     /* n_max (paper) */
#define LAMBDA_GROWTH 6.0 /* beta (paper) */
#define INNER_ITERATIONS 200
#define HISTORY 5
#define STEP_SAFETY 0.8
#define ARMIJO 1e-4

typedef struct problem {
    size_t nv, nt, nb;
    const uint32_t *tri, *loop;
    double *inv;    /* 4 per triangle: rest edge matrix inverse, row-major */
    double *weight; /* per triangle: rest area / total */
    double *l0;     /* per boundary edge: rest length */
    double l0_total;
    double *target; /* per boundary edge: (pi/2) Theta */
    double *theta;  /* per boundary edge: its angle at ref */
    double *ref;    /* accepted positions (2 per vertex) */
    double lambda;
} problem;

static double edge_angle_at(const problem *p, const double *x, size_t i, double *dx, double *dy)
{
    const double *a = x + 2 * (size_t)p->loop[i], *b = x + 2 * (size_t)p->loop[(i + 1) % p->nb];
    *dx = b[0] - a[0];
    *dy = b[1] - a[1];
    const double *ra = p->ref + 2 * (size_t)p->loop[i], *rb = p->ref + 2 * (size_t)p->loop[(i + 1) % p->nb];
    double rx = rb[0] - ra[0], ry = rb[1] - ra[1];
    return p->theta[i] + atan2(rx * *dy - ry * *dx, rx * *dx + ry * *dy);
}

static double distortion(const problem *p, const double *x, double *grad)
{
    double e = 0.0;
    for (size_t t = 0; t < p->nt; t++) {
        const uint32_t *v = p->tri + 3 * t;
        const double *x0 = x + 2 * (size_t)v[0], *x1 = x + 2 * (size_t)v[1], *x2 = x + 2 * (size_t)v[2];
        double D[4] = {x1[0] - x0[0], x2[0] - x0[0], x1[1] - x0[1], x2[1] - x0[1]};
        const double *B = p->inv + 4 * t;
        double J[4] = {D[0] * B[0] + D[1] * B[2], D[0] * B[1] + D[1] * B[3], D[2] * B[0] + D[3] * B[2],
                       D[2] * B[1] + D[3] * B[3]};
        double f = J[0] * J[0] + J[1] * J[1] + J[2] * J[2] + J[3] * J[3], g = J[0] * J[3] - J[1] * J[2];
        if (!(g > 0.0))
            return INFINITY;
        double w = p->weight[t];
        e += 0.25 * w * (f + f / (g * g));
        if (!grad)
            continue;
        double cof[4] = {J[3], -J[2], -J[1], J[0]}, dJ[4];
        for (int k = 0; k < 4; k++)
            dJ[k] = 0.25 * w * (2.0 * J[k] + 2.0 * J[k] / (g * g) - 2.0 * f / (g * g * g) * cof[k]);
        /* dE/dD = dJ B^T */
        double dD[4] = {dJ[0] * B[0] + dJ[1] * B[1], dJ[0] * B[2] + dJ[1] * B[3], dJ[2] * B[0] + dJ[3] * B[1],
                        dJ[2] * B[2] + dJ[3] * B[3]};
        double *g0 = grad + 2 * (size_t)v[0], *g1 = grad + 2 * (size_t)v[1], *g2 = grad + 2 * (size_t)v[2];
        g1[0] += dD[0];
        g2[0] += dD[1];
        g1[1] += dD[2];
        g2[1] += dD[3];
        g0[0] -= dD[0] + dD[1];
        g0[1] -= dD[2] + dD[3];
    }
    return e;
}

/* E_align of eq. 8, its gradient (times scale) added to grad; the largest angle error. */
static double alignment(const problem *p, const double *x, double *grad, double scale, double *max_error)
{
    double e = 0.0;
    *max_error = 0.0;
    for (size_t i = 0; i < p->nb; i++) {
        double dx, dy, th = edge_angle_at(p, x, i, &dx, &dy), l2 = dx * dx + dy * dy, l = sqrt(l2);
        double w = p->l0[i] / p->l0_total, da = th - p->target[i], dl = l / p->l0[i] - 1.0;
        *max_error = fmax(*max_error, fabs(da));
        e += w * (0.5 * (1.0 - GAMMA) * da * da + 0.5 * GAMMA * dl * dl);
        if (!grad || !(l > 0.0))
            continue;
        double ga = scale * w * (1.0 - GAMMA) * da, gl = scale * w * GAMMA * dl / p->l0[i];
        double gx = ga * (-dy / l2) + gl * dx / l, gy = ga * (dx / l2) + gl * dy / l;
        double *gb = grad + 2 * (size_t)p->loop[(i + 1) % p->nb], *gA = grad + 2 * (size_t)p->loop[i];
        gb[0] += gx;
        gb[1] += gy;
        gA[0] -= gx;
        gA[1] -= gy;
    }
    return e;
}

static double energy(const problem *p, const double *x, double *grad)
{
    if (grad)
        memset(grad, 0, 2 * p->nv * sizeof *grad);
    double err, ed = distortion(p, x, grad);
    return ed + p->lambda * alignment(p, x, grad, p->lambda, &err);
}

/* First step length along dir at which some triangle's determinant reaches zero. */
static double max_step(const problem *p, const double *x, const double *dir)
{
    double best = INFINITY;
    for (size_t t = 0; t < p->nt; t++) {
        const uint32_t *v = p->tri + 3 * t;
        double e[4], f[4];
        for (int c = 0; c < 2; c++) {
            e[2 * c] = x[2 * (size_t)v[1] + c] - x[2 * (size_t)v[0] + c];
            e[2 * c + 1] = x[2 * (size_t)v[2] + c] - x[2 * (size_t)v[0] + c];
            f[2 * c] = dir[2 * (size_t)v[1] + c] - dir[2 * (size_t)v[0] + c];
            f[2 * c + 1] = dir[2 * (size_t)v[2] + c] - dir[2 * (size_t)v[0] + c];
        }
        /* det(E + t F) = c0 + c1 t + c2 t^2 with E = [e0 e1; e2 e3] */
        double c0 = e[0] * e[3] - e[1] * e[2];
        double c1 = e[0] * f[3] + f[0] * e[3] - e[1] * f[2] - f[1] * e[2];
        double c2 = f[0] * f[3] - f[1] * f[2];
        double root = INFINITY;
        if (fabs(c2) < 1e-300) {
            if (c1 < 0.0)
                root = -c0 / c1;
        } else {
            double disc = c1 * c1 - 4.0 * c2 * c0;
            if (disc >= 0.0) {
                double s = sqrt(disc), r1 = (-c1 - s) / (2.0 * c2), r2 = (-c1 + s) / (2.0 * c2);
                if (r1 > 0.0)
                    root = r1;
                if (r2 > 0.0 && r2 < root)
                    root = r2;
            }
        }
        best = fmin(best, root);
    }
    return best;
}

/* Whether positions x turn some boundary edge by a quarter turn or more from ref. */
static int turns_too_far(const problem *p, const double *x)
{
    for (size_t i = 0; i < p->nb; i++) {
        double dx, dy;
        if (fabs(edge_angle_at(p, x, i, &dx, &dy) - p->theta[i]) >= 0.5 * PI)
            return 1;
    }
    return 0;
}

static void accept(problem *p, const double *x)
{
    for (size_t i = 0; i < p->nb; i++) {
        double dx, dy;
        p->theta[i] = edge_angle_at(p, x, i, &dx, &dy);
    }
    memcpy(p->ref, x, 2 * p->nv * sizeof *x);
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}

/* L-BFGS on E_d + lambda E_align from p->ref; work holds 6 + 4 HISTORY vectors of 2 nv. */
static void minimise(problem *p, double *work)
{
    size_t n = 2 * p->nv;
    double *x = work, *g = work + n, *d = work + 2 * n, *trial = work + 3 * n, *gt = work + 4 * n;
    double *S = work + 6 * n, *Y = S + HISTORY * n, rho[HISTORY], alpha[HISTORY];
    memcpy(x, p->ref, n * sizeof *x);
    double e = energy(p, x, g);
    int stored = 0, newest = -1;
    for (int it = 0; it < INNER_ITERATIONS; it++) {
        memcpy(d, g, n * sizeof *d);
        for (int k = 0; k < stored; k++) {
            int j = (newest - k + HISTORY) % HISTORY;
            alpha[j] = rho[j] * dot(S + j * n, d, n);
            for (size_t i = 0; i < n; i++)
                d[i] -= alpha[j] * Y[j * n + i];
        }
        if (stored > 0) {
            double gamma = dot(S + newest * n, Y + newest * n, n) / dot(Y + newest * n, Y + newest * n, n);
            for (size_t i = 0; i < n; i++)
                d[i] *= gamma;
        }
        for (int k = stored - 1; k >= 0; k--) {
            int j = (newest - k + HISTORY) % HISTORY;
            double beta = rho[j] * dot(Y + j * n, d, n);
            for (size_t i = 0; i < n; i++)
                d[i] += (alpha[j] - beta) * S[j * n + i];
        }
        for (size_t i = 0; i < n; i++)
            d[i] = -d[i];
        double slope = dot(g, d, n);
        if (!(slope < 0.0)) { /* not a descent direction: steepest descent */
            for (size_t i = 0; i < n; i++)
                d[i] = -g[i];
            slope = -dot(g, g, n);
            stored = 0;
        }
        if (!(slope < 0.0))
            break;
        double t = fmin(1.0, STEP_SAFETY * max_step(p, x, d)), et = INFINITY;
        for (int h = 0; h < 40; h++, t *= 0.5) {
            for (size_t i = 0; i < n; i++)
                trial[i] = x[i] + t * d[i];
            if (turns_too_far(p, trial))
                continue;
            et = energy(p, trial, gt);
            if (et <= e + ARMIJO * t * slope)
                break;
        }
        if (!(et <= e + ARMIJO * t * slope))
            break;
        newest = (newest + 1) % HISTORY;
        for (size_t i = 0; i < n; i++) {
            S[newest * n + i] = trial[i] - x[i];
            Y[newest * n + i] = gt[i] - g[i];
        }
        double sy = dot(S + newest * n, Y + newest * n, n);
        rho[newest] = sy > 0.0 ? 1.0 / sy : 0.0;
        if (sy > 0.0 && stored < HISTORY)
            stored++;
        double change = e - et;
        memcpy(x, trial, n * sizeof *x);
        memcpy(g, gt, n * sizeof *g);
        e = et;
        accept(p, x);
        if (change <= 1e-10 * fabs(e))
            break;
    }
}

static texopt_status set_up(problem *p, const double *rest, const texopt_axis_angles *angles, double *xy, char *err,
                            size_t err_len)
{
    double area = 0.0;
    for (size_t t = 0; t < p->nt; t++) {
        const uint32_t *v = p->tri + 3 * t;
        for (int j = 0; j < 3; j++)
            if (v[j] >= p->nv)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis deform: triangle %zu: bad vertex", t);
        const double *a = rest + 2 * (size_t)v[0], *b = rest + 2 * (size_t)v[1], *c = rest + 2 * (size_t)v[2];
        double e0 = b[0] - a[0], e1 = c[0] - a[0], e2 = b[1] - a[1], e3 = c[1] - a[1], det = e0 * e3 - e1 * e2;
        if (!(det > 0.0))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "axis deform: triangle %zu is not counter-clockwise at rest", t);
        double *B = p->inv + 4 * t;
        B[0] = e3 / det;
        B[1] = -e1 / det;
        B[2] = -e2 / det;
        B[3] = e0 / det;
        p->weight[t] = 0.5 * det;
        area += 0.5 * det;
    }
    for (size_t t = 0; t < p->nt; t++)
        p->weight[t] /= area;
    double c = cos(angles->rotation), s = sin(angles->rotation);
    for (size_t v = 0; v < p->nv; v++) {
        xy[2 * v] = c * rest[2 * v] - s * rest[2 * v + 1];
        xy[2 * v + 1] = s * rest[2 * v] + c * rest[2 * v + 1];
    }
    p->l0_total = 0.0;
    for (size_t i = 0; i < p->nb; i++) {
        if (p->loop[i] >= p->nv)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis deform: loop point %zu: bad vertex", i);
        const double *a = xy + 2 * (size_t)p->loop[i], *b = xy + 2 * (size_t)p->loop[(i + 1) % p->nb];
        p->l0[i] = hypot(b[0] - a[0], b[1] - a[1]);
        if (!(p->l0[i] > 0.0))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis deform: loop edge %zu has no length", i);
        p->l0_total += p->l0[i];
        p->target[i] = 0.5 * PI * angles->theta[i];
    }
    /* The start edge's angle near its target's multiple of 2 pi, the others by their turns. */
    size_t st = angles->start;
    const double *a = xy + 2 * (size_t)p->loop[st], *b = xy + 2 * (size_t)p->loop[(st + 1) % p->nb];
    double th = atan2(b[1] - a[1], b[0] - a[0]);
    p->theta[st] = th + 2.0 * PI * round((p->target[st] - th) / (2.0 * PI));
    for (size_t k = 1; k < p->nb; k++) {
        size_t i = (st + k) % p->nb, prev = (st + k - 1) % p->nb;
        const double *p0 = xy + 2 * (size_t)p->loop[prev], *p1 = xy + 2 * (size_t)p->loop[i];
        const double *p2 = xy + 2 * (size_t)p->loop[(i + 1) % p->nb];
        double ux = p1[0] - p0[0], uy = p1[1] - p0[1], wx = p2[0] - p1[0], wy = p2[1] - p1[1];
        p->theta[i] = p->theta[prev] + atan2(ux * wy - uy * wx, ux * wx + uy * wy);
    }
    memcpy(p->ref, xy, 2 * p->nv * sizeof *xy);
    return TEXOPT_OK;
}

texopt_status texopt_axis_deform(size_t vertex_count, const double *rest, size_t triangle_count,
                                 const uint32_t *triangle, const uint32_t *loop, const texopt_axis_angles *angles,
                                 double *xy, texopt_axis_deform_report *report, char *err, size_t err_len)
{
    if (!rest || !triangle || !loop || !angles || !xy || angles->count < 3 || !triangle_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis deform: missing chart, loop or angles");
    problem p;
    memset(&p, 0, sizeof p);
    p.nv = vertex_count;
    p.nt = triangle_count;
    p.nb = angles->count;
    p.tri = triangle;
    p.loop = loop;
    size_t n = 2 * vertex_count;
    p.inv = malloc(4 * triangle_count * sizeof *p.inv);
    p.weight = malloc(triangle_count * sizeof *p.weight);
    p.l0 = malloc(p.nb * sizeof *p.l0);
    p.target = malloc(p.nb * sizeof *p.target);
    p.theta = malloc(p.nb * sizeof *p.theta);
    p.ref = malloc(n * sizeof *p.ref);
    double *work = malloc((6 + 2 * HISTORY) * n * sizeof *work);
    texopt_status st = TEXOPT_OK;
    if (!p.inv || !p.weight || !p.l0 || !p.target || !p.theta || !p.ref || !work)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "axis deform: out of memory");
    if (st == TEXOPT_OK)
        st = set_up(&p, rest, angles, xy, err, err_len);
    texopt_axis_deform_report rep = {0};
    if (st == TEXOPT_OK) {
        double error, align = alignment(&p, p.ref, NULL, 0.0, &error);
        p.lambda = align > 0.0 ? distortion(&p, p.ref, NULL) / align : 1.0;
        while (error >= ANGLE_DONE && rep.rounds < MAX_ROUNDS) {
            minimise(&p, work);
            alignment(&p, p.ref, NULL, 0.0, &error);
            p.lambda *= LAMBDA_GROWTH;
            rep.rounds++;
        }
        memcpy(xy, p.ref, n * sizeof *xy);
        rep.max_angle_error = error;
        rep.distortion = distortion(&p, xy, NULL);
        if (report)
            *report = rep;
    }
    free(p.inv);
    free(p.weight);
    free(p.l0);
    free(p.target);
    free(p.theta);
    free(p.ref);
    free(work);
    return st;
}
