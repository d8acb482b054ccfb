/* target_search.h - the smallest relative cost whose loss meets a target.
 *
 * Does: the target_loss budget's search (TEXOPT_BUDGET_TARGET_LOSS; DESIGN.md 3.4 "a target
 * whole-mesh loss"): the smallest relative cost whose q is at most a target, by bisection on
 * log(c_r) assuming q falls as the cost grows (q changes by similar amounts per halving of the
 * cost, not per fixed step). It takes a callback "q at this cost", so the job answers it
 * without re-running the stages that do not depend on the budget (loss_search.h). Does not:
 * lay out or evaluate anything itself. */
#ifndef TEXOPT_TARGET_SEARCH_H
#define TEXOPT_TARGET_SEARCH_H

#include <stddef.h>

#include "status.h"

/* q at relative cost c (run the layout at that budget, evaluate it); non-OK stops the search. */
typedef texopt_status (*texopt_loss_at_cost_fn)(void *user, double relative_cost, double *q, char *err, size_t err_len);

typedef struct texopt_target_search {
    double relative_cost; /* smallest cost found with q <= target (or cost_max if none) */
    double q;             /* q at that cost */
    int reached;          /* 0 when even cost_max has q > target */
    int evaluations;      /* calls of the callback */
    double cost_below;    /* the largest cost tried whose q missed the target, 0 when none
                             was (the floor met it, or the search stopped at cost_max) */
    double q_below;       /* q at cost_below */
} texopt_target_search;

/* Bisection on log(c_r) in [cost_min, cost_max] (0 < cost_min < cost_max <= 4) until the
 * bracket's ratio is below 1 + tolerance (tolerance 0 -> 0.05) or max_evaluations (0 -> 12)
 * calls were made. Evaluates cost_max first: when it misses the target the search stops
 * with reached = 0. */
texopt_status texopt_search_target_loss(texopt_loss_at_cost_fn loss_at, void *user, double target, double cost_min,
                                        double cost_max, double tolerance, int max_evaluations,
                                        texopt_target_search *out, char *err, size_t err_len);

#endif
