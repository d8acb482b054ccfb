/* test_meshrender.c - the evaluation's cameras and rasteriser (engine/evaluate/meshrender.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "meshrender.h"
#include "sample.h"
#include "test.h"
#include "texture_filter.h"
#include "texture_keys.h"

static double dot(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

TEST(views_are_the_dodecahedron_vertices)
{
    texopt_model *m = fixture_uv_sphere(12, 6, 16);
    CHECK(m);
    texopt_view v[TEXOPT_VIEW_COUNT];
    char err[256] = "";
    CHECK_OK(texopt_meshrender_views(m, v, err, sizeof err), err);
    /* Every vertex of a regular dodecahedron has exactly 3 nearest neighbours, at the angle
     * whose cosine is sqrt(5)/3, and its antipode among the others. */
    const double nearest = sqrt(5.0) / 3.0;
    for (int i = 0; i < TEXOPT_VIEW_COUNT; i++) {
        CHECK_NEAR(dot(v[i].direction, v[i].direction), 1, 1e-12);
        CHECK_NEAR(dot(v[i].right, v[i].right), 1, 1e-12);
        CHECK_NEAR(dot(v[i].up, v[i].up), 1, 1e-12);
        CHECK_NEAR(dot(v[i].right, v[i].up), 0, 1e-12);
        CHECK_NEAR(dot(v[i].right, v[i].direction), 0, 1e-12);
        /* right x up = direction: the camera does not mirror the scene. */
        double c[3] = {v[i].right[1] * v[i].up[2] - v[i].right[2] * v[i].up[1],
                       v[i].right[2] * v[i].up[0] - v[i].right[0] * v[i].up[2],
                       v[i].right[0] * v[i].up[1] - v[i].right[1] * v[i].up[0]};
        CHECK_NEAR(dot(c, v[i].direction), 1, 1e-12);
        int near = 0, antipode = 0;
        double best = -2;
        for (int j = 0; j < TEXOPT_VIEW_COUNT; j++) {
            if (j == i)
                continue;
            double d = dot(v[i].direction, v[j].direction);
            CHECK(d < nearest + 1e-9);
            near += fabs(d - nearest) < 1e-9;
            antipode += fabs(d + 1) < 1e-9;
            best = fmax(best, d);
        }
        CHECK_EQ_INT(near, 3);
        CHECK_EQ_INT(antipode, 1);
        /* The unit sphere's bounding sphere, with 1% margin. */
        CHECK_NEAR(v[i].half_extent, 1.01, 1e-6);
        CHECK_NEAR(v[i].centre[0], 0, 1e-6);
    }
    texopt_model_destroy(m);
}

/* The second camera set: 12 icosahedron vertices, each with 5 nearest neighbours at the
 * angle whose cosine is 1/sqrt(5), and none of them a dodecahedron camera (each is a face
 * centre of the dodecahedron: its nearest dodecahedron cameras are 5, all equally far). */
TEST(icosahedron_views_look_between_the_dodecahedron_views)
{
    texopt_model *m = fixture_uv_sphere(12, 6, 16);
    CHECK(m);
    texopt_view ico[TEXOPT_VIEW_COUNT], dod[TEXOPT_VIEW_COUNT];
    int n = 0, nd = 0;
    char err[256] = "";
    CHECK_OK(texopt_meshrender_camera_set(m, TEXOPT_CAMERAS_ICOSAHEDRON, ico, &n, err, sizeof err), err);
    CHECK_OK(texopt_meshrender_camera_set(m, TEXOPT_CAMERAS_DODECAHEDRON, dod, &nd, err, sizeof err), err);
    CHECK_EQ_INT(n, 12);
    CHECK_EQ_INT(nd, TEXOPT_VIEW_COUNT);
    for (int i = 0; i < n; i++) {
        CHECK_NEAR(dot(ico[i].direction, ico[i].direction), 1, 1e-12);
        CHECK_NEAR(dot(ico[i].right, ico[i].direction), 0, 1e-12);
        CHECK_NEAR(ico[i].half_extent, 1.01, 1e-6);
        int near = 0;
        for (int j = 0; j < n; j++)
            near += j != i && fabs(dot(ico[i].direction, ico[j].direction) - 1 / sqrt(5.0)) < 1e-9;
        CHECK_EQ_INT(near, 5);
        double best = -2;
        for (int j = 0; j < nd; j++)
            best = fmax(best, dot(ico[i].direction, dod[j].direction));
        int closest = 0;
        for (int j = 0; j < nd; j++)
            closest += fabs(dot(ico[i].direction, dod[j].direction) - best) < 1e-9;
        CHECK(best < 0.8);
        CHECK_EQ_INT(closest, 5);
    }
    CHECK(texopt_meshrender_camera_set(m, (texopt_camera_set)7, ico, &n, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_model_destroy(m);
}

/* A view looking down -z at the unit quad [0,1]^2, the window exactly [0,1]^2 (no margin). */
static texopt_view quad_view(void)
{
    texopt_view v = {
        .centre = {0.5, 0.5, 0}, .direction = {0, 0, 1}, .right = {1, 0, 0}, .up = {0, 1, 0}, .half_extent = 0.5};
    return v;
}

TEST(face_on_quad_covers_every_pixel_once_and_shades_its_texture)
{
    texopt_model *m = fixture_textured_quad(64, "gradient");
    CHECK(m);
    texopt_view v = quad_view();
    texopt_raster r;
    char err[256] = "";
    CHECK_OK(texopt_meshrender_rasterize(m, &v, 32, &r, err, sizeof err), err);
    CHECK_EQ_INT(r.covered, 32 * 32);
    texopt_image img;
    CHECK_OK(texopt_meshrender_shade(m, &r, &img, err, sizeof err), err);
    /* Screen row 0 is the top (y = 1 = v = 1); the gradient has r = (x + 0.5)/64 at texel x
     * and g = (y + 0.5)/64 at texel row y. Pixel (i, j) centre maps to u = (i + 0.5)/32,
     * v = 1 - (j + 0.5)/32, texel position 64 u, 64 v: bilinear of a linear ramp is exact
     * away from the wrapping edge. */
    for (int j = 2; j < 30; j++)
        for (int i = 2; i < 30; i++) {
            const float *px = texopt_image_at(&img, i, j);
            double u = (i + 0.5) / 32, vv = 1 - (j + 0.5) / 32;
            CHECK_NEAR(px[0], u, 1e-5);
            CHECK_NEAR(px[1], vv, 1e-5);
            CHECK_NEAR(px[2], 0.25, 1e-6);
        }
    texopt_image_destroy(&img);
    texopt_raster_destroy(&r);
    texopt_model_destroy(m);
}

TEST(nearer_triangle_wins_the_depth_test)
{
    /* Two quads over the same square, at z = 0 (first) and z = 0.5 (second, nearer to a
     * camera on +z). The second one's UVs sit in the other half of a "half" texture. */
    const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 0.5f, 1, 0, 0.5f, 1, 1, 0.5f, 0, 1, 0.5f};
    const float uv[] = {0, 0, 0.25f, 0, 0.25f, 1, 0, 1, 0.75f, 0, 1, 0, 1, 1, 0.75f, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    texopt_model *m = fixture_model_from_arrays(pos, uv, 8, tri, 4, 32, 32, "flat");
    CHECK(m);
    texopt_view v = quad_view();
    v.centre[2] = 0.25;
    texopt_raster r;
    char err[256] = "";
    CHECK_OK(texopt_meshrender_rasterize(m, &v, 16, &r, err, sizeof err), err);
    for (int i = 0; i < 16 * 16; i++)
        CHECK(r.triangle[i] == 2 || r.triangle[i] == 3);
    texopt_raster_destroy(&r);
    /* Seen from below (-z), the z = 0 quad is in front. */
    v.direction[2] = -1;
    v.right[0] = -1; /* keep right x up = direction */
    CHECK_OK(texopt_meshrender_rasterize(m, &v, 16, &r, err, sizeof err), err);
    for (int i = 0; i < 16 * 16; i++)
        CHECK(r.triangle[i] == 0 || r.triangle[i] == 1);
    texopt_raster_destroy(&r);
    texopt_model_destroy(m);
}

TEST(mipmapped_shading_averages_minified_stripes)
{
    /* The quad's 256^2 vertical stripes (period 8 texels) on an 8 x 8 screen: every pixel
     * spans 32 texels, four periods. Filtered lookups see the mean grey; bilinear lookups
     * see one texel. The window is shifted by 2 texels so that pixel centres (texel x = 18 +
     * 32 i) fall inside a stripe, not on an edge. */
    texopt_model *m = fixture_textured_quad(256, "stripes0");
    CHECK(m);
    texopt_view v = quad_view();
    v.centre[0] += 2.0 / 256;
    texopt_raster r;
    char err[256] = "";
    CHECK_OK(texopt_meshrender_rasterize(m, &v, 8, &r, err, sizeof err), err);
    texopt_texture_filter *filters[1] = {NULL};
    CHECK_OK(texopt_texture_filter_create(&filters[0], &m->images[0], TEXOPT_WRAP_REPEAT, TEXOPT_WRAP_REPEAT, err,
                                          sizeof err),
             err);
    texopt_image plain, filtered;
    CHECK_OK(texopt_meshrender_shade(m, &r, &plain, err, sizeof err), err);
    CHECK_OK(texopt_meshrender_shade_filtered(m, &r, filters, &filtered, err, sizeof err), err);
    int checked = 0;
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 7; i++) { /* the last column is past the quad after the shift */
            size_t k = (size_t)j * 8 + (size_t)i;
            CHECK(r.triangle[k] >= 0);
            CHECK_NEAR(filtered.pixels[3 * k], 0.5, 0.02);
            CHECK_MSG(fabs(plain.pixels[3 * k] - 0.5) > 0.49, "pixel %d,%d: %g", i, j, plain.pixels[3 * k]);
            checked++;
        }
    CHECK_EQ_INT(checked, 56);
    texopt_image_destroy(&plain);
    texopt_image_destroy(&filtered);
    texopt_texture_filter_destroy(filters[0]);
    texopt_raster_destroy(&r);
    texopt_model_destroy(m);
}

/* A quad whose two triangles are two primitives: the first's material has a "gradient"
 * normal map, the second's none. Luma shading of the normal slot reads the map on the first
 * and is mid grey on the second; base colour ("flat") is the same on both. */
TEST(luma_shading_reads_the_chosen_slot)
{
    texopt_model *m = fixture_textured_quad(32, "flat");
    CHECK(m);
    char err[256] = "";
    texopt_image *images = realloc(m->images, 2 * sizeof *images);
    texopt_primitive *prims = realloc(m->primitives, 2 * sizeof *prims);
    if (images)
        m->images = images;
    if (prims)
        m->primitives = prims;
    texopt_material *mats = realloc(m->materials, 2 * sizeof *mats);
    if (mats)
        m->materials = mats;
    char **names = realloc(m->image_names, 2 * sizeof *names);
    if (names) {
        m->image_names = names;
        names[1] = NULL;
    }
    CHECK(images && prims && mats && names);
    CHECK_OK(texopt_image_create(&m->images[1], 32, 32, 3, err, sizeof err), err);
    m->image_count = 2;
    CHECK(fixture_fill_pattern(&m->images[1], "gradient") == 0);
    m->materials[1] = m->materials[0];
    m->material_count = 2;
    m->materials[0].slot[TEXOPT_SLOT_NORMAL] = m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR];
    m->materials[0].slot[TEXOPT_SLOT_NORMAL].image = 1;
    m->primitives[1] = m->primitives[0];
    m->primitive_count = 2;
    m->primitives[0].triangle_count = 1;
    m->primitives[1].first_triangle = 1;
    m->primitives[1].triangle_count = 1;
    m->primitives[1].material = 1;
    CHECK(texopt_meshrender_has_texture(m, TEXOPT_SLOT_NORMAL));
    CHECK(!texopt_meshrender_has_texture(m, TEXOPT_SLOT_OCCLUSION));
    CHECK(texopt_meshrender_binding(m, 0, TEXOPT_SLOT_NORMAL) != NULL);
    CHECK(texopt_meshrender_binding(m, 1, TEXOPT_SLOT_NORMAL) == NULL);

    texopt_view v = quad_view();
    texopt_raster r;
    CHECK_OK(texopt_meshrender_rasterize(m, &v, 32, &r, err, sizeof err), err);
    float *normal = malloc(32 * 32 * sizeof *normal), *base = malloc(32 * 32 * sizeof *base);
    float *ao = malloc(32 * 32 * sizeof *ao);
    CHECK(normal && base && ao);
    CHECK_OK(texopt_meshrender_shade_luma(m, &r, TEXOPT_SLOT_NORMAL, NULL, NULL, normal, err, sizeof err), err);
    CHECK_OK(texopt_meshrender_shade_luma(m, &r, TEXOPT_SLOT_BASE_COLOR, NULL, NULL, base, err, sizeof err), err);
    CHECK_OK(texopt_meshrender_shade_luma(m, &r, TEXOPT_SLOT_OCCLUSION, NULL, NULL, ao, err, sizeof err), err);
    const float flat[3] = {0.6f, 0.4f, 0.2f};
    int seen[2] = {0, 0};
    for (int j = 1; j < 31; j++)
        for (int i = 1; i < 31; i++) {
            size_t k = (size_t)j * 32 + (size_t)i;
            int tri = r.triangle[k];
            CHECK(tri == 0 || tri == 1);
            seen[tri]++;
            /* The gradient at u = (i + 0.5)/32, v = 1 - (j + 0.5)/32 (bilinear of a ramp). */
            const float grad[3] = {(float)((i + 0.5) / 32), (float)(1 - (j + 0.5) / 32), 0.25f};
            CHECK_NEAR(normal[k], tri == 0 ? texopt_luma(grad, 3) : 0.5f, 1e-5);
            CHECK_NEAR(base[k], texopt_luma(flat, 3), 1e-6);
            CHECK(ao[k] == 0.5f);
        }
    CHECK(seen[0] > 300 && seen[1] > 300);
    CHECK(texopt_meshrender_shade_luma(m, &r, TEXOPT_TEXTURE_KEY_COUNT, NULL, NULL, ao, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_meshrender_shade_luma(m, &r, -1, NULL, NULL, ao, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    free(normal);
    free(base);
    free(ao);
    texopt_raster_destroy(&r);
    texopt_model_destroy(m);
}

/* The quad's flat base colour given an alpha channel: 0.2 in texel columns 0..15, 1 in 16..31. */
static texopt_model *quad_with_alpha_columns(texopt_alpha_mode mode)
{
    texopt_model *m = fixture_textured_quad(32, "flat");
    texopt_image rgba = {0};
    if (!m || texopt_image_create(&rgba, 32, 32, 4, NULL, 0) != TEXOPT_OK)
        return texopt_model_destroy(m), NULL;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            float *to = texopt_image_at(&rgba, x, y);
            memcpy(to, texopt_image_at(&m->images[0], x, y), 3 * sizeof *to);
            to[3] = x < 16 ? 0.2f : 1.0f;
        }
    texopt_image_destroy(&m->images[0]);
    m->images[0] = rgba;
    m->materials[0].alpha_mode = mode;
    m->materials[0].alpha_cutoff = 0.5;
    return m;
}

/* One RGBA image, flat colour (0.6, 0.4, 0.2) with flat alpha, bound in five ways: a texture
 * read in R, G and B shows its luma; one read in fewer channels the mean of those, so the
 * channels of a shared image that it does not read do not show. */
TEST(luma_shading_shows_the_channels_a_texture_is_read_in)
{
    texopt_model *m = fixture_textured_quad(16, "flat");
    CHECK(m && fixture_add_alpha(&m->images[0], "flat") == 0);
    texopt_material *mat = &m->materials[0];
    const texopt_texture_ref image = mat->slot[TEXOPT_SLOT_BASE_COLOR];
    mat->slot[TEXOPT_SLOT_OCCLUSION] = mat->slot[TEXOPT_SLOT_METALLIC_ROUGHNESS] = image;
    mat->extra[0] = (texopt_extra_texture){image, TEXOPT_TEXTURE_DATA, TEXOPT_CHANNEL_A, "specularTexture"};
    mat->extra[1] = (texopt_extra_texture){image, TEXOPT_TEXTURE_COLOR, TEXOPT_CHANNELS_RGB, "sheenColorTexture"};
    mat->extra_count = 2;
    const float rgb[3] = {0.6f, 0.4f, 0.2f}, alpha = m->images[0].pixels[3];
    CHECK(alpha > 0.1f && alpha < 0.9f);
    const struct {
        int texture;
        float grey;
    } want[] = {{TEXOPT_SLOT_BASE_COLOR, texopt_luma(rgb, 3)},
                {TEXOPT_SLOT_OCCLUSION, 0.6f},
                {TEXOPT_SLOT_METALLIC_ROUGHNESS, 0.3f},
                {texopt_texture_key_from_name("specularTexture"), alpha},
                {texopt_texture_key_from_name("sheenColorTexture"), texopt_luma(rgb, 3)}};
    char err[256] = "";
    texopt_view v = quad_view();
    texopt_raster r;
    CHECK_OK(texopt_meshrender_rasterize(m, &v, 16, &r, err, sizeof err), err);
    float *grey = malloc(16 * 16 * sizeof *grey);
    CHECK(grey != NULL);
    for (size_t w = 0; w < sizeof want / sizeof want[0]; w++) {
        CHECK_OK(texopt_meshrender_shade_luma(m, &r, want[w].texture, NULL, NULL, grey, err, sizeof err), err);
        for (int k = 0; k < 16 * 16; k++)
            if (r.triangle[k] >= 0)
                CHECK_MSG(fabsf(grey[k] - want[w].grey) < 1e-6f, "%s: pixel %d shows %.4f, not %.4f",
                          texopt_texture_key_name(want[w].texture), k, grey[k], want[w].grey);
    }
    free(grey);
    texopt_raster_destroy(&r);
    texopt_model_destroy(m);
}

TEST(base_colour_alpha_cuts_or_blends_over_grey_where_the_material_shows_it)
{
    const float flat[3] = {0.6f, 0.4f, 0.2f};
    const double colour = texopt_luma(flat, 3);
    const texopt_alpha_mode modes[3] = {TEXOPT_ALPHA_OPAQUE, TEXOPT_ALPHA_MASK, TEXOPT_ALPHA_BLEND};
    /* Columns 0..14 (alpha 0.2) as each mode shows them; columns 17..31 (alpha 1) are the colour. */
    const double low[3] = {colour, 0.5, 0.2 * colour + 0.8 * 0.5};
    for (int k = 0; k < 3; k++) {
        texopt_model *m = quad_with_alpha_columns(modes[k]);
        CHECK(m);
        texopt_view v = quad_view();
        texopt_raster r;
        char err[256] = "";
        CHECK_OK(texopt_meshrender_rasterize(m, &v, 32, &r, err, sizeof err), err);
        float *luma = malloc(32 * 32 * sizeof *luma), *normal = malloc(32 * 32 * sizeof *normal);
        CHECK(luma && normal);
        CHECK_OK(texopt_meshrender_shade_luma(m, &r, TEXOPT_SLOT_BASE_COLOR, NULL, NULL, luma, err, sizeof err), err);
        /* Another slot reading the same RGBA image ignores its alpha. */
        m->materials[0].slot[TEXOPT_SLOT_NORMAL] = m->materials[0].slot[TEXOPT_SLOT_BASE_COLOR];
        CHECK_OK(texopt_meshrender_shade_luma(m, &r, TEXOPT_SLOT_NORMAL, NULL, NULL, normal, err, sizeof err), err);
        for (int j = 1; j < 31; j++)
            for (int i = 1; i < 31; i++) {
                size_t p = (size_t)j * 32 + (size_t)i;
                if (i < 15)
                    CHECK_NEAR(luma[p], low[k], 1e-5);
                if (i > 16)
                    CHECK_NEAR(luma[p], colour, 1e-5);
                CHECK_NEAR(normal[p], colour, 1e-5);
            }
        free(luma);
        free(normal);
        texopt_raster_destroy(&r);
        texopt_model_destroy(m);
    }
}

TEST(bad_arguments_are_refused)
{
    texopt_model *m = fixture_textured_quad(16, "flat");
    CHECK(m);
    texopt_view v = quad_view();
    texopt_raster r;
    char err[256] = "";
    CHECK(texopt_meshrender_rasterize(m, &v, 4, &r, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    m->triangles[4] = 99; /* past the vertex count */
    CHECK(texopt_meshrender_rasterize(m, &v, 16, &r, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle 1") != NULL);
    m->triangles[4] = 2;
    for (int i = 0; i < 12; i++)
        m->positions[i] = 0.25f; /* every vertex at one point */
    texopt_view views[TEXOPT_VIEW_COUNT];
    CHECK(texopt_meshrender_views(m, views, err, sizeof err) == TEXOPT_E_UNSUPPORTED);
    CHECK(strstr(err, "one point") != NULL);
    texopt_model_destroy(m);
}
