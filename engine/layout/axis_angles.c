/* axis_angles.c - target polar angles of an axis-aligned chart (Liu et al. 2019, 3.1.1).
 *
 * Angles are kept as turns between consecutive edges (tau_i = pi - alpha_i, alpha_i the
 * interior angle at the point between edges i and i + 1): a simple counter-clockwise loop
 * turns by 2 pi in all, and every update below changes two neighbouring turns by opposite
 * amounts, so the sum stays 2 pi and the K_i always add up to 4. */
#include "axis_angles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define SIGMA_FRACTION 0.004 /* of the boundary length (paper) */
#define SMOOTHING_PASSES 5
#define SMOOTHING_STOP 1e-4 /* largest interior-angle change that ends smoothing */
#define ROTATION_SAMPLES 720

/* Signed angle from direction a to direction b, in (-pi, pi]. */
static double turn_between(const double *a, const double *b)
{
    return atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]);
}

/* Gaussian smoothing of the edge directions s (unit, 2 each) along the boundary, eq. 3;
 * centre[i] is the arc length of edge i's midpoint. */
static void smooth_directions(const double *s, const double *len, const double *centre, size_t n, double total,
                              double *out)
{
    double sigma = SIGMA_FRACTION * total;
    for (size_t i = 0; i < n; i++) {
        double g[2] = {0.0, 0.0};
        for (size_t j = 0; j < n; j++) {
            double d = fabs(centre[i] - centre[j]);
            d = fmin(d, total - d);
            if (d > 5.0 * sigma && j != i)
                continue;
            double w = len[j] * exp(-d * d / (2.0 * sigma * sigma));
            g[0] += w * s[2 * j];
            g[1] += w * s[2 * j + 1];
        }
        double norm = hypot(g[0], g[1]);
        int keep = !(norm > 0.0) || (g[0] * s[2 * i] + g[1] * s[2 * i + 1]) < 0.0;
        out[2 * i] = keep ? s[2 * i] : g[0] / norm;
        out[2 * i + 1] = keep ? s[2 * i + 1] : g[1] / norm;
    }
}

/* Moves each edge's direction to next[], updating the turns (eq. 4); returns the largest
 * change of a turn. */
static double apply_directions(double *s, const double *next, double *tau, size_t n)
{
    double *delta = malloc(n * sizeof *delta), largest = 0.0;
    if (!delta)
        return 0.0;
    for (size_t i = 0; i < n; i++)
        delta[i] = turn_between(s + 2 * i, next + 2 * i);
    for (size_t i = 0; i < n; i++) {
        double change = delta[(i + 1) % n] - delta[i];
        tau[i] += change;
        largest = fmax(largest, fabs(change));
    }
    memcpy(s, next, 2 * n * sizeof *s);
    free(delta);
    return largest;
}

static double rotation_energy(const double *s, const double *len, size_t n, double phi)
{
    double c = cos(phi), sn = sin(phi), e = 0.0;
    for (size_t i = 0; i < n; i++) {
        double x = c * s[2 * i] - sn * s[2 * i + 1], y = sn * s[2 * i] + c * s[2 * i + 1];
        e += len[i] * x * x * y * y;
    }
    return e;
}

/* The rotation in [-pi/4, pi/4) minimising eq. 5 (period pi/2): the best sample, then a
 * golden-section search between its neighbours. */
static double best_rotation(const double *s, const double *len, size_t n)
{
    double step = 0.5 * PI / ROTATION_SAMPLES, best = -0.25 * PI, best_e = INFINITY;
    for (int k = 0; k < ROTATION_SAMPLES; k++) {
        double phi = -0.25 * PI + k * step, e = rotation_energy(s, len, n, phi);
        if (e < best_e) {
            best_e = e;
            best = phi;
        }
    }
    double a = best - step, b = best + step, g = 0.5 * (sqrt(5.0) - 1.0);
    for (int it = 0; it < 60; it++) {
        double c = b - g * (b - a), d = a + g * (b - a);
        if (rotation_energy(s, len, n, c) < rotation_energy(s, len, n, d))
            b = d;
        else
            a = c;
    }
    return 0.5 * (a + b);
}

/* Quarter turns of the axis closest to direction d: 0 (+x), 1 (+y), 2 (-x), 3 (-y). */
static int closest_axis(const double *d)
{
    double a = atan2(d[1], d[0]);
    int q = (int)lround(a / (0.5 * PI));
    return ((q % 4) + 4) % 4;
}

/* Splits every corner turning by more than one quarter (K > 1, a fold-over) onto K - 1
 * non-corner points nearest to it along the loop, alternating sides. */
static void split_sharp_corners(int *turn, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        for (size_t step = 1; turn[i] > 1 && step < n; step++) {
            size_t after = (i + step) % n, before = (i + n - step % n) % n;
            if (turn[after] == 0 && turn[i] > 1) {
                turn[after] = 1;
                turn[i]--;
            }
            if (turn[before] == 0 && turn[i] > 1) {
                turn[before] = 1;
                turn[i]--;
            }
        }
    }
}

static texopt_status check_loop(const double *xy, size_t n, double *s, double *len, double *tau, char *err,
                                size_t err_len)
{
    if (n < 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis angles: %zu points", n);
    for (size_t i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        len[i] = hypot(b[0] - a[0], b[1] - a[1]);
        if (!(len[i] > 0.0) || !isfinite(len[i]))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis angles: edge %zu has no length", i);
        s[2 * i] = (b[0] - a[0]) / len[i];
        s[2 * i + 1] = (b[1] - a[1]) / len[i];
    }
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        tau[i] = turn_between(s + 2 * i, s + 2 * ((i + 1) % n));
        sum += tau[i];
    }
    if (!(fabs(sum - 2.0 * PI) < 1e-6))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "axis angles: the loop turns by %g, not once counter-clockwise", sum);
    return TEXOPT_OK;
}

texopt_status texopt_axis_angles_compute(const double *xy, size_t n, texopt_axis_angles *out, char *err, size_t err_len)
{
    if (!xy || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "axis angles: NULL argument");
    memset(out, 0, sizeof *out);
    size_t m = n ? n : 1;
    double *s = malloc(2 * m * sizeof *s), *s1 = malloc(2 * m * sizeof *s1), *next = malloc(2 * m * sizeof *next);
    double *len = malloc(m * sizeof *len), *tau = malloc(m * sizeof *tau), *centre = malloc(m * sizeof *centre);
    out->theta = malloc(m * sizeof *out->theta);
    out->turn = malloc(m * sizeof *out->turn);
    texopt_status st = TEXOPT_OK;
    if (!s || !s1 || !next || !len || !tau || !centre || !out->theta || !out->turn)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "axis angles: out of memory");
    if (st == TEXOPT_OK)
        st = check_loop(xy, n, s, len, tau, err, err_len);
    if (st == TEXOPT_OK) {
        memcpy(s1, s, 2 * n * sizeof *s);
        double total = 0.0;
        for (size_t i = 0; i < n; i++) {
            centre[i] = total + 0.5 * len[i];
            total += len[i];
        }
        for (int pass = 0; pass < SMOOTHING_PASSES; pass++) {
            smooth_directions(s, len, centre, n, total, next);
            if (apply_directions(s, next, tau, n) < SMOOTHING_STOP)
                break;
        }
        double phi = best_rotation(s, len, n), c = cos(phi), sn = sin(phi);
        for (size_t i = 0; i < n; i++) { /* rotate the smoothed and the original directions */
            double x = s[2 * i], y = s[2 * i + 1];
            s[2 * i] = c * x - sn * y;
            s[2 * i + 1] = sn * x + c * y;
            x = s1[2 * i];
            y = s1[2 * i + 1];
            s1[2 * i] = c * x - sn * y;
            s1[2 * i + 1] = sn * x + c * y;
        }
        for (size_t i = 0; i < n; i++) { /* eq. 6: snap to the closest axis */
            int q = closest_axis(s + 2 * i);
            next[2 * i] = q == 0 ? 1.0 : q == 2 ? -1.0 : 0.0;
            next[2 * i + 1] = q == 1 ? 1.0 : q == 3 ? -1.0 : 0.0;
        }
        apply_directions(s, next, tau, n);
        for (size_t i = 0; i < n; i++)
            out->turn[i] = (int)lround(tau[i] / (0.5 * PI));
        split_sharp_corners(out->turn, n);
        size_t start = 0;
        double best = INFINITY;
        for (size_t i = 0; i < n; i++) {
            double d = fabs(turn_between(s1 + 2 * i, s + 2 * i));
            if (d < best) {
                best = d;
                start = i;
            }
        }
        double theta_s = atan2(s1[2 * start + 1], s1[2 * start]);
        int q = closest_axis(s + 2 * start);
        long k = lround((theta_s / (0.5 * PI) - q) / 4.0);
        out->theta[start] = (int)(4 * k + q);
        for (size_t step = 1; step < n; step++) {
            size_t i = (start + step) % n, prev = (start + step - 1) % n;
            out->theta[i] = out->theta[prev] + out->turn[prev];
        }
        out->rotation = phi;
        out->count = n;
        out->start = start;
    }
    free(s);
    free(s1);
    free(next);
    free(len);
    free(tau);
    free(centre);
    if (st != TEXOPT_OK)
        texopt_axis_angles_destroy(out);
    return st;
}

void texopt_axis_angles_destroy(texopt_axis_angles *a)
{
    if (!a)
        return;
    free(a->theta);
    free(a->turn);
    memset(a, 0, sizeof *a);
}
