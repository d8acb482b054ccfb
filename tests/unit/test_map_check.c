/* test_map_check.c - the measures of every map (map_check.h): which a domain is shown by,
 * their q, and the per-map rule against a resize (a loss on any map keeps the resize, the map
 * with the worst ratio decides). Generated grids (grid_glb.h). */
#include <math.h>
#include <string.h>

#include "map_check.h"
#include "pipeline_scratch.h"
#include "test.h"

/* q values for the rule: base colour and emissive measured. */
static void two_maps(texopt_map_q *q, double base, double emissive)
{
    memset(q, 0, sizeof *q);
    q->measured[TEXOPT_SLOT_BASE_COLOR] = q->measured[TEXOPT_SLOT_EMISSIVE] = 1;
    q->q[TEXOPT_SLOT_BASE_COLOR] = base;
    q->q[TEXOPT_SLOT_EMISSIVE] = emissive;
}

TEST(a_loss_on_any_map_keeps_the_resize_and_names_that_map)
{
    texopt_map_q layout, resize;
    int by = -1;
    two_maps(&layout, 0.001, 0.004);
    two_maps(&resize, 0.010, 0.002);
    CHECK(!texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_SLOT_EMISSIVE);
    two_maps(&layout, 0.001, 0.0019);
    CHECK(texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_SLOT_EMISSIVE); /* 0.95, the closest call */
    two_maps(&layout, 0.0099, 0.001);
    CHECK(texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_SLOT_BASE_COLOR);
}

TEST(equal_maps_keep_the_resize_and_a_loss_over_zero_decides)
{
    texopt_map_q layout, resize;
    int by = -1;
    two_maps(&layout, 0, 0);
    two_maps(&resize, 0, 0);
    CHECK(!texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_SLOT_BASE_COLOR);
    two_maps(&layout, 0, 0.001); /* flat base colour: only emissive differs */
    CHECK(!texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_SLOT_EMISSIVE);
    two_maps(&resize, 0, 0.002);
    CHECK(texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_SLOT_EMISSIVE);
    layout.measured[TEXOPT_MAP_LIT] = resize.measured[TEXOPT_MAP_LIT] = 1;
    layout.q[TEXOPT_MAP_LIT] = 0.003;
    resize.q[TEXOPT_MAP_LIT] = 0.002;
    CHECK(!texopt_map_layout_wins(&layout, &resize, &by));
    CHECK(by == TEXOPT_MAP_LIT);
    CHECK(strcmp(texopt_map_measure_name(by), "lit") == 0);
    CHECK(strcmp(texopt_map_measure_name(TEXOPT_SLOT_EMISSIVE), "emissive") == 0);
}

/* Two primitives on one grid: material 0 binds base colour and emissive, material 1 base
 * colour only; with the emissive map's pattern. */
static int write_emissive_grid(const char *path, const char *base, const char *emissive)
{
    const char *patterns[2] = {base, emissive};
    return write_grid_glb_material(path, 4, 32, patterns, 2,
                                   "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
                                   "\"emissiveTexture\":{\"index\":1},\"emissiveFactor\":[1,1,1]}");
}

TEST(the_measures_are_the_bound_maps_and_lit)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 32, NULL) == 0);
    CHECK(write_emissive_grid(s.in, "flat", "half") == 0);
    texopt_model *m = load(s.in);
    CHECK(m != NULL);
    int measured[TEXOPT_MAP_MEASURES];
    texopt_map_measures(m, -1, measured);
    for (int k = 0; k < TEXOPT_MAP_MEASURES; k++)
        CHECK_MSG(measured[k] == (k == TEXOPT_SLOT_BASE_COLOR || k == TEXOPT_SLOT_EMISSIVE || k == TEXOPT_MAP_LIT),
                  "measure %s", texopt_map_measure_name(k));
    texopt_map_measures(m, 0, measured);
    CHECK(measured[TEXOPT_SLOT_EMISSIVE] && measured[TEXOPT_MAP_LIT] && !measured[TEXOPT_SLOT_NORMAL]);
    texopt_model_destroy(m);
    CHECK(write_grid_glb(s.in, 4, 32, "half") == 0);
    CHECK((m = load(s.in)) != NULL);
    texopt_map_measures(m, -1, measured);
    for (int k = 0; k < TEXOPT_MAP_MEASURES; k++)
        CHECK(measured[k] == (k == TEXOPT_SLOT_BASE_COLOR));
    texopt_model_destroy(m);
    scratch_free(&s);
}

/* The input against itself is 0 on every measure; a copy whose emissive map is blanked is
 * above 0 on emissive and lit and still 0 on base colour, which it did not touch. */
TEST(each_map_is_measured_on_its_own)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 32, NULL) == 0);
    CHECK(write_emissive_grid(s.in, "flat", "half") == 0);
    texopt_model *m = load(s.in);
    CHECK(m != NULL && m->image_count == 2);
    int measured[TEXOPT_MAP_MEASURES];
    texopt_map_measures(m, -1, measured);
    texopt_model blank = *m;
    texopt_image images[2] = {m->images[0], m->images[1]};
    char err[256];
    CHECK(texopt_image_create(&images[1], m->images[1].width, m->images[1].height, m->images[1].channels, err,
                              sizeof err) == TEXOPT_OK);
    blank.images = images;
    blank.document = NULL;
    blank.destroy_document = NULL;
    const texopt_model *cands[2] = {m, &blank};
    texopt_evaluate_options opt = {0};
    opt.resolution = 96;
    texopt_map_q q[2];
    CHECK(texopt_map_evaluate(m, cands, 2, &opt, measured, q, err, sizeof err) == TEXOPT_OK);
    for (int k = 0; k < TEXOPT_MAP_MEASURES; k++)
        if (measured[k])
            CHECK(q[0].q[k] == 0);
    printf("  blanked emissive: base %.5f emissive %.5f lit %.5f\n", q[1].q[TEXOPT_SLOT_BASE_COLOR],
           q[1].q[TEXOPT_SLOT_EMISSIVE], q[1].q[TEXOPT_MAP_LIT]);
    CHECK(q[1].q[TEXOPT_SLOT_BASE_COLOR] == 0);
    CHECK(q[1].q[TEXOPT_SLOT_EMISSIVE] > 0.01 && q[1].q[TEXOPT_MAP_LIT] > 0);
    int by = -1;
    CHECK(texopt_map_layout_wins(&q[0], &q[1], &by) && by == TEXOPT_SLOT_EMISSIVE);
    CHECK(!texopt_map_layout_wins(&q[1], &q[0], &by) && by == TEXOPT_SLOT_EMISSIVE);
    texopt_image_destroy(&images[1]);
    texopt_model_destroy(m);
    scratch_free(&s);
}
