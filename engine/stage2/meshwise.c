/* meshwise.c - stage 2: local-global solve of Sun et al. 2022, eq. 19 (section 4.2, app. B).
 *
 * Turns per-triangle target Jacobians into one conforming layout of the same charts. The
 * local step is closed form per triangle; the global step is a damped Newton step on the
 * texel positions with the locally injective barrier of Schueller et al. 2013, "Locally
 * Injective Mappings", and a line search bounded by the first step at which some
 * determinant would reach zero. It does not pack, scale to a budget or re-bake.
 *
 * Decisions the paper leaves open (see also meshwise.h):
 *  - Energy per triangle is weighted by its input texel area: G is a map from input texels
 *    to output texels, so that is the measure the integral is taken over.
 *  - Translation: one vertex per chart is pinned at its starting position. A tiny
 *    Levenberg-Marquardt term mu |x - x_k|^2 (mu = 1e-9 of the mean diagonal) keeps parts
 *    that are held together only by degenerate triangles solvable; it is zero at the accepted
 *    point and not part of E.
 *  - The fitting term has a constant Hessian (M_i = R_i S_i is fixed during the global
 *    step) that does not couple the u and v coordinates: the same n x n matrix for both.
 *    The barrier Hessian is approximated by the u and v diagonal blocks of its Gauss-Newton
 *    part B''(det) grad(det) grad(det)^T (positive semi-definite; the indefinite
 *    B'(det) hess(det) part and the u-v coupling are dropped), so the Newton system splits
 *    into two n x n systems. That is 4-8x fewer flops than the coupled 2n x 2n system (on
 *    a 30K-face sphere: 2.2 s wall coupled, 0.4 s CPU split; BENCHMARKS.md@9f788a8); the line
 *    search keeps every step a descent. The numeric factorisation is redone only when some
 *    barrier is active (then once per axis, the two in parallel with threads >= 2) or was
 *    active at the last factorisation.
 *  - Barrier: B(d) = 1/g(d/s) - 1 for 0 < d < s, 0 for d >= s, g(t) = t^3 - 3t^2 + 3t, with
 *    the threshold s_i = 0.5 * lambda1 * lambda2 of the triangle's target (at most 0.5): a
 *    triangle pays nothing until it is squeezed to half the area its target asks for.
 *  - w_R rotation targets are matched up to the 90-degree symmetry of the texel grid:
 *    k_i is chosen each local step.
 *  - Folded charts (a chart holding both orientations: mirrored halves joined along a fold)
 *    keep their halves on the same texels: coincident vertices of a chart share one unknown
 *    (merge_coincident), and vertices used only by the minority side are tied to the point
 *    of the majority-side triangle under them (find_fold_ties) by kappa |r|^2, its
 *    curvature 2 kappa = 100x the mean diagonal of the fitting Hessian: the residual is
 *    about 1% of the halves' disagreement (< 0.1 texel in the tests). The ties are
 *    quadratic, so they join the constant Hessian.
 *  - Sharing groups (opt->share, texel_share.h: separate charts on one texel region) are
 *    the same thing across charts: one pin per group, coincident vertices of the group
 *    merged, and each secondary vertex tied (add_shared_ties, same kappa) to the point of
 *    its primary's triangle that texel_share.h found under it, whatever its orientation.
 *  - Scaffold triangles (optional, layout/scaffold.h) are frames after the mesh's, with
 *    their own rest shapes, target I, w_R 0, w_S 1 and their area scaled by the scaffold's
 *    weight; the weight normalisation, pins, folds and ties see only the mesh's triangles,
 *    and the scaffold's extra vertices are fixed, so it adds terms but no unknowns.
 *  - The rotation step takes the closest rotation of w_R Rbar R^k + w_rs G S (not G S^-1):
 *    since |G - R S|^2 = |G|^2 - 2 tr(R^T G S) + |S|^2 for a rotation R and symmetric S,
 *    that is the exact minimiser of eq. 19 over R, which keeps E non-increasing. */
#include "meshwise.h"

#include <cholmod.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "distortion.h"
#include "parallel.h"
#include "sort_keys.h"
#include "tri_bins.h"

#define PI 3.14159265358979323846
#define BARRIER_FRACTION 0.5
#define BARRIER_REDUCTION 20.0 /* eq. 28 */
#define DAMPING 1e-9
#define ARMIJO 1e-4
#define MAX_HALVINGS 40
#define STRETCH_WEIGHT_FLOOR 1.0 /* relative to the mean w_S, see normalise_weights */
#define STEP_SAFETY 0.8          /* fraction of the largest step that keeps every det > 0 */
#define TIE_STIFFNESS 100.0      /* fold ties, relative to the mean fitting curvature */

typedef struct mat2 {
    double a, b, c, d; /* [[a b] [c d]] */
} mat2;

/* One axis' n x n system. Each has its own CHOLMOD workspace (a cholmod_common is not
 * shared between threads) and factor; both factors come from one symbolic analysis. */
typedef struct axis_system {
    cholmod_common cm;
    int started;
    cholmod_sparse *A; /* same pattern on both axes */
    cholmod_factor *L;
    int factorizations;
} axis_system;

/* A fold tie: vertex v[0] of a folded chart's minority side kept on the point of the
 * majority-side triangle v[1..3] it lay on in the input: r = sum c_i x_i = 0 per axis. */
typedef struct fold_tie {
    uint32_t v[4];
    double c[4];      /* 1, -barycentric weights */
    int32_t slot[16]; /* value index of (row, col) in the upper CSC, or -1 */
} fold_tie;

/* Per triangle data fixed for the whole solve. */
typedef struct tri_frame {
    uint32_t v[3];
    double grad[3][2]; /* gradients of the barycentric functions in input texel space */
    double area;       /* input texel area, > 0 */
    int orientation;   /* sign of the input signed texel area */
    double threshold;  /* barrier threshold s_i */
    double w_r, w_s;   /* normalised weights */
    mat2 rbar, sbar;
    int fitted;    /* contributes the fitting, rotation and stretch terms */
    int barrier;   /* carries the barrier */
    int collapsed; /* no input texel area but a 3D one: held on a line (collapse ties) */
} tri_frame;

typedef struct tri_state {
    mat2 r, s;
    int k;
} tri_state;

typedef struct solver {
    const texopt_mesh *mesh;
    size_t tri_count, vertex_count; /* the mesh's, then the scaffold's (meshwise.h) */
    size_t mesh_tris, mesh_vertices;
    const texopt_meshwise_scaffold *scaffold;
    tri_frame *tri;
    tri_state *st;
    double w_rs, w_b;

    int *var;               /* per vertex: its unknown (same index on both axes), or -1 when fixed */
    size_t unknowns;        /* free vertices: the size of each axis' system */
    int32_t *slot;          /* 9 per triangle: value index of (row, col) in the upper CSC, or -1 */
    int32_t *diag;          /* per unknown: value index of its diagonal entry */
    double *fit_values;     /* constant part of the Hessian (fitting term + damping) */
    double *axis_values[2]; /* fit + barrier block of the u and the v system */

    axis_system ax[2]; /* u and v; the fitting-only factor lives in ax[0] */
    int factor_is_fit; /* ax[0].L holds the factor of the fitting matrix alone */
    int threads;       /* 2 or more: the two axes factorise in parallel */

    fold_tie *ties;
    size_t tie_count;
    double tie_weight;               /* kappa of kappa |r|^2 per tie and axis */
    uint32_t *rep_of;                /* per vertex: the vertex whose unknown it shares */
    uint32_t *chart_of_vertex;       /* per used vertex: its chart's sharing group */
    const texopt_texel_share *share; /* may be NULL: every chart is its own group */
    size_t collapse_ties;            /* after the fold ties: collapsed triangles held on a line */
    size_t shared_ties;              /* the last ties: secondaries held on their primaries */

    double *x, *trial, *grad, *step;
} solver;

/* ---- 2x2 algebra ------------------------------------------------------------------- */

static mat2 rotation(double angle)
{
    mat2 m = {cos(angle), -sin(angle), sin(angle), cos(angle)};
    return m;
}

static mat2 mul(mat2 p, mat2 q)
{
    mat2 m = {p.a * q.a + p.b * q.c, p.a * q.b + p.b * q.d, p.c * q.a + p.d * q.c, p.c * q.b + p.d * q.d};
    return m;
}

static mat2 transpose(mat2 p)
{
    mat2 m = {p.a, p.c, p.b, p.d};
    return m;
}

static mat2 sym(mat2 p)
{
    double off = 0.5 * (p.b + p.c);
    mat2 m = {p.a, off, off, p.d};
    return m;
}

static double frob2(mat2 p)
{
    return p.a * p.a + p.b * p.b + p.c * p.c + p.d * p.d;
}

static mat2 sub(mat2 p, mat2 q)
{
    mat2 m = {p.a - q.a, p.b - q.b, p.c - q.c, p.d - q.d};
    return m;
}

static double rotation_angle(mat2 r)
{
    return atan2(r.c, r.a);
}

/* The rotation R maximising tr(R^T A): the rotation factor of A's 2x2 polar decomposition
 * (for det A > 0; the closest proper rotation otherwise). */
static mat2 closest_rotation(mat2 A)
{
    return rotation(atan2(A.c - A.b, A.a + A.d));
}

/* ---- per-triangle quantities ------------------------------------------------------- */

static mat2 jacobian(const tri_frame *f, const double *x)
{
    mat2 g = {0, 0, 0, 0};
    for (int j = 0; j < 3; j++) {
        const double *p = x + 2 * (size_t)f->v[j];
        g.a += p[0] * f->grad[j][0];
        g.b += p[0] * f->grad[j][1];
        g.c += p[1] * f->grad[j][0];
        g.d += p[1] * f->grad[j][1];
    }
    return g;
}

static double det2(mat2 m)
{
    return m.a * m.d - m.b * m.c;
}

/* Schueller et al. 2013 barrier and its first two derivatives in d = det G. */
static double barrier_value(double d, double s)
{
    if (!(d > 0.0))
        return INFINITY;
    if (d >= s)
        return 0.0;
    double t = d / s;
    double g = t * t * t - 3.0 * t * t + 3.0 * t;
    return 1.0 / g - 1.0;
}

static void barrier_derivatives(double d, double s, double *first, double *second)
{
    *first = *second = 0.0;
    if (!(d > 0.0) || d >= s)
        return;
    double t = d / s;
    double g = t * t * t - 3.0 * t * t + 3.0 * t;
    double g1 = 3.0 * (1.0 - t) * (1.0 - t);
    double g2 = 6.0 * t - 6.0;
    *first = -g1 / (g * g) / s;
    *second = (2.0 * g1 * g1 - g * g2) / (g * g * g) / (s * s);
}

/* d det G / d x for the 6 local coordinates (vertex j, axis c) -> out[2 j + c]. */
static void det_gradient(const tri_frame *f, mat2 g, double out[6])
{
    /* det G = g.a g.d - g.b g.c; g.a = sum x_j grad_j0, g.b = sum x_j grad_j1 (u row),
     * g.c, g.d the same with the v coordinates. */
    for (int j = 0; j < 3; j++) {
        out[2 * j + 0] = f->grad[j][0] * g.d - f->grad[j][1] * g.c;
        out[2 * j + 1] = f->grad[j][1] * g.a - f->grad[j][0] * g.b;
    }
}

static mat2 target_fit(const tri_state *s)
{
    return mul(s->r, s->s);
}

/* The non-barrier energy of one fitted triangle (without its area). */
static double fit_energy(const solver *sv, const tri_frame *f, const tri_state *s, mat2 g)
{
    mat2 rk = mul(f->rbar, rotation(s->k * PI / 2));
    return sv->w_rs * frob2(sub(g, target_fit(s))) + f->w_r * frob2(sub(s->r, rk)) + f->w_s * frob2(sub(s->s, f->sbar));
}

/* Residual of a fold tie on one axis. */
static double tie_residual(const fold_tie *tie, const double *x, int axis)
{
    double r = 0.0;
    for (int i = 0; i < 4; i++)
        r += tie->c[i] * x[2 * (size_t)tie->v[i] + axis];
    return r;
}

static double tie_residual2(const fold_tie *tie, const double *x)
{
    double u = tie_residual(tie, x, 0), v = tie_residual(tie, x, 1);
    return u * u + v * v;
}

/* Energy at positions x split into its fitting part (fold ties included) and its
 * (weighted) barrier part. */
static void total_energy(const solver *sv, const double *x, double *fit, double *barrier)
{
    double e_fit = 0.0, e_bar = 0.0;
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->fitted && !f->barrier)
            continue;
        mat2 g = jacobian(f, x);
        if (f->fitted)
            e_fit += f->area * fit_energy(sv, f, &sv->st[t], g);
        if (f->barrier)
            e_bar += f->area * barrier_value(det2(g), f->threshold);
    }
    for (size_t k = 0; k < sv->tie_count; k++)
        e_fit += sv->tie_weight * tie_residual2(&sv->ties[k], x);
    *fit = e_fit;
    *barrier = sv->w_b * e_bar;
}

/* ---- local step ---------------------------------------------------------------------- */

static int closest_symmetry(const tri_frame *f, const tri_state *s)
{
    double diff = rotation_angle(s->r) - rotation_angle(f->rbar);
    int best = 0;
    double best_cost = INFINITY;
    for (int k = 0; k < 4; k++) {
        double c = 1.0 - cos(diff - k * PI / 2);
        if (c < best_cost) {
            best_cost = c;
            best = k;
        }
    }
    return best;
}

/* Exact block minimisation in the order k, R (given S), S (given R): E never increases. */
static void local_step(solver *sv, const double *x)
{
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        tri_state *s = &sv->st[t];
        if (!f->fitted)
            continue;
        mat2 g = jacobian(f, x);
        s->k = closest_symmetry(f, s);
        mat2 rk = mul(f->rbar, rotation(s->k * PI / 2));
        mat2 gs = mul(g, s->s);
        mat2 A = {f->w_r * rk.a + sv->w_rs * gs.a, f->w_r * rk.b + sv->w_rs * gs.b, f->w_r * rk.c + sv->w_rs * gs.c,
                  f->w_r * rk.d + sv->w_rs * gs.d};
        s->r = closest_rotation(A);
        mat2 fitted = sym(mul(transpose(s->r), g));
        double w = f->w_s + sv->w_rs;
        mat2 S = {(f->w_s * f->sbar.a + sv->w_rs * fitted.a) / w, (f->w_s * f->sbar.b + sv->w_rs * fitted.b) / w,
                  (f->w_s * f->sbar.c + sv->w_rs * fitted.c) / w, (f->w_s * f->sbar.d + sv->w_rs * fitted.d) / w};
        s->s = S;
    }
}

/* The state a triangle starts from: its own polar factors, so the fitting term is 0. */
static void initial_state(solver *sv, const double *x)
{
    for (size_t t = 0; t < sv->tri_count; t++) {
        tri_state *s = &sv->st[t];
        mat2 g = jacobian(&sv->tri[t], x);
        s->r = closest_rotation(g);
        s->s = sym(mul(transpose(s->r), g));
        s->k = 0;
    }
}

/* ---- setup ----------------------------------------------------------------------------- */

static texopt_status check_target(const texopt_triangle_target *tg, size_t t, char *err, size_t err_len)
{
    if (!isfinite(tg->alpha) || !isfinite(tg->beta) || !(tg->lambda1 > 0.0) || !(tg->lambda2 > 0.0) ||
        !isfinite(tg->lambda1) || !isfinite(tg->lambda2))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "meshwise: target of triangle %zu has a non-finite angle or a "
                           "non-positive singular value (%g, %g)",
                           t, tg->lambda1, tg->lambda2);
    if (!(tg->w_rotation >= 0.0) || !(tg->w_stretch >= 0.0) || !isfinite(tg->w_rotation) || !isfinite(tg->w_stretch))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "meshwise: target of triangle %zu has a negative or non-finite weight", t);
    return TEXOPT_OK;
}

static mat2 target_stretch(const texopt_triangle_target *tg)
{
    mat2 v = rotation(tg->beta);
    mat2 l = {tg->lambda1, 0, 0, tg->lambda2};
    return mul(mul(v, l), transpose(v));
}

/* Sets the barycentric gradients, area and orientation of f from its rest corners; returns
 * the signed doubled area. */
static double set_rest_shape(tri_frame *f, const double *p0, const double *p1, const double *p2)
{
    double e1x = p1[0] - p0[0], e1y = p1[1] - p0[1];
    double e2x = p2[0] - p0[0], e2y = p2[1] - p0[1];
    double det = e1x * e2y - e1y * e2x;
    if (!(fabs(det) > 0.0) || !isfinite(det))
        return det;
    /* Rows of [e1 e2]^-1 are the gradients of barycentrics 1 and 2. */
    f->grad[1][0] = e2y / det;
    f->grad[1][1] = -e2x / det;
    f->grad[2][0] = -e1y / det;
    f->grad[2][1] = e1x / det;
    f->grad[0][0] = -f->grad[1][0] - f->grad[2][0];
    f->grad[0][1] = -f->grad[1][1] - f->grad[2][1];
    f->area = 0.5 * fabs(det);
    f->orientation = det < 0.0 ? -1 : 1;
    return det;
}

/* Scaffold triangles (meshwise.h): fitted to their rest shape with the barrier. */
static texopt_status build_scaffold_frames(solver *sv, char *err, size_t err_len)
{
    const texopt_meshwise_scaffold *sc = sv->scaffold;
    for (size_t k = 0; sc && k < sc->triangle_count; k++) {
        tri_frame *f = &sv->tri[sv->mesh_tris + k];
        for (int j = 0; j < 3; j++) {
            f->v[j] = sc->triangle[3 * k + j];
            if (f->v[j] >= sv->vertex_count)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                   "meshwise: scaffold triangle %zu uses vertex %u past %zu", k, f->v[j],
                                   sv->vertex_count);
        }
        const double *r = sc->rest + 6 * k;
        if (!(set_rest_shape(f, r, r + 2, r + 4) > 0.0))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "meshwise: scaffold triangle %zu has no counter-clockwise rest shape", k);
        f->area *= sc->weight;
        f->fitted = f->barrier = 1;
        f->threshold = BARRIER_FRACTION;
        f->rbar = rotation(0.0);
        f->sbar = rotation(0.0);
        f->w_r = 0.0;
        f->w_s = 1.0;
    }
    return TEXOPT_OK;
}

static texopt_status build_frames(solver *sv, const texopt_triangle_target *targets, char *err, size_t err_len)
{
    const texopt_mesh *m = sv->mesh;
    for (size_t t = 0; t < sv->mesh_tris; t++) {
        tri_frame *f = &sv->tri[t];
        texopt_status st = check_target(&targets[t], t, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        for (int j = 0; j < 3; j++) {
            f->v[j] = m->triangle[3 * t + j];
            if (f->v[j] >= m->vertex_count)
                return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                                   "meshwise: triangle %zu uses vertex %u past vertex count %zu", t, f->v[j],
                                   m->vertex_count);
        }
        double det = set_rest_shape(f, m->texel + 2 * (size_t)f->v[0], m->texel + 2 * (size_t)f->v[1],
                                    m->texel + 2 * (size_t)f->v[2]);
        int degenerate_uv = (m->flags[t] & TEXOPT_TRI_DEGENERATE_UV) || !(fabs(det) > 0.0) || !isfinite(det);
        f->barrier = !degenerate_uv;
        f->fitted = f->barrier && !(m->flags[t] & TEXOPT_TRI_DEGENERATE_3D);
        f->collapsed = degenerate_uv && !(m->flags[t] & TEXOPT_TRI_DEGENERATE_3D);
        if (!f->barrier)
            continue;
        double target_det = targets[t].lambda1 * targets[t].lambda2;
        f->threshold = BARRIER_FRACTION * fmin(1.0, target_det);
        f->rbar = rotation(targets[t].alpha);
        f->sbar = target_stretch(&targets[t]);
        f->w_r = targets[t].w_rotation;
        f->w_s = targets[t].w_stretch;
    }
    return build_scaffold_frames(sv, err, err_len);
}

/* Divides w_R and w_S by the mean w_S (or mean w_R when no triangle has a w_S) of the fitted
 * triangles, so that stage 1's variances keep their ratios but do not vanish against w_rs.
 * Then w_S is raised to at least STRETCH_WEIGHT_FLOOR: a triangle whose loss does not depend
 * on its stretch (flat colour: variance 0) got its target from the area term of eq. 14 and
 * should still move toward it, not stay wherever its neighbours leave it. w_R has no floor:
 * a zero rotation weight means any rotation is as good.
 * The floor was chosen by measurement (stage-1 targets, layout scaled to the targets' total
 * area, share of triangles with E <= 0.01 under it): floor 0 / 0.01 / 0.1 / 1 / 10 gave
 * 48 / 51 / 68 / 72 / 72 % on Fox and - / 38 / 43 / 50 / 52 % on the 16x16 "half" grid.
 * Below the mean, stage 1's variances hurt; above it they keep their ratios. */
static void normalise_weights(solver *sv)
{
    double sum_s = 0.0, sum_r = 0.0;
    size_t n = 0;
    for (size_t t = 0; t < sv->mesh_tris; t++) {
        if (!sv->tri[t].fitted)
            continue;
        sum_s += sv->tri[t].w_s;
        sum_r += sv->tri[t].w_r;
        n++;
    }
    double scale = sum_s > 0.0 ? sum_s / (double)n : sum_r > 0.0 ? sum_r / (double)n : 1.0;
    for (size_t t = 0; t < sv->mesh_tris; t++) {
        sv->tri[t].w_s = fmax(sv->tri[t].w_s / scale, STRETCH_WEIGHT_FLOOR);
        sv->tri[t].w_r /= scale;
    }
}

/* A used vertex with the keys that decide whether it coincides with another. */
typedef struct vertex_key {
    uint32_t chart;
    double x, y;   /* input texel position */
    double sx, sy; /* starting position */
    uint32_t vertex;
} vertex_key;

static int compare_vertex_keys(const void *pa, const void *pb)
{
    const vertex_key *a = pa, *b = pb;
    if (a->chart != b->chart)
        return a->chart < b->chart ? -1 : 1;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    return a->vertex < b->vertex ? -1 : a->vertex > b->vertex;
}

/* rep[v]: the vertex whose unknown v shares. Vertices of one chart at bit-identical input
 * texel positions (and equal starting positions) share one unknown, so the two halves of
 * a folded chart (mirrored halves joined along their fold line, as in Duck and
 * DamagedHelmet) keep sharing their texels exactly instead of drifting apart and giving one
 * texel two different contents. Different charts are never tied. */
static texopt_status merge_coincident(solver *sv, const uint32_t *chart_of_vertex, uint32_t *rep, char *err,
                                      size_t err_len)
{
    size_t n = 0;
    vertex_key *keys = malloc((sv->vertex_count ? sv->vertex_count : 1) * sizeof *keys);
    if (!keys)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
    for (size_t v = 0; v < sv->vertex_count; v++) {
        rep[v] = (uint32_t)v;
        if (sv->var[v] == -2)
            continue;
        vertex_key k = {chart_of_vertex[v], sv->mesh->texel[2 * v], sv->mesh->texel[2 * v + 1],
                        sv->x[2 * v],       sv->x[2 * v + 1],       (uint32_t)v};
        keys[n++] = k;
    }
    qsort(keys, n, sizeof *keys, compare_vertex_keys);
    for (size_t i = 1; i < n; i++) {
        const vertex_key *a = &keys[i - 1], *b = &keys[i];
        if (a->chart == b->chart && a->x == b->x && a->y == b->y && a->sx == b->sx && a->sy == b->sy)
            rep[b->vertex] = rep[a->vertex];
    }
    free(keys);
    return TEXOPT_OK;
}

/* The sharing group of a chart (texel_share.h): its primary, or itself. */
static uint32_t group_of(const solver *sv, uint32_t chart)
{
    return sv->share ? sv->share->primary_of[chart] : chart;
}

/* Free unknowns: every vertex used by a triangle with an input area, except one pinned
 * vertex per sharing group (the first vertex of its primary's first such triangle: the
 * secondaries follow the primary through their ties); coincident vertices of a group share
 * one (merge_coincident: exact twins and same-point charts then share exactly). */
static texopt_status number_unknowns(solver *sv, char *err, size_t err_len)
{
    const texopt_mesh *m = sv->mesh;
    size_t nv = sv->vertex_count ? sv->vertex_count : 1;
    unsigned char *pinned_chart = calloc(m->chart_count ? m->chart_count : 1, 1);
    uint32_t *chart_of_vertex = sv->chart_of_vertex = calloc(nv, sizeof *chart_of_vertex);
    uint32_t *rep = sv->rep_of = calloc(nv, sizeof *rep);
    uint32_t *pins = calloc(m->chart_count ? m->chart_count : 1, sizeof *pins);
    texopt_status st = TEXOPT_OK;
    if (!pinned_chart || !chart_of_vertex || !rep || !pins)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
    for (size_t v = 0; v < sv->vertex_count; v++)
        sv->var[v] = -2; /* unused */
    size_t pin_count = 0;
    for (size_t t = 0; t < sv->mesh_tris && st == TEXOPT_OK; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->barrier && !f->collapsed)
            continue;
        if (m->chart_of[t] >= m->chart_count) {
            st = texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                             "meshwise: triangle %zu in chart %u past chart count %zu", t, m->chart_of[t],
                             m->chart_count);
            break;
        }
        uint32_t chart = group_of(sv, m->chart_of[t]);
        if (f->barrier && !pinned_chart[chart] && chart == m->chart_of[t]) {
            pinned_chart[chart] = 1;
            pins[pin_count++] = f->v[0];
        }
        for (int j = 0; j < 3; j++) {
            sv->var[f->v[j]] = 0;
            chart_of_vertex[f->v[j]] = chart;
        }
    }
    if (st == TEXOPT_OK)
        st = merge_coincident(sv, chart_of_vertex, rep, err, err_len);
    if (st == TEXOPT_OK) {
        for (size_t i = 0; i < pin_count; i++)
            sv->var[rep[pins[i]]] = -1;
        size_t n = 0;
        for (size_t v = 0; v < sv->vertex_count; v++) /* representatives come first in v */
            if (rep[v] == v)
                sv->var[v] = sv->var[v] == 0 ? (int)n++ : -1;
        for (size_t v = 0; v < sv->vertex_count; v++)
            sv->var[v] = sv->var[rep[v]];
        sv->unknowns = n;
    }
    free(pinned_chart);
    free(pins);
    return st;
}

static int64_t unknown_of(const solver *sv, uint32_t vertex)
{
    return sv->var[vertex];
}

/* Index of entry (row, col) among the sorted rows of column col. */
static int32_t find_slot(const cholmod_sparse *A, int64_t row, int64_t col)
{
    const int *p = A->p, *i = A->i;
    int lo = p[col], hi = p[col + 1] - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        if (i[mid] == row)
            return mid;
        if (i[mid] < row)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return -1;
}

/* ---- fold ties ------------------------------------------------------------------------ */

/* Per chart, the orientation of the larger total texel area (+1 on a tie), like mesh.c's
 * chart_sign, recomputed so that hand-made meshes need not fill it. */
static int8_t *chart_orientations(const solver *sv)
{
    const texopt_mesh *m = sv->mesh;
    double *balance = calloc(m->chart_count ? m->chart_count : 1, sizeof *balance);
    int8_t *sign = malloc(m->chart_count ? m->chart_count : 1);
    if (!balance || !sign) {
        free(balance);
        free(sign);
        return NULL;
    }
    for (size_t t = 0; t < sv->mesh_tris; t++)
        if (sv->tri[t].barrier)
            balance[m->chart_of[t]] += sv->tri[t].orientation * sv->tri[t].area;
    for (size_t c = 0; c < m->chart_count; c++)
        sign[c] = balance[c] < 0.0 ? -1 : 1;
    free(balance);
    return sign;
}

/* Barycentric weights of p in triangle f (input texels); 1 when p is inside (with a
 * tolerance of 1e-9 of the weights). */
static int barycentric(const texopt_mesh *m, const tri_frame *f, const double p[2], double w[3])
{
    const double *a = m->texel + 2 * (size_t)f->v[0];
    double dx = p[0] - a[0], dy = p[1] - a[1];
    /* grad[j] are the gradients of the barycentric functions: w_j = w_j(a) + grad_j . d */
    w[1] = f->grad[1][0] * dx + f->grad[1][1] * dy;
    w[2] = f->grad[2][0] * dx + f->grad[2][1] * dy;
    w[0] = 1.0 - w[1] - w[2];
    return w[0] >= -1e-9 && w[1] >= -1e-9 && w[2] >= -1e-9;
}

/* Finds, for every vertex used only by minority-side triangles of a folded chart, the
 * majority-side triangle of the same chart it lies on in the input, and ties it there.
 * Vertices already merged with a coincident one need no tie. */
static texopt_status find_fold_ties(solver *sv, char *err, size_t err_len)
{
    const texopt_mesh *m = sv->mesh;
    size_t nv = sv->vertex_count ? sv->vertex_count : 1, nt = sv->tri_count ? sv->tri_count : 1;
    int8_t *sign = chart_orientations(sv);
    unsigned char *side = calloc(nv, 1);     /* bit 0: majority triangle, bit 1: minority */
    unsigned char *majority = calloc(nt, 1); /* majority triangle of a folded chart */
    unsigned char *folded = calloc(m->chart_count ? m->chart_count : 1, 1);
    texopt_tri_bins grid = {0};
    texopt_status st = TEXOPT_OK;
    if (!sign || !side || !majority || !folded) {
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
        goto done;
    }
    for (size_t t = 0; t < sv->mesh_tris; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->barrier || group_of(sv, m->chart_of[t]) != m->chart_of[t]) /* secondaries: add_shared_ties */
            continue;
        int minority = f->orientation != sign[m->chart_of[t]];
        for (int j = 0; j < 3; j++)
            side[f->v[j]] |= (unsigned char)(minority ? 2 : 1);
        if (minority)
            folded[m->chart_of[t]] = 1;
    }
    for (size_t v = 0; v < sv->vertex_count; v++) /* a merged group counts as one vertex */
        side[sv->rep_of[v]] |= side[v];
    for (size_t t = 0; t < sv->mesh_tris; t++)
        majority[t] = sv->tri[t].barrier && folded[m->chart_of[t]] && sv->tri[t].orientation == sign[m->chart_of[t]];
    if ((st = texopt_tri_bins_build(&grid, m, majority, err, err_len)) != TEXOPT_OK)
        goto done;
    size_t cap = 0;
    for (size_t v = 0; v < sv->vertex_count && grid.start; v++) {
        if (side[v] != 2 || sv->rep_of[v] != v)
            continue;
        const double *p = m->texel + 2 * v;
        size_t b = texopt_tri_bins_index(&grid, p[1], 1) * grid.nx + texopt_tri_bins_index(&grid, p[0], 0);
        for (uint32_t k = grid.start[b]; k < grid.start[b + 1]; k++) {
            const tri_frame *f = &sv->tri[grid.tri[k]];
            double w[3];
            if (m->chart_of[grid.tri[k]] != sv->chart_of_vertex[v] || !barycentric(m, f, p, w))
                continue;
            if (sv->tie_count == cap) {
                cap = cap ? 2 * cap : 64;
                fold_tie *grown = realloc(sv->ties, cap * sizeof *grown);
                if (!grown) {
                    st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
                    goto done;
                }
                sv->ties = grown;
            }
            fold_tie *tie = &sv->ties[sv->tie_count++];
            tie->v[0] = (uint32_t)v;
            tie->c[0] = 1.0;
            for (int j = 0; j < 3; j++) {
                tie->v[j + 1] = f->v[j];
                tie->c[j + 1] = -w[j];
            }
            break;
        }
    }
done:
    free(sign);
    free(side);
    free(majority);
    free(folded);
    texopt_tri_bins_free(&grid);
    return st;
}

/* Appends a tie sum_i c[i] x[v[i]] = 0 over three vertices (the fourth slot unused). */
static texopt_status push_line_tie(solver *sv, size_t *cap, const uint32_t v[3], const double c[3], char *err,
                                   size_t err_len)
{
    if (sv->tie_count == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        fold_tie *grown = realloc(sv->ties, *cap * sizeof *grown);
        if (!grown)
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory for the collapse ties");
        sv->ties = grown;
    }
    fold_tie *tie = &sv->ties[sv->tie_count++];
    for (int i = 0; i < 3; i++) {
        tie->v[i] = v[i];
        tie->c[i] = c[i];
    }
    tie->v[3] = v[2];
    tie->c[3] = 0.0;
    sv->collapse_ties++;
    return TEXOPT_OK;
}

/* Ties every collapsed triangle (no input texel area, a 3D one: a face an exporter mapped
 * to one texel line or point) to stay collapsed: the corner opposite its longest input
 * edge is held on the point of that edge it lay on (the same fraction along it), or, when
 * the corners coincide, two corners on the third. Its Jacobian against the input is
 * singular, so no fitting term can hold it; without the tie its corners follow the
 * triangles on either side of the line, which stage 2 solves apart, and it opens into a
 * large triangle that shows one line of input texels smeared and can cover other charts'
 * texels (issue 37). The tie keeps it a line wherever the line goes. */
static texopt_status add_collapse_ties(solver *sv, char *err, size_t err_len)
{
    const texopt_mesh *m = sv->mesh;
    size_t cap = sv->tie_count;
    texopt_status st = TEXOPT_OK;
    for (size_t t = 0; t < sv->tri_count && st == TEXOPT_OK; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->collapsed)
            continue;
        int longest = 0; /* edge (j, j + 1) */
        double best = -1.0;
        for (int j = 0; j < 3; j++) {
            const double *a = m->texel + 2 * (size_t)f->v[j], *b = m->texel + 2 * (size_t)f->v[(j + 1) % 3];
            double l2 = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]);
            if (l2 > best) {
                best = l2;
                longest = j;
            }
        }
        uint32_t p = f->v[longest], q = f->v[(longest + 1) % 3], r = f->v[(longest + 2) % 3];
        const double *a = m->texel + 2 * (size_t)p, *b = m->texel + 2 * (size_t)q, *c = m->texel + 2 * (size_t)r;
        if (best > 0.0) {
            double s = ((c[0] - a[0]) * (b[0] - a[0]) + (c[1] - a[1]) * (b[1] - a[1])) / best;
            s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
            const uint32_t v[3] = {r, p, q};
            const double w[3] = {1.0, -(1.0 - s), -s};
            st = push_line_tie(sv, &cap, v, w, err, err_len);
        } else {
            const uint32_t v1[3] = {q, p, r}, v2[3] = {r, p, q};
            const double w[3] = {1.0, -1.0, 0.0};
            st = push_line_tie(sv, &cap, v1, w, err, err_len);
            if (st == TEXOPT_OK)
                st = push_line_tie(sv, &cap, v2, w, err, err_len);
        }
    }
    return st;
}

/* The ties of the sharing groups (texel_share.h), after the fold ties: each secondary
 * vertex held on the point of its primary's triangle it lay on in the input, like a fold's
 * minority vertex. A vertex sharing the unknown of another needs no tie of its own (its
 * representative has one, or is the primary's), and a fixed one would pull the primary. */
static texopt_status add_shared_ties(solver *sv, char *err, size_t err_len)
{
    const texopt_texel_share *share = sv->share;
    if (!share || share->tie_count == 0)
        return TEXOPT_OK;
    fold_tie *grown = realloc(sv->ties, (sv->tie_count + share->tie_count) * sizeof *grown);
    if (!grown)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory for %zu ties", share->tie_count);
    sv->ties = grown;
    for (size_t k = 0; k < share->tie_count; k++) {
        const texopt_texel_tie *t = &share->ties[k];
        int in_range = t->vertex < sv->mesh_vertices;
        for (int j = 0; j < 3; j++)
            in_range = in_range && t->corner[j] < sv->mesh_vertices;
        if (!in_range)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "meshwise: shared-texel tie %zu uses a vertex past vertex count %zu", k,
                               sv->vertex_count);
        if (sv->rep_of[t->vertex] != t->vertex || unknown_of(sv, t->vertex) < 0)
            continue;
        fold_tie *tie = &sv->ties[sv->tie_count++];
        tie->v[0] = t->vertex;
        tie->c[0] = 1.0;
        for (int j = 0; j < 3; j++) {
            tie->v[j + 1] = t->corner[j];
            tie->c[j + 1] = -t->weight[j];
        }
        sv->shared_ties++;
    }
    return TEXOPT_OK;
}

static size_t pattern_nnz(const solver *sv)
{
    return (size_t)((const int *)sv->ax[0].A->p)[sv->unknowns];
}

/* The one symbolic analysis (fill-reducing ordering, supernodes) of the shared pattern; the
 * v axis gets a copy of it and its own matrix. */
static texopt_status analyse(solver *sv, char *err, size_t err_len)
{
    axis_system *u = &sv->ax[0], *v = &sv->ax[1];
    u->L = cholmod_analyze(u->A, &u->cm);
    if (!u->L || u->cm.status < CHOLMOD_OK)
        return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "meshwise: CHOLMOD analysis failed (status %d)",
                           u->cm.status);
    v->A = cholmod_copy_sparse(u->A, &v->cm);
    v->L = cholmod_copy_factor(u->L, &v->cm);
    if (!v->A || !v->L)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory for the factor");
    return TEXOPT_OK;
}

/* The upper-triangular pattern of one axis' system: a 3x3 block per triangle plus every
 * diagonal. Analysed by CHOLMOD once. */
static texopt_status build_pattern(solver *sv, char *err, size_t err_len)
{
    size_t cap = sv->unknowns + 3 * sv->tri_count + 6 * sv->tie_count;
    uint64_t *keys = malloc(cap * sizeof *keys);
    if (!keys)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
    size_t n = 0;
    for (size_t u = 0; u < sv->unknowns; u++)
        keys[n++] = ((uint64_t)u << 32) | u;
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->barrier)
            continue;
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                int64_t r = unknown_of(sv, f->v[j]);
                int64_t c = unknown_of(sv, f->v[k]);
                if (r < 0 || c < 0 || r >= c)
                    continue;
                keys[n++] = ((uint64_t)c << 32) | (uint64_t)r;
            }
    }
    for (size_t k = 0; k < sv->tie_count; k++)
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++) {
                int64_t r = unknown_of(sv, sv->ties[k].v[i]);
                int64_t c = unknown_of(sv, sv->ties[k].v[j]);
                if (r < 0 || c < 0 || r >= c)
                    continue;
                keys[n++] = ((uint64_t)c << 32) | (uint64_t)r;
            }
    qsort(keys, n, sizeof *keys, texopt_compare_u64);
    size_t unique = 0;
    for (size_t k = 0; k < n; k++)
        if (unique == 0 || keys[unique - 1] != keys[k])
            keys[unique++] = keys[k];

    cholmod_sparse *A =
        cholmod_allocate_sparse(sv->unknowns, sv->unknowns, unique, 1, 1, 1, CHOLMOD_REAL, &sv->ax[0].cm);
    sv->ax[0].A = A;
    if (!A) {
        free(keys);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: cannot allocate the %zu x %zu matrix", sv->unknowns,
                           sv->unknowns);
    }
    int *p = A->p, *i = A->i;
    size_t col = 0;
    p[0] = 0;
    for (size_t k = 0; k < unique; k++) {
        size_t c = (size_t)(keys[k] >> 32);
        while (col < c)
            p[++col] = (int)k;
        i[k] = (int)(keys[k] & 0xffffffffu);
    }
    while (col < sv->unknowns)
        p[++col] = (int)unique;
    free(keys);

    for (size_t u = 0; u < sv->unknowns; u++)
        sv->diag[u] = find_slot(A, (int64_t)u, (int64_t)u);
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        for (int l = 0; l < 9; l++) {
            int64_t r = f->barrier ? unknown_of(sv, f->v[l / 3]) : -1;
            int64_t c = f->barrier ? unknown_of(sv, f->v[l % 3]) : -1;
            sv->slot[9 * t + l] = (r < 0 || c < 0 || r > c) ? -1 : find_slot(A, r, c);
        }
    }
    for (size_t k = 0; k < sv->tie_count; k++)
        for (int l = 0; l < 16; l++) {
            int64_t r = unknown_of(sv, sv->ties[k].v[l / 4]);
            int64_t c = unknown_of(sv, sv->ties[k].v[l % 4]);
            sv->ties[k].slot[l] = (r < 0 || c < 0 || r > c) ? -1 : find_slot(A, r, c);
        }
    return TEXOPT_OK;
}

/* The constant Hessian of sum a w_rs |G - M|^2: 2 a w_rs (grad_j . grad_k), equal on both
 * axes. */
static void build_fit_hessian(solver *sv)
{
    size_t nnz = pattern_nnz(sv);
    memset(sv->fit_values, 0, nnz * sizeof *sv->fit_values);
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->fitted)
            continue;
        double w = 2.0 * f->area * sv->w_rs;
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) {
                int32_t s = sv->slot[9 * t + 3 * j + k];
                if (s >= 0)
                    sv->fit_values[s] += w * (f->grad[j][0] * f->grad[k][0] + f->grad[j][1] * f->grad[k][1]);
            }
    }
    double mean_diag = 0.0;
    for (size_t u = 0; u < sv->unknowns; u++)
        mean_diag += sv->fit_values[sv->diag[u]];
    mean_diag = sv->unknowns ? mean_diag / (double)sv->unknowns : 1.0;
    /* Barrier-only parts have no fitting curvature; keep the damping meaningful there. */
    double mu = DAMPING * (mean_diag > 0.0 ? mean_diag : 1.0);
    for (size_t u = 0; u < sv->unknowns; u++)
        sv->fit_values[sv->diag[u]] += mu;
    /* Fold ties: kappa |sum c_i x_i|^2 per axis, stiff against the fitting terms. */
    sv->tie_weight = 0.5 * TIE_STIFFNESS * (mean_diag > 0.0 ? mean_diag : 1.0);
    for (size_t k = 0; k < sv->tie_count; k++)
        for (int l = 0; l < 16; l++) {
            int32_t s = sv->ties[k].slot[l];
            if (s >= 0)
                sv->fit_values[s] += 2.0 * sv->tie_weight * sv->ties[k].c[l / 4] * sv->ties[k].c[l % 4];
        }
}

/* ---- global step ----------------------------------------------------------------------- */

/* Gradient of the global-step objective into sv->grad (2 per free unknown: u, v); adds the
 * u and v blocks of the barrier's Gauss-Newton Hessian to sv->axis_values. Returns the
 * number of triangles whose barrier is active. */
static size_t gradient_and_barrier(solver *sv)
{
    memset(sv->grad, 0, 2 * sv->unknowns * sizeof *sv->grad);
    size_t active = 0;
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->barrier)
            continue;
        mat2 g = jacobian(f, sv->x);
        double local[6] = {0};
        if (f->fitted) {
            mat2 r = sub(g, target_fit(&sv->st[t]));
            double w = 2.0 * f->area * sv->w_rs;
            for (int j = 0; j < 3; j++) {
                local[2 * j + 0] += w * (r.a * f->grad[j][0] + r.b * f->grad[j][1]);
                local[2 * j + 1] += w * (r.c * f->grad[j][0] + r.d * f->grad[j][1]);
            }
        }
        double b1, b2;
        barrier_derivatives(det2(g), f->threshold, &b1, &b2);
        if (b1 != 0.0 || b2 != 0.0) {
            double dd[6];
            det_gradient(f, g, dd);
            double w = sv->w_b * f->area;
            for (int l = 0; l < 6; l++)
                local[l] += w * b1 * dd[l];
            for (int l = 0; l < 9; l++) {
                int32_t s = sv->slot[9 * t + l];
                int j = l / 3, k = l % 3;
                if (s < 0)
                    continue;
                sv->axis_values[0][s] += w * b2 * dd[2 * j] * dd[2 * k];
                sv->axis_values[1][s] += w * b2 * dd[2 * j + 1] * dd[2 * k + 1];
            }
            active++;
        }
        for (int l = 0; l < 6; l++) {
            int64_t u = unknown_of(sv, f->v[l / 2]);
            if (u >= 0)
                sv->grad[2 * u + l % 2] += local[l];
        }
    }
    for (size_t k = 0; k < sv->tie_count; k++) {
        const fold_tie *tie = &sv->ties[k];
        for (int axis = 0; axis < 2; axis++) {
            double r = 2.0 * sv->tie_weight * tie_residual(tie, sv->x, axis);
            for (int i = 0; i < 4; i++) {
                int64_t u = unknown_of(sv, tie->v[i]);
                if (u >= 0)
                    sv->grad[2 * u + axis] += r * tie->c[i];
            }
        }
    }
    return active;
}

/* Smallest t > 0 with c0 + c1 t + c2 t^2 = 0 (c0 > 0), or +inf. */
static double first_positive_root(double c0, double c1, double c2)
{
    double best = INFINITY;
    if (fabs(c2) <= 1e-14 * (fabs(c1) + fabs(c0))) {
        if (c1 < 0.0)
            best = -c0 / c1;
        return best;
    }
    double disc = c1 * c1 - 4.0 * c2 * c0;
    if (disc < 0.0)
        return best;
    double q = -0.5 * (c1 + (c1 >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    double r1 = q / c2, r2 = q != 0.0 ? c0 / q : INFINITY;
    if (r1 > 0.0 && r1 < best)
        best = r1;
    if (r2 > 0.0 && r2 < best)
        best = r2;
    return best;
}

/* Largest step along dx (per vertex, full layout) before some det G reaches zero. */
static double max_feasible_step(const solver *sv, const double *dx)
{
    double t_max = INFINITY;
    for (size_t t = 0; t < sv->tri_count; t++) {
        const tri_frame *f = &sv->tri[t];
        if (!f->barrier)
            continue;
        mat2 g = jacobian(f, sv->x);
        mat2 dg = jacobian(f, dx);
        /* det(G + t dG) = det G + t (g.a dg.d + dg.a g.d - g.b dg.c - dg.b g.c) + t^2 det dG */
        double c0 = det2(g);
        double c1 = g.a * dg.d + dg.a * g.d - g.b * dg.c - dg.b * g.c;
        double c2 = det2(dg);
        double r = first_positive_root(c0, c1, c2);
        if (r < t_max)
            t_max = r;
    }
    return t_max;
}

/* Loads `values` into the axis' matrix and refactorises it numerically. */
static texopt_status factorize(solver *sv, int axis, const double *values, char *err, size_t err_len)
{
    axis_system *sys = &sv->ax[axis];
    memcpy(sys->A->x, values, pattern_nnz(sv) * sizeof *values);
    if (!cholmod_factorize(sys->A, sys->L, &sys->cm) || sys->cm.status != CHOLMOD_OK)
        return texopt_fail(err, err_len, TEXOPT_E_NUMERIC,
                           "meshwise: CHOLMOD factorisation failed (status %d, the system is "
                           "not positive definite)",
                           sys->cm.status);
    sys->factorizations++;
    return TEXOPT_OK;
}

/* Solves with the factor of system `sys` for -grad of `axis` and scatters the result into
 * sv->step (fixed vertices: 0). */
static texopt_status solve_axis(solver *sv, int sys_index, int axis, char *err, size_t err_len)
{
    axis_system *sys = &sv->ax[sys_index];
    cholmod_dense *b = cholmod_allocate_dense(sv->unknowns, 1, sv->unknowns, CHOLMOD_REAL, &sys->cm);
    if (!b)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
    double *bx = b->x;
    for (size_t u = 0; u < sv->unknowns; u++)
        bx[u] = -sv->grad[2 * u + axis];
    cholmod_dense *sol = cholmod_solve(CHOLMOD_A, sys->L, b, &sys->cm);
    cholmod_free_dense(&b, &sys->cm);
    if (!sol)
        return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "meshwise: CHOLMOD solve failed");
    const double *sx = sol->x;
    for (size_t v = 0; v < sv->vertex_count; v++) {
        int k = sv->var[v];
        sv->step[2 * v + axis] = k < 0 ? 0.0 : sx[k];
    }
    cholmod_free_dense(&sol, &sys->cm);
    return TEXOPT_OK;
}

/* Factorise-and-solve of one axis with its own fit + barrier matrix; runs in a thread. */
typedef struct axis_job {
    solver *sv;
    int axis;
    texopt_status status;
    char err[256];
} axis_job;

static void *run_axis_job(void *arg)
{
    axis_job *job = arg;
    job->status = factorize(job->sv, job->axis, job->sv->axis_values[job->axis], job->err, sizeof job->err);
    if (job->status == TEXOPT_OK)
        job->status = solve_axis(job->sv, job->axis, job->axis, job->err, sizeof job->err);
    return NULL;
}

/* Both axes with their barrier blocks: the v axis in a second thread when allowed. The two
 * jobs write disjoint entries of sv->step and only read the rest. */
static texopt_status solve_both_axes(solver *sv, char *err, size_t err_len)
{
    axis_job jobs[2] = {{sv, 0, TEXOPT_OK, ""}, {sv, 1, TEXOPT_OK, ""}};
    if (sv->threads > 1)
        texopt_parallel_run(run_axis_job, jobs, sizeof *jobs, 2);
    else
        for (int axis = 0; axis < 2; axis++)
            run_axis_job(&jobs[axis]);
    for (int axis = 0; axis < 2; axis++)
        if (jobs[axis].status != TEXOPT_OK)
            return texopt_fail(err, err_len, jobs[axis].status, "%s", jobs[axis].err);
    return TEXOPT_OK;
}

/* Newton direction -H^-1 grad, per axis, into sv->step. Without an active barrier both axes
 * share the fitting matrix, whose factor is kept across iterations. */
static texopt_status newton_direction(solver *sv, char *err, size_t err_len)
{
    size_t nnz = pattern_nnz(sv);
    for (int axis = 0; axis < 2; axis++)
        memcpy(sv->axis_values[axis], sv->fit_values, nnz * sizeof *sv->fit_values);
    size_t active = gradient_and_barrier(sv);
    texopt_status st = TEXOPT_OK;
    if (active == 0) {
        if (!sv->factor_is_fit && (st = factorize(sv, 0, sv->fit_values, err, err_len)) != TEXOPT_OK)
            return st;
        sv->factor_is_fit = 1;
        for (int axis = 0; axis < 2 && st == TEXOPT_OK; axis++)
            st = solve_axis(sv, 0, axis, err, err_len);
        return st;
    }
    sv->factor_is_fit = 0;
    return solve_both_axes(sv, err, err_len);
}

/* Backtracking from the largest safe step; accepts only a decrease. Returns the step taken. */
static double line_search(solver *sv, double energy)
{
    double slope = 0.0;
    for (size_t v = 0; v < sv->vertex_count; v++) {
        int k = sv->var[v];
        if (k >= 0)
            slope += sv->grad[2 * k] * sv->step[2 * v] + sv->grad[2 * k + 1] * sv->step[2 * v + 1];
    }
    if (!(slope < 0.0))
        return 0.0;
    double t = fmin(1.0, STEP_SAFETY * max_feasible_step(sv, sv->step));
    for (int h = 0; h < MAX_HALVINGS; h++, t *= 0.5) {
        for (size_t i = 0; i < 2 * sv->vertex_count; i++)
            sv->trial[i] = sv->x[i] + t * sv->step[i];
        double fit, bar;
        total_energy(sv, sv->trial, &fit, &bar);
        if (fit + bar <= energy + ARMIJO * t * slope) {
            memcpy(sv->x, sv->trial, 2 * sv->vertex_count * sizeof *sv->x);
            return t;
        }
    }
    return 0.0;
}

/* ---- driver ---------------------------------------------------------------------------- */

static void solver_free(solver *sv)
{
    for (int axis = 0; axis < 2; axis++) {
        axis_system *sys = &sv->ax[axis];
        if (!sys->started)
            continue;
        if (sys->L)
            cholmod_free_factor(&sys->L, &sys->cm);
        if (sys->A)
            cholmod_free_sparse(&sys->A, &sys->cm);
        cholmod_finish(&sys->cm);
    }
    free(sv->tri);
    free(sv->st);
    free(sv->var);
    free(sv->slot);
    free(sv->diag);
    free(sv->fit_values);
    free(sv->axis_values[0]);
    free(sv->axis_values[1]);
    free(sv->x);
    free(sv->trial);
    free(sv->grad);
    free(sv->step);
    free(sv->ties);
    free(sv->rep_of);
    free(sv->chart_of_vertex);
}

static texopt_status check_start(const solver *sv, const double *x, char *err, size_t err_len)
{
    for (size_t i = 0; i < 2 * sv->vertex_count; i++)
        if (!isfinite(x[i]))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "meshwise: starting texel position of vertex %zu is not finite", i / 2);
    for (size_t t = 0; t < sv->tri_count; t++)
        if (sv->tri[t].barrier && !(det2(jacobian(&sv->tri[t], x)) > 0.0))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "meshwise: triangle %zu of the starting layout is flipped or "
                               "collapsed relative to the input",
                               t);
    return TEXOPT_OK;
}

static texopt_status solver_init(solver *sv, const texopt_mesh *mesh, const texopt_triangle_target *targets,
                                 const double *start, const texopt_meshwise_options *opt, char *err, size_t err_len)
{
    memset(sv, 0, sizeof *sv);
    for (int axis = 0; axis < 2; axis++) {
        cholmod_start(&sv->ax[axis].cm);
        sv->ax[axis].started = 1;
        sv->ax[axis].cm.print = 0;
        sv->ax[axis].cm.error_handler = NULL;
    }
    sv->threads = opt && opt->threads > 0 ? opt->threads : 1;
    sv->mesh = mesh;
    sv->scaffold = opt ? opt->scaffold : NULL;
    sv->mesh_tris = mesh->triangle_count;
    sv->mesh_vertices = mesh->vertex_count;
    sv->tri_count = sv->mesh_tris + (sv->scaffold ? sv->scaffold->triangle_count : 0);
    sv->vertex_count = sv->mesh_vertices + (sv->scaffold ? sv->scaffold->vertex_count : 0);
    sv->w_rs = opt && opt->fit_weight > 0.0 ? opt->fit_weight : 1.0;
    sv->w_b = opt && opt->barrier_weight > 0.0 ? opt->barrier_weight : 1.0;
    sv->share = opt ? opt->share : NULL;
    size_t nt = sv->tri_count ? sv->tri_count : 1, nv = sv->vertex_count ? sv->vertex_count : 1;
    sv->tri = calloc(nt, sizeof *sv->tri);
    sv->st = calloc(nt, sizeof *sv->st);
    sv->var = calloc(nv, sizeof *sv->var);
    sv->slot = calloc(9 * nt, sizeof *sv->slot);
    sv->diag = calloc(nv, sizeof *sv->diag);
    sv->x = calloc(2 * nv, sizeof *sv->x);
    sv->trial = calloc(2 * nv, sizeof *sv->trial);
    sv->grad = calloc(2 * nv, sizeof *sv->grad);
    sv->step = calloc(2 * nv, sizeof *sv->step);
    if (!sv->tri || !sv->st || !sv->var || !sv->slot || !sv->diag || !sv->x || !sv->trial || !sv->grad || !sv->step)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory for %zu triangles", sv->tri_count);
    texopt_status st = build_frames(sv, targets, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    normalise_weights(sv);
    memcpy(sv->x, start, 2 * sv->mesh_vertices * sizeof *sv->x);
    if (sv->scaffold && sv->scaffold->vertex_count)
        memcpy(sv->x + 2 * sv->mesh_vertices, sv->scaffold->position, 2 * sv->scaffold->vertex_count * sizeof *sv->x);
    if ((st = check_start(sv, sv->x, err, err_len)) != TEXOPT_OK)
        return st;
    if ((st = number_unknowns(sv, err, err_len)) != TEXOPT_OK)
        return st;
    if (sv->unknowns == 0)
        return TEXOPT_OK;
    if ((st = find_fold_ties(sv, err, err_len)) != TEXOPT_OK)
        return st;
    if ((st = add_collapse_ties(sv, err, err_len)) != TEXOPT_OK)
        return st;
    if ((st = add_shared_ties(sv, err, err_len)) != TEXOPT_OK)
        return st;
    if ((st = build_pattern(sv, err, err_len)) != TEXOPT_OK)
        return st;
    size_t nnz = pattern_nnz(sv);
    sv->fit_values = malloc(nnz * sizeof *sv->fit_values);
    sv->axis_values[0] = malloc(nnz * sizeof *sv->fit_values);
    sv->axis_values[1] = malloc(nnz * sizeof *sv->fit_values);
    if (!sv->fit_values || !sv->axis_values[0] || !sv->axis_values[1])
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "meshwise: out of memory");
    build_fit_hessian(sv);
    return analyse(sv, err, err_len);
}

static double seconds_since(const struct timespec *start)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)(now.tv_sec - start->tv_sec) + 1e-9 * (double)(now.tv_nsec - start->tv_nsec);
}

static void report_progress(const texopt_monitor *monitor, int iteration, int max_iterations)
{
    texopt_progress p = {0};
    p.stage = "stage2";
    p.stage_fraction = (double)iteration / (double)max_iterations;
    p.fraction = p.stage_fraction;
    p.eta_seconds = -1.0;
    texopt_monitor_report(monitor, &p);
}

static int is_finite_layout(const double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i]))
            return 0;
    return 1;
}

/* The local-global loop; fills the report's energy trace. */
static texopt_status iterate(solver *sv, int max_iterations, double tolerance, texopt_meshwise_report *rep,
                             const texopt_monitor *monitor, char *err, size_t err_len)
{
    double fit, bar;
    initial_state(sv, sv->x);
    local_step(sv, sv->x);
    total_energy(sv, sv->x, &fit, &bar);
    rep->energy_initial = fit + bar;
    double energy = fit + bar;
    for (int it = 0; it < max_iterations; it++) {
        if (texopt_monitor_canceled(monitor))
            return texopt_fail(err, err_len, TEXOPT_E_CANCELED, "meshwise: canceled at iteration %d", it);
        if (it > 0) {
            local_step(sv, sv->x);
            total_energy(sv, sv->x, &fit, &bar);
        }
        double before = fit + bar;
        if (sv->unknowns > 0) {
            texopt_status st = newton_direction(sv, err, err_len);
            if (st != TEXOPT_OK)
                return st;
            line_search(sv, before);
        }
        if (!is_finite_layout(sv->x, 2 * sv->vertex_count))
            return texopt_fail(err, err_len, TEXOPT_E_NUMERIC, "meshwise: non-finite texel position at iteration %d",
                               it);
        total_energy(sv, sv->x, &fit, &bar);
        if (fit < bar) { /* eq. 28 */
            bar /= BARRIER_REDUCTION;
            sv->w_b /= BARRIER_REDUCTION;
        }
        double previous = energy;
        energy = fit + bar;
        if (rep->energy_count < TEXOPT_MESHWISE_MAX_REPORTED)
            rep->energy[rep->energy_count++] = energy;
        rep->iterations = it + 1;
        report_progress(monitor, it + 1, max_iterations);
        if (fabs(previous - energy) <= tolerance * fmax(previous, 1e-300))
            break;
    }
    rep->energy_final = energy;
    return TEXOPT_OK;
}

texopt_status texopt_meshwise_solve(const texopt_mesh *mesh, const texopt_triangle_target *targets,
                                    const double *initial_texel, const texopt_meshwise_options *opt, double *texel_out,
                                    texopt_meshwise_report *report, const texopt_monitor *monitor, char *err,
                                    size_t err_len)
{
    if (!mesh || !targets || !texel_out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "meshwise: NULL mesh, targets or output");
    if (!mesh->texel || (mesh->triangle_count && (!mesh->triangle || !mesh->flags || !mesh->chart_of)))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "meshwise: the mesh lacks texels, triangles, flags or charts");
    if (opt && (opt->max_iterations < 0 || opt->tolerance < 0.0 || opt->barrier_weight < 0.0 || opt->fit_weight < 0.0 ||
                opt->threads < 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "meshwise: negative option (iterations, tolerance, weights or threads)");
    if (opt && opt->share && opt->share->chart_count != mesh->chart_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "meshwise: sharing groups of %zu charts for a mesh of %zu", opt->share->chart_count,
                           mesh->chart_count);
    const texopt_meshwise_scaffold *sc = opt ? opt->scaffold : NULL;
    if (sc && ((sc->triangle_count && (!sc->triangle || !sc->rest)) || (sc->vertex_count && !sc->position) ||
               !(sc->weight > 0.0) || !isfinite(sc->weight)))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "meshwise: scaffold without triangles, rest shapes, positions or a positive weight");
    int max_iterations = opt && opt->max_iterations > 0 ? opt->max_iterations : 50;
    double tolerance = opt && opt->tolerance > 0.0 ? opt->tolerance : 1e-4;

    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    texopt_meshwise_report rep;
    memset(&rep, 0, sizeof rep);

    solver sv;
    texopt_status st = solver_init(&sv, mesh, targets, initial_texel ? initial_texel : mesh->texel, opt, err, err_len);
    if (st == TEXOPT_OK)
        st = iterate(&sv, max_iterations, tolerance, &rep, monitor, err, err_len);
    if (st == TEXOPT_OK) {
        rep.flipped = (int)texopt_count_flipped(mesh, sv.x);
        if (rep.flipped > 0)
            st = texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "meshwise: %d triangles flipped despite the barrier",
                             rep.flipped);
    }
    if (st == TEXOPT_OK) {
        memcpy(texel_out, sv.x, 2 * mesh->vertex_count * sizeof *texel_out);
        rep.barrier_weight_final = sv.w_b;
        rep.factorizations = sv.ax[0].factorizations + sv.ax[1].factorizations;
        rep.fold_ties = (int)(sv.tie_count - sv.shared_ties - sv.collapse_ties);
        rep.collapse_ties = (int)sv.collapse_ties;
        rep.shared_ties = (int)sv.shared_ties;
        for (size_t v = 0; v < mesh->vertex_count && sv.rep_of; v++)
            rep.merged_vertices += sv.rep_of[v] != v;
        rep.seconds = seconds_since(&start);
        if (report)
            *report = rep;
    }
    solver_free(&sv);
    return st;
}
