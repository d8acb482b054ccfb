/* Tests of tests/support/fixtures.c: the texture patterns other tests rely on have the
 * documented values, and every fixture model is well formed. */
#include <string.h>

#include "fixtures.h"
#include "test.h"

static const float *px(const texopt_image *img, int x, int y)
{
    return texopt_image_at(img, x, y);
}

TEST(patterns_have_their_documented_values)
{
    texopt_image img;
    CHECK_OK(texopt_image_create(&img, 64, 32, 3, NULL, 0), "image");
    CHECK_EQ_INT(fixture_fill_pattern(&img, "flat"), 0);
    CHECK_NEAR(px(&img, 63, 31)[0], 0.6, 1e-7);
    CHECK_NEAR(px(&img, 0, 0)[2], 0.2, 1e-7);

    CHECK_EQ_INT(fixture_fill_pattern(&img, "stripes0"), 0);
    CHECK_NEAR(px(&img, 3, 5)[0], 0, 0);  /* x / 4 even: black */
    CHECK_NEAR(px(&img, 4, 5)[0], 1, 0);  /* next stripe: white */
    CHECK_NEAR(px(&img, 8, 30)[1], 0, 0); /* period 8, constant along y */

    CHECK_EQ_INT(fixture_fill_pattern(&img, "stripes45"), 0);
    CHECK_NEAR(px(&img, 2, 1)[0], 0, 0); /* (x + y) / 4 = 0 */
    CHECK_NEAR(px(&img, 2, 2)[0], 1, 0); /* (x + y) / 4 = 1 */

    CHECK_EQ_INT(fixture_fill_pattern(&img, "checker"), 0);
    CHECK_NEAR(px(&img, 0, 0)[0], 0, 0); /* squares 8 x 4 texels */
    CHECK_NEAR(px(&img, 8, 0)[0], 1, 0);
    CHECK_NEAR(px(&img, 0, 4)[0], 1, 0);
    CHECK_NEAR(px(&img, 8, 4)[0], 0, 0);

    CHECK_EQ_INT(fixture_fill_pattern(&img, "gradient"), 0);
    CHECK_NEAR(px(&img, 0, 0)[0], 0.5 / 64, 1e-7);
    CHECK_NEAR(px(&img, 63, 31)[1], 31.5 / 32, 1e-7);
    CHECK_NEAR(px(&img, 10, 10)[2], 0.25, 0);

    CHECK_EQ_INT(fixture_fill_pattern(&img, "half"), 0);
    int ink = 0, paper = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++) {
            const float *p = px(&img, x, y);
            if (x < 32) {
                CHECK_NEAR(p[0], 0.6, 1e-7);
                continue;
            }
            CHECK(p[0] == 0 || p[0] == 1);
            ink += p[0] == 0;
            paper += p[0] == 1;
        }
    /* text-like: a real share of ink, mostly paper */
    CHECK(ink > 32 * 32 / 10);
    CHECK(paper > ink);

    CHECK_EQ_INT(fixture_fill_pattern(&img, "nope"), -1);
    texopt_image_destroy(&img);
    CHECK_OK(texopt_image_create(&img, 4, 4, 1, NULL, 0), "image");
    CHECK_EQ_INT(fixture_fill_pattern(&img, "flat"), -1); /* needs 3 channels */
    texopt_image_destroy(&img);
}

TEST(fixture_models_are_well_formed)
{
    texopt_model *models[4] = {fixture_textured_quad(16, "half"), fixture_grid(3, 16, "gradient"),
                               fixture_cube_with_seams(16), fixture_uv_sphere(6, 4, 16)};
    for (int k = 0; k < 4; k++) {
        texopt_model *m = models[k];
        CHECK(m != NULL);
        CHECK_EQ_INT(m->domain_count, 1);
        CHECK_EQ_INT(m->primitives[0].domain, 0);
        CHECK_EQ_INT(m->domains[0].width, 16);
        CHECK(m->domains[0].wrap_s == TEXOPT_WRAP_REPEAT);
        CHECK_EQ_INT(m->images[0].channels, 3);
        CHECK(m->image_names[0] != NULL && strncmp(m->image_names[0], "fixture_", 8) == 0);
        for (size_t i = 0; i < 3 * m->triangle_count; i++)
            CHECK(m->triangles[i] < m->vertex_count);
        for (size_t t = 0; t < m->triangle_count; t++) { /* positive UV orientation */
            const uint32_t *v = m->triangles + 3 * t;
            const float *a = m->uvs + 2 * v[0], *b = m->uvs + 2 * v[1], *c = m->uvs + 2 * v[2];
            CHECK((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0);
        }
        texopt_model_destroy(m);
        models[k] = NULL;
    }
    CHECK(fixture_grid(0, 16, "flat") == NULL);
    CHECK(fixture_uv_sphere(2, 4, 16) == NULL);
    CHECK(fixture_textured_quad(16, "unknown") == NULL);
    CHECK(fixture_textured_quad(0, "flat") == NULL);
}
