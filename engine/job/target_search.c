/* target_search.c - the smallest relative cost whose loss meets a target (target_search.h). */
#include "target_search.h"

#include <math.h>

texopt_status texopt_search_target_loss(texopt_loss_at_cost_fn loss_at, void *user, double target, double cost_min,
                                        double cost_max, double tolerance, int max_evaluations,
                                        texopt_target_search *out, char *err, size_t err_len)
{
    if (!loss_at || !out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "target search: missing callback or result");
    if (!(target > 0) || !(cost_min > 0 && cost_min < cost_max && cost_max <= 4))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "target search: target %g and cost range [%g, %g] must be positive, "
                           "increasing and at most 4",
                           target, cost_min, cost_max);
    if (tolerance <= 0)
        tolerance = 0.05;
    if (max_evaluations <= 0)
        max_evaluations = 12;
    texopt_target_search s = {.relative_cost = cost_max, .q = NAN};
    double q = 0;
    texopt_status st = loss_at(user, cost_max, &q, err, err_len);
    s.evaluations = 1;
    if (st != TEXOPT_OK)
        return st;
    s.q = q;
    s.reached = q <= target;
    /* Invariant: hi meets the target (s holds it), lo does not or is the untested floor. */
    double lo = cost_min, hi = cost_max;
    int lo_tested = 0;
    while (s.reached && s.evaluations < max_evaluations) {
        if (lo_tested && hi / lo <= 1 + tolerance)
            break;
        double mid = lo_tested ? sqrt(lo * hi) : lo;
        st = loss_at(user, mid, &q, err, err_len);
        s.evaluations++;
        if (st != TEXOPT_OK)
            return st;
        if (q <= target) {
            hi = mid;
            s.relative_cost = mid;
            s.q = q;
            if (!lo_tested)
                break; /* even the floor is good enough */
        } else {
            lo = mid;
            lo_tested = 1;
            s.cost_below = mid;
            s.q_below = q;
        }
    }
    *out = s;
    return TEXOPT_OK;
}
