/* param_abf.c - LABF angles (one sparse symmetric solve of the constraint system) and the
 * lecture's least-squares reconstruction of the layout from the angles (a second solve).
 * Constraints are numbered: triangles first, then each interior vertex's angle sum, then
 * its sine condition. */
#include "param_abf.h"

#include <math.h>
#include <stdlib.h>

#include "sparse_spd.h"

typedef struct abf_problem {
    const texopt_param_chart *chart;
    const texopt_param_boundary *boundary;
    size_t interior;      /* interior vertex count */
    int64_t *interior_of; /* per vertex: its interior index or -1 */
    double *beta;         /* 3 per triangle, target angles */
    double *theta;        /* 3 per triangle, planar angles */
} abf_problem;

static texopt_status target_angles(abf_problem *p)
{
    const texopt_param_chart *c = p->chart;
    double *sum = calloc(c->vertex_count, sizeof *sum);
    if (!sum)
        return TEXOPT_E_NOMEM;
    for (size_t t = 0; t < c->triangle_count; t++) {
        texopt_param_corner_angles(c, t, p->beta + 3 * t);
        for (int k = 0; k < 3; k++)
            sum[c->triangle[3 * t + k]] += p->beta[3 * t + k];
    }
    for (size_t i = 0; i < 3 * c->triangle_count; i++)
        if (p->interior_of[c->triangle[i]] >= 0)
            p->beta[i] *= 2.0 * TEXOPT_PI / sum[c->triangle[i]];
    free(sum);
    return TEXOPT_OK;
}

/* The constraints corner (t, k) enters, with its coefficients (at most four). */
static int corner_constraints(const abf_problem *p, size_t t, int k, uint32_t *con, double *coef)
{
    const uint32_t *tri = p->chart->triangle + 3 * t;
    size_t nt = p->chart->triangle_count;
    int n = 0;
    con[n] = (uint32_t)t;
    coef[n++] = 1.0;
    int64_t self = p->interior_of[tri[k]];
    if (self >= 0) {
        con[n] = (uint32_t)(nt + (size_t)self);
        coef[n++] = 1.0;
    }
    /* In triangle (i, j, k) the sine condition of i reads sum log sin theta_j - log sin
     * theta_k = 0: this corner is j for the vertex before it and k for the one after. */
    double cot = 1.0 / tan(p->beta[3 * t + k]);
    int64_t before = p->interior_of[tri[(k + 2) % 3]], after = p->interior_of[tri[(k + 1) % 3]];
    if (before >= 0) {
        con[n] = (uint32_t)(nt + p->interior + (size_t)before);
        coef[n++] = cot;
    }
    if (after >= 0) {
        con[n] = (uint32_t)(nt + p->interior + (size_t)after);
        coef[n++] = -cot;
    }
    return n;
}

/* b = residuals of the constraints at beta (what phi must make up). */
static void add_constraint_rhs(const abf_problem *p, texopt_spd *spd)
{
    const texopt_param_chart *c = p->chart;
    size_t nt = c->triangle_count;
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *tri = c->triangle + 3 * t;
        const double *b = p->beta + 3 * t;
        texopt_spd_add_rhs(spd, (uint32_t)t, 0, TEXOPT_PI - b[0] - b[1] - b[2]);
        for (int k = 0; k < 3; k++) {
            int64_t self = p->interior_of[tri[k]];
            if (self >= 0)
                texopt_spd_add_rhs(spd, (uint32_t)(nt + (size_t)self), 0, -b[k]);
            /* Vertex i = tri[k], j = tri[k + 1], k = tri[k + 2]. */
            if (self >= 0)
                texopt_spd_add_rhs(spd, (uint32_t)(nt + p->interior + (size_t)self), 0,
                                   -(log(sin(b[(k + 1) % 3])) - log(sin(b[(k + 2) % 3]))));
        }
    }
    for (size_t v = 0; v < c->vertex_count; v++)
        if (p->interior_of[v] >= 0)
            texopt_spd_add_rhs(spd, (uint32_t)(nt + (size_t)p->interior_of[v]), 0, 2.0 * TEXOPT_PI);
}

/* Solves (A D^-1 A^T) lambda = b, D = diag(beta^-2), and sets theta = beta + D^-1 A^T lambda. */
static texopt_status solve_angles(abf_problem *p, char *err, size_t err_len)
{
    size_t nt = p->chart->triangle_count, constraints = nt + 2 * p->interior;
    double *lambda = malloc(constraints * sizeof *lambda);
    texopt_spd *spd = NULL;
    texopt_status st = lambda ? texopt_spd_create(&spd, constraints, 1, err, err_len)
                              : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "abf: out of memory");
    uint32_t con[4];
    double coef[4], zero = 0.0;
    for (size_t t = 0; t < nt && st == TEXOPT_OK; t++)
        for (int k = 0; k < 3 && st == TEXOPT_OK; k++) {
            int n = corner_constraints(p, t, k, con, coef);
            double b = p->beta[3 * t + k];
            st = texopt_spd_add_row(spd, con, coef, n, &zero, b * b);
        }
    if (st == TEXOPT_OK) {
        add_constraint_rhs(p, spd);
        st = texopt_spd_solve(spd, lambda, err, err_len);
    }
    for (size_t t = 0; t < nt && st == TEXOPT_OK; t++)
        for (int k = 0; k < 3; k++) {
            int n = corner_constraints(p, t, k, con, coef);
            double b = p->beta[3 * t + k], phi = 0.0;
            for (int c = 0; c < n; c++)
                phi += coef[c] * lambda[con[c]];
            p->theta[3 * t + k] = b + b * b * phi;
            if (!(p->theta[3 * t + k] > 0.0))
                st = texopt_fail(err, err_len, TEXOPT_E_NUMERIC,
                                 "abf: the flattened angle of triangle %zu is not positive", t);
        }
    texopt_spd_destroy(spd);
    free(lambda);
    return st;
}

/* Rows e_ik - r R(theta_i) e_ij = 0 (u and v) for corner k of triangle t. */
static texopt_status add_corner_rows(texopt_spd *spd, const abf_problem *p, size_t t, int k, const int64_t *var,
                                     const double *uv)
{
    const uint32_t *tri = p->chart->triangle + 3 * t;
    const double *th = p->theta + 3 * t;
    uint32_t i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
    double r = sin(th[(k + 1) % 3]) / sin(th[(k + 2) % 3]), c = r * cos(th[k]), s = r * sin(th[k]);
    uint32_t vertex[5] = {l, i, j, j, i};
    int axis_u[5] = {0, 0, 0, 1, 1}, axis_v[5] = {1, 1, 1, 0, 0};
    double row_u[5] = {1.0, c - 1.0, -c, s, -s};
    double row_v[5] = {1.0, c - 1.0, -c, -s, s};
    texopt_status st = texopt_param_add_layout_row(spd, var, uv, vertex, axis_u, row_u, 5);
    return st == TEXOPT_OK ? texopt_param_add_layout_row(spd, var, uv, vertex, axis_v, row_v, 5) : st;
}

/* The rows of every corner of triangle t. */
static texopt_status add_triangle_rows(texopt_spd *spd, const void *context, size_t t, const int64_t *var,
                                       const double *uv)
{
    texopt_status st = TEXOPT_OK;
    for (int k = 0; k < 3 && st == TEXOPT_OK; k++)
        st = add_corner_rows(spd, context, t, k, var, uv);
    return st;
}

static double layout_angle(const double *uv, uint32_t a, uint32_t b, uint32_t c)
{
    double e1[2] = {uv[2 * (size_t)b] - uv[2 * (size_t)a], uv[2 * (size_t)b + 1] - uv[2 * (size_t)a + 1]};
    double e2[2] = {uv[2 * (size_t)c] - uv[2 * (size_t)a], uv[2 * (size_t)c + 1] - uv[2 * (size_t)a + 1]};
    return atan2(e1[0] * e2[1] - e1[1] * e2[0], e1[0] * e2[0] + e1[1] * e2[1]);
}

static void fill_report(const abf_problem *p, const double *uv, texopt_abf_report *report)
{
    report->max_angle_change = report->max_angle_error = 0.0;
    for (size_t t = 0; t < p->chart->triangle_count; t++) {
        const uint32_t *tri = p->chart->triangle + 3 * t;
        for (int k = 0; k < 3; k++) {
            double a = layout_angle(uv, tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            report->max_angle_change = fmax(report->max_angle_change, fabs(p->theta[3 * t + k] - p->beta[3 * t + k]));
            report->max_angle_error = fmax(report->max_angle_error, fabs(a - p->theta[3 * t + k]));
        }
    }
}

texopt_status texopt_param_abf(const texopt_param_chart *chart, double *uv, texopt_abf_report *report, char *err,
                               size_t err_len)
{
    if (!uv)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "abf: NULL output");
    texopt_param_boundary *b = NULL;
    texopt_status st = texopt_param_boundary_create(&b, chart, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    abf_problem p = {.chart = chart, .boundary = b};
    p.interior_of = malloc(chart->vertex_count * sizeof *p.interior_of);
    p.beta = malloc(3 * chart->triangle_count * sizeof *p.beta);
    p.theta = malloc(3 * chart->triangle_count * sizeof *p.theta);
    if (!p.interior_of || !p.beta || !p.theta)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "abf: out of memory");
    for (size_t v = 0; v < chart->vertex_count && st == TEXOPT_OK; v++)
        p.interior_of[v] = b->on_boundary[v] ? -1 : (int64_t)p.interior++;
    if (st == TEXOPT_OK && target_angles(&p) != TEXOPT_OK)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "abf: out of memory");
    if (st == TEXOPT_OK)
        st = solve_angles(&p, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_param_solve_pinned(chart, chart->triangle, add_triangle_rows, &p, uv, err, err_len);
    if (st == TEXOPT_OK && report)
        fill_report(&p, uv, report);
    free(p.interior_of);
    free(p.beta);
    free(p.theta);
    texopt_param_boundary_destroy(b);
    return st;
}
