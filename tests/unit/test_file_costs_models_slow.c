/* Tests that a job's statistics report the costs of the file it wrote, as `texopt info`
 * measures them (file_cost.h), for every method on the small models of tests/data. */
#include "file_cost_checks.h"
#include "test.h"

static void check_model(const char *name)
{
    char in[512];
    snprintf(in, sizeof in, "%s/%s", TEXOPT_TEST_DATA_DIR, name);
    for (size_t m = 0; m < sizeof file_cost_methods / sizeof *file_cost_methods; m++) {
        char why[512];
        CHECK_MSG(stats_match_file(in, file_cost_methods[m], 0.3, why, sizeof why) == 0, "%s", why);
    }
}

TEST(statistics_equal_info_on_spot)
{
    check_model("spot/spot.glb");
}

TEST(statistics_equal_info_on_fox)
{
    check_model("Fox/Fox.glb");
}
