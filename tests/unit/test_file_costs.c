/* Tests that a job's statistics report the costs of the file it wrote, as `texopt info`
 * measures them (file_cost.h), for every method on generated fixtures: a grid, and grids
 * with a strip of zero-area UV triangles, alone and as mirrored twins (sliver_grids.h), whose
 * triangles the budget once left out while info on the file counted them. */
#include "file_cost_checks.h"
#include "sliver_grids.h"
#include "test.h"

static void check_fixture(int twins, double strip_height)
{
    sliver_grid g;
    scratch s;
    CHECK(sliver_grid_make(&g, 16, strip_height, twins) == 0);
    CHECK(scratch_init(&s, 0, 0, NULL) == 0);
    CHECK(write_mesh_glb(s.in, g.positions, g.uvs, g.vertex_count, g.triangles, g.triangle_count, 128, "half", NULL) ==
          0);
    for (size_t m = 0; m < sizeof file_cost_methods / sizeof *file_cost_methods; m++) {
        char why[512];
        CHECK_MSG(stats_match_file(s.in, file_cost_methods[m], 0.4, why, sizeof why) == 0, "%s", why);
    }
    scratch_free(&s);
    sliver_grid_free(&g);
}

TEST(statistics_equal_info_on_the_file_for_a_zero_area_strip)
{
    check_fixture(0, 0.0);
}

TEST(statistics_equal_info_on_the_file_for_mirrored_twins)
{
    check_fixture(1, 0.0);
}

TEST(statistics_equal_info_on_the_file_for_a_plain_grid)
{
    scratch s;
    CHECK(scratch_init(&s, 12, 64, "checker") == 0);
    for (size_t m = 0; m < sizeof file_cost_methods / sizeof *file_cost_methods; m++) {
        char why[512];
        CHECK_MSG(stats_match_file(s.in, file_cost_methods[m], 0.3, why, sizeof why) == 0, "%s", why);
    }
    scratch_free(&s);
}
