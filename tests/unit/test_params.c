/* Tests of params.c and status.c: defaults, range checks and messages. */
#include <string.h>

#include "params.h"
#include "status.h"
#include "test.h"

TEST(zero_params_resolve_to_paper_defaults)
{
    texopt_params p = {0};
    texopt_params_resolve(&p);
    CHECK_NEAR(p.epsilon, TEXOPT_DEFAULT_EPSILON, 0);
    CHECK_EQ_INT(p.iterations, 100);
    CHECK_NEAR(p.relative_cost, 1.0, 0);
    CHECK(p.method == TEXOPT_METHOD_PERCEPTUAL);
    CHECK_EQ_INT(p.refinements, TEXOPT_DEFAULT_REFINEMENTS);
    CHECK_NEAR(p.hessian_floor, TEXOPT_DEFAULT_HESSIAN_FLOOR, 0);
    CHECK_EQ_INT(p.metric_candidates, 1);
    CHECK_EQ_INT(p.resize_check, 1);
    char err[128] = "";
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
    texopt_params paper = {.method = TEXOPT_METHOD_PAPER};
    texopt_params_resolve(&paper);
    CHECK_NEAR(paper.epsilon, TEXOPT_PAPER_EPSILON, 0); /* the paper's own */
    paper.epsilon = 0.05;
    texopt_params_resolve(&paper);
    CHECK_NEAR(paper.epsilon, 0.05, 0);
}

/* New charts are solved with scaffolds: stage 2 alone runs them over themselves. */
TEST(new_charts_resolve_to_a_bijective_stage_2)
{
    texopt_params p = {.charts = TEXOPT_CHARTS_NEW};
    texopt_params_resolve(&p);
    CHECK_EQ_INT(p.bijective, 1);
    texopt_params keep = {0};
    texopt_params_resolve(&keep);
    CHECK_EQ_INT(keep.bijective, 0);
}

/* A packing-efficiency bound is the refinement's: giving one turns it on, and the refinement
 * without one holds the paper's. */
TEST(a_packing_efficiency_bound_is_the_refinements)
{
    texopt_params bound = {.packing_efficiency = 0.7};
    texopt_params_resolve(&bound);
    CHECK_EQ_INT(bound.packing_refine, 1);
    CHECK_NEAR(bound.packing_efficiency, 0.7, 0);
    texopt_params refine = {.packing_refine = 1};
    texopt_params_resolve(&refine);
    CHECK_NEAR(refine.packing_efficiency, TEXOPT_DEFAULT_PACKING_EFFICIENCY, 0);
    texopt_params plain = {0};
    texopt_params_resolve(&plain);
    CHECK_EQ_INT(plain.packing_refine, 0);
    CHECK_NEAR(plain.packing_efficiency, 0, 0);
}

/* The Hessian floor as users give it: 0 is none, which the field encodes as -1. */
TEST(the_hessian_floor_as_users_give_it)
{
    texopt_params p = {0};
    texopt_params_resolve(&p);
    CHECK_NEAR(texopt_params_hessian_floor(&p), TEXOPT_DEFAULT_HESSIAN_FLOOR, 0);
    texopt_params_set_hessian_floor(&p, 0);
    CHECK_NEAR(p.hessian_floor, -1, 0);
    CHECK_NEAR(texopt_params_hessian_floor(&p), 0, 0);
    texopt_params_resolve(&p); /* none stays none */
    CHECK_NEAR(p.hessian_floor, -1, 0);
    texopt_params_set_hessian_floor(&p, 0.75);
    CHECK_NEAR(texopt_params_hessian_floor(&p), 0.75, 0);
    char err[128] = "";
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
}

TEST(out_of_range_fields_are_named)
{
    texopt_params p = {0};
    texopt_params_resolve(&p);
    p.epsilon = 2;
    char err[128] = "";
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "epsilon") != NULL);
    p.epsilon = 0.01;
    p.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    p.texture_width = 0;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "texture_size") != NULL);
    p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    p.refinements = -1; /* none: valid */
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
    p.refinements = -2;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "refinements") != NULL);
    p.refinements = 0;
    p.packing_efficiency = 1; /* a packing cannot be that tight */
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "packing_efficiency") != NULL);
    p.packing_efficiency = NAN;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    p.packing_efficiency = 0;
    p.hessian_floor = -1; /* none: valid */
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
    p.hessian_floor = 1.5;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "hessian_floor") != NULL);
    p.hessian_floor = -0.5;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    p.hessian_floor = -1;
    p.metric_candidates = -1; /* not made: valid */
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
    p.metric_candidates = 2;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "metric_candidates") != NULL);
    p.metric_candidates = 1;
    p.resize_check = -1; /* never: valid */
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
    p.resize_check = 3;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "resize_check") != NULL);
    p.resize_check = 1;
    p.refine_lit = -1; /* base colour: valid */
    CHECK_OK(texopt_params_validate(&p, err, sizeof err), err);
    p.refine_lit = 2;
    CHECK(texopt_params_validate(&p, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "refine_lit") != NULL);
}

TEST(refinement_rounds_count_as_users_do)
{
    texopt_params p = {0};
    texopt_params_resolve(&p);
    CHECK_EQ_INT(texopt_params_refinement_rounds(&p), TEXOPT_DEFAULT_REFINEMENTS);
    texopt_params_set_refinement_rounds(&p, 0);
    CHECK_EQ_INT(p.refinements, -1); /* none, not "default" */
    CHECK_EQ_INT(texopt_params_refinement_rounds(&p), 0);
    texopt_params_set_refinement_rounds(&p, 3);
    CHECK_EQ_INT(texopt_params_refinement_rounds(&p), 3);
}

TEST(method_names_round_trip)
{
    for (int m = 0; m < TEXOPT_METHOD_COUNT; m++)
        CHECK_EQ_INT(texopt_method_from_name(texopt_method_name((texopt_method)m)), m);
    CHECK(texopt_method_from_name("bogus") == TEXOPT_METHOD_COUNT);
}

TEST(lookup_names_round_trip)
{
    CHECK(strcmp(texopt_lookup_name(0), "bilinear") == 0);
    CHECK(strcmp(texopt_lookup_name(1), "mipmapped") == 0);
    for (int mip = 0; mip <= 1; mip++)
        CHECK_EQ_INT(texopt_lookup_from_name(texopt_lookup_name(mip)), mip);
    CHECK_EQ_INT(texopt_lookup_from_name("trilinear"), -1);
    CHECK_EQ_INT(texopt_lookup_from_name(NULL), -1);
}

TEST(strerror_names_every_status)
{
    for (int s = 0; s < TEXOPT_STATUS_COUNT; s++)
        CHECK(strcmp(texopt_strerror((texopt_status)s), "unknown status") != 0);
    char err[8];
    CHECK(texopt_fail(err, sizeof err, TEXOPT_E_IO, "%s", "truncated message") == TEXOPT_E_IO);
    CHECK_EQ_INT(strlen(err), 7);
}
