/* target_allocation.c - water-filling of the per-triangle targets to a texel budget (target_allocation.h).
 *
 * The allocated area A(s) = sum a_i min(cap, s l1_i) min(cap, s l2_i) (lossless targets
 * with s^growth in place of s) is continuous and non-decreasing in s, so s is found by
 * bisection on log s.
 * texopt_reallocate_by_error multiplies each target's area by a step from its on-screen
 * error and rescales with the same water-filling; the error of the one-ring instead of the
 * triangle's own measured worse on Fox (BENCHMARKS.md@9f788a8 "Quality").
 * Does not: look at the texture, the loss curve of a triangle beyond its stage-1 loss, or
 * the layout; measure the errors (evaluate.h does). */
#include "target_allocation.h"

#include <math.h>
#include <string.h>

static int counted(const texopt_mesh *mesh, size_t t)
{
    return !(mesh->flags[t] & (TEXOPT_TRI_DEGENERATE_3D | TEXOPT_TRI_DEGENERATE_UV));
}

static int lossless(const texopt_allocate_options *opt, const texopt_triangle_target *t)
{
    return opt && opt->slow_lossless && t->loss <= opt->lossless_loss;
}

static double cap_of(const texopt_allocate_options *opt)
{
    return opt && opt->cap > 0 ? opt->cap : 1;
}

/* What triangle t's texels cost in the budget at the input's density. */
static double paid_area(const texopt_mesh *mesh, size_t t, const texopt_allocate_options *opt)
{
    double a = fabs(mesh->area_texel[t]);
    return opt && opt->paid ? opt->paid[t] * a : a;
}

double texopt_targets_area(const texopt_mesh *mesh, const texopt_triangle_target *targets, const double *paid)
{
    texopt_allocate_options o = {0};
    o.paid = paid;
    double sum = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (counted(mesh, t))
            sum += paid_area(mesh, t, &o) * targets[t].lambda1 * targets[t].lambda2;
    return sum;
}

static double capped(double s, double lambda, double cap)
{
    double v = s * lambda;
    return v < cap ? v : cap;
}

/* Total target area at factor s; `keep` says whether lossless targets stay as they are. */
static double area_at(const texopt_mesh *mesh, const texopt_triangle_target *in, double s,
                      const texopt_allocate_options *opt)
{
    double sum = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!counted(mesh, t))
            continue;
        double a = paid_area(mesh, t, opt);
        if (lossless(opt, &in[t])) {
            double g = pow(s, opt->lossless_growth);
            sum += a * capped(g, in[t].lambda1, cap_of(opt)) * capped(g, in[t].lambda2, cap_of(opt));
        } else
            sum += a * capped(s, in[t].lambda1, cap_of(opt)) * capped(s, in[t].lambda2, cap_of(opt));
    }
    return sum;
}

static texopt_status check_targets(const texopt_mesh *mesh, const texopt_triangle_target *in, double *lambda_min,
                                   char *err, size_t err_len)
{
    *lambda_min = 1;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        if (!counted(mesh, t))
            continue;
        double l1 = in[t].lambda1, l2 = in[t].lambda2;
        if (!(l1 > 0 && l2 > 0 && isfinite(l1) && isfinite(l2)))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "allocate: triangle %zu has singular values %g, %g (must be positive)", t, l1, l2);
        *lambda_min = fmin(*lambda_min, fmin(l1, l2));
    }
    return TEXOPT_OK;
}

static texopt_status check_paid(const texopt_mesh *mesh, const texopt_allocate_options *opt, char *err, size_t err_len)
{
    for (size_t t = 0; opt && opt->paid && t < mesh->triangle_count; t++)
        if (!(opt->paid[t] >= 0 && opt->paid[t] <= 1))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "allocate: triangle %zu pays %g of its texels (must be in [0, 1])", t, opt->paid[t]);
    return TEXOPT_OK;
}

/* The factor s in [lo, hi] whose area is the request (bisection on log s). */
static double solve_scale(const texopt_mesh *mesh, const texopt_triangle_target *in, double request, double lo,
                          double hi, const texopt_allocate_options *opt)
{
    if (area_at(mesh, in, hi, opt) <= request)
        return hi;
    if (area_at(mesh, in, lo, opt) >= request)
        return lo;
    for (int i = 0; i < 100 && hi / lo > 1 + 1e-12; i++) {
        double mid = sqrt(lo * hi);
        if (area_at(mesh, in, mid, opt) < request)
            lo = mid;
        else
            hi = mid;
    }
    return sqrt(lo * hi);
}

texopt_status texopt_allocate_targets(const texopt_mesh *mesh, const texopt_triangle_target *in, double area_requested,
                                      const texopt_allocate_options *opt, texopt_triangle_target *out,
                                      texopt_allocation *report, char *err, size_t err_len)
{
    if (!mesh || !in || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "allocate: missing mesh or targets");
    if (!(area_requested > 0) || !isfinite(area_requested))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "allocate: requested area %g must be positive",
                           area_requested);
    double lambda_min;
    texopt_status st = check_targets(mesh, in, &lambda_min, err, err_len);
    if (st == TEXOPT_OK)
        st = check_paid(mesh, opt, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    /* Lossless targets alone may already exceed a small request: then everything scales. */
    double cap = cap_of(opt);
    texopt_allocate_options none = {0, 0, cap, 0, opt ? opt->paid : NULL};
    if (opt && opt->slow_lossless && area_at(mesh, in, 1e-9, opt) >= area_requested)
        opt = &none;
    /* Past cap / lambda_min every singular value is capped: the area cannot grow further. */
    double s = solve_scale(mesh, in, area_requested, 1e-6, cap / lambda_min, opt);
    texopt_allocation rep = {.scale = s, .area_requested = area_requested};
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        texopt_triangle_target tt = in[t];
        if (counted(mesh, t)) {
            double a = paid_area(mesh, t, opt);
            rep.area_input += a;
            if (lossless(opt, &tt)) {
                rep.lossless++;
                double g = pow(s, opt->lossless_growth);
                tt.lambda1 = capped(g, tt.lambda1, cap);
                tt.lambda2 = capped(g, tt.lambda2, cap);
            } else {
                rep.capped += s * tt.lambda1 >= cap || s * tt.lambda2 >= cap;
                tt.lambda1 = capped(s, tt.lambda1, cap);
                tt.lambda2 = capped(s, tt.lambda2, cap);
            }
            rep.area_allocated += a * tt.lambda1 * tt.lambda2;
        }
        out[t] = tt;
    }
    if (report)
        *report = rep;
    return TEXOPT_OK;
}

/* Mean of the errors over the counted triangles, weighted by 3D area. */
static double mean_error(const texopt_mesh *mesh, const double *error)
{
    double sum = 0, weight = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (counted(mesh, t)) {
            sum += mesh->area_3d[t] * error[t];
            weight += mesh->area_3d[t];
        }
    return weight > 0 ? sum / weight : 0;
}

static texopt_status check_reallocate(const texopt_mesh *mesh, const double *error,
                                      const texopt_reallocate_options *opt, char *err, size_t err_len)
{
    if (!opt || !(opt->gamma > 0) || !(opt->step_min > 0) || !(opt->step_min <= 1) || !(opt->step_max >= 1) ||
        !isfinite(opt->step_max) || !(opt->cap > 0) || !isfinite(opt->cap))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "reallocate: needs gamma > 0, 0 < step_min <= 1 <= step_max, cap > 0");
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (!(error[t] >= 0) || !isfinite(error[t]))
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                               "reallocate: triangle %zu has error %g (must be finite, >= 0)", t, error[t]);
    return TEXOPT_OK;
}

texopt_status texopt_reallocate_by_error(const texopt_mesh *mesh, const texopt_triangle_target *in, const double *error,
                                         double area_requested, const texopt_reallocate_options *opt,
                                         texopt_triangle_target *out, texopt_allocation *report, char *err,
                                         size_t err_len)
{
    if (!mesh || !in || !error || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "reallocate: missing mesh, targets or errors");
    texopt_status st = check_reallocate(mesh, error, opt, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    double mean = mean_error(mesh, error), floor = 0.05 * mean;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        out[t] = in[t];
        if (!counted(mesh, t) || !(mean > 0))
            continue;
        double m = pow((error[t] + floor) / (mean + floor), opt->gamma);
        m = sqrt(fmin(opt->step_max, fmax(opt->step_min, m)));
        out[t].lambda1 *= m;
        out[t].lambda2 *= m;
    }
    texopt_allocate_options rescale = {0, 0, opt->cap, 0, opt->paid};
    return texopt_allocate_targets(mesh, out, area_requested, &rescale, out, report, err, err_len);
}
