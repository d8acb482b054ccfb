/* allocate.c - water-filling of the per-triangle targets to a texel budget (allocate.h).
 *
 * The allocated area A(s) = sum a_i min(cap, s l1_i) min(cap, s l2_i) (lossless targets
 * with s^growth in place of s) is continuous and non-decreasing in s, so s is found by
 * bisection on log s.
 * Does not: look at the texture, the loss curve of a triangle beyond its stage-1 loss, or
 * the layout. */
#include "allocate.h"

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
        double a = fabs(mesh->area_texel[t]);
        if (lossless(opt, &in[t])) {
            double g = pow(s, opt->lossless_growth);
            sum += a * capped(g, in[t].lambda1, cap_of(opt)) * capped(g, in[t].lambda2, cap_of(opt));
        } else
            sum += a * capped(s, in[t].lambda1, cap_of(opt)) * capped(s, in[t].lambda2, cap_of(opt));
    }
    return sum;
}

static texopt_status check_targets(const texopt_mesh *mesh, const texopt_triangle_target *in,
                                   double *lambda_min, char *err, size_t err_len)
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

/* The factor s in [lo, hi] whose area is the request (bisection on log s). */
static double solve_scale(const texopt_mesh *mesh, const texopt_triangle_target *in, double request,
                          double lo, double hi, const texopt_allocate_options *opt)
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

texopt_status texopt_allocate_targets(const texopt_mesh *mesh, const texopt_triangle_target *in,
                                      double area_requested, const texopt_allocate_options *opt,
                                      texopt_triangle_target *out, texopt_allocation *report,
                                      char *err, size_t err_len)
{
    if (!mesh || !in || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "allocate: missing mesh or targets");
    if (!(area_requested > 0) || !isfinite(area_requested))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "allocate: requested area %g must be positive",
                           area_requested);
    double lambda_min;
    texopt_status st = check_targets(mesh, in, &lambda_min, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    /* Lossless targets alone may already exceed a small request: then everything scales. */
    double cap = cap_of(opt);
    texopt_allocate_options none = {0, 0, cap, 0};
    if (opt && opt->slow_lossless && area_at(mesh, in, 1e-9, opt) >= area_requested)
        opt = &none;
    /* Past cap / lambda_min every singular value is capped: the area cannot grow further. */
    double s = solve_scale(mesh, in, area_requested, 1e-6, cap / lambda_min, opt);
    texopt_allocation rep = {.scale = s, .area_requested = area_requested};
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        texopt_triangle_target tt = in[t];
        if (counted(mesh, t)) {
            double a = fabs(mesh->area_texel[t]);
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
