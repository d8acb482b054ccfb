/* test_pipeline_budget_slow.c - the per-budget checks of test_pipeline_budget.c on the
 * perceptual method (stage 1 runs, too slow for the sanitizer build): one job writing two
 * budgets equals separate runs, and target_loss finds the smallest cost meeting its target
 * (checked against independent runs at that cost and one search step below). */
#include "pipeline_budget_checks.h"

TEST(perceptual_job_writes_each_budget_as_a_separate_run_would)
{
    check_job_reuse(TEXOPT_METHOD_PERCEPTUAL);
}

TEST(perceptual_target_loss_finds_the_smallest_cost_meeting_the_target)
{
    check_target_loss(TEXOPT_METHOD_PERCEPTUAL, 0.08);
}
