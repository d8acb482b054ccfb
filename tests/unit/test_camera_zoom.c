/* test_camera_zoom.c - stage 1's camera with its zoom limited (camera.h
 * texopt_camera_limit_zoom, applied by uvraster.c): what the one-ring loss then sees. */
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "mesh.h"
#include "test.h"
#include "triloss.h"
#include "uvraster.h"

/* Texels per world unit over the one-ring of t, as uvraster.c measures it. */
static double ring_density(const texopt_mesh *mesh, uint32_t t)
{
    uint32_t ring[64];
    size_t n = texopt_mesh_one_ring(mesh, t, ring, 64);
    double texel = 0, world = 0;
    for (size_t f = 0; f < n && f < 64; f++) {
        texel += fabs(mesh->area_texel[ring[f]]);
        world += mesh->area_3d[ring[f]];
    }
    return sqrt(texel / world);
}

/* Field by field (memcmp would compare the struct's padding): exactly equal. */
static int same_camera(const texopt_camera *x, const texopt_camera *y)
{
    for (int k = 0; k < 3; k++)
        if (x->center[k] != y->center[k] || x->right[k] != y->right[k] || x->up[k] != y->up[k] ||
            x->normal[k] != y->normal[k])
            return 0;
    return x->window_x0 == y->window_x0 && x->window_y0 == y->window_y0 && x->window_side == y->window_side &&
           x->size == y->size;
}

/* E of the isotropic Jacobian lambda I on triangle t. */
static double isotropic_loss(texopt_triloss *loss, uint32_t t, double lambda)
{
    char err[256] = "";
    double J[4], e = -1;
    texopt_jacobian_from_params(0, lambda, lambda, 0, J);
    if (texopt_triloss_prepare(loss, t, err, sizeof err) != TEXOPT_OK ||
        texopt_triloss_eval(loss, J, INFINITY, &e, err, sizeof err) != TEXOPT_OK)
        return NAN;
    return e;
}

TEST(limited_zoom_sees_a_shrink_the_papers_window_hides)
{
    char err[256] = "";
    /* 1-texel strokes on a grid whose one-rings the paper's window shows at about 2
     * input texels per pixel: halving the texel density loses detail no pixel shows. */
    texopt_model *model = fixture_grid(8, 256, "half");
    CHECK(model);
    texopt_mesh *mesh = NULL;
    texopt_triloss *loss = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_triloss_create(&loss, model, mesh, 64, err, sizeof err), err);
    uint32_t t = 2 * (3 * 8 + 5); /* quad (5, 3), inside the text half */
    double density = ring_density(mesh, t);
    double limited = isotropic_loss(loss, t, 0.5);
    const texopt_uvraster *raster = texopt_triloss_raster(loss);
    double zoom_limited = texopt_camera_zoom(&raster->camera, density);
    /* The paper's window: stage 1 has no switch for it, so the test turns the raster's. */
    ((texopt_uvraster *)raster)->max_zoom = 0;
    double paper = isotropic_loss(loss, t, 0.5);
    double zoom_paper = texopt_camera_zoom(&raster->camera, density);
    CHECK(zoom_paper > 1.9);
    CHECK_NEAR(zoom_limited, TEXOPT_CAMERA_MAX_ZOOM, 1e-9);
    CHECK(paper < 0.01);
    CHECK(limited > 0.01);
    texopt_triloss_destroy(loss);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(a_ring_seen_at_no_more_than_the_limit_keeps_the_papers_camera)
{
    char err[256] = "";
    texopt_model *model = fixture_grid(8, 64, "half");
    CHECK(model);
    texopt_mesh *mesh = NULL;
    texopt_uvraster *raster = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_create(&raster, 64, err, sizeof err), err);
    CHECK_NEAR(raster->max_zoom, TEXOPT_CAMERA_MAX_ZOOM, 0);
    for (uint32_t t = 0; t < mesh->triangle_count; t += 7) {
        CHECK_OK(texopt_uvraster_render(raster, mesh, t, err, sizeof err), err);
        uint32_t ring[64];
        size_t n = texopt_mesh_one_ring(mesh, t, ring, 64);
        double points[64 * 9];
        for (size_t f = 0; f < n; f++)
            for (int k = 0; k < 3; k++)
                memcpy(points + 9 * f + 3 * k,
                       mesh->position + 3 * (size_t)mesh->point_of[mesh->triangle[3 * ring[f] + k]],
                       3 * sizeof(double));
        texopt_camera paper;
        const uint32_t *tri = mesh->triangle + 3 * (size_t)t;
        CHECK_OK(texopt_camera_create(&paper, mesh->position + 3 * (size_t)mesh->point_of[tri[0]],
                                      mesh->position + 3 * (size_t)mesh->point_of[tri[1]],
                                      mesh->position + 3 * (size_t)mesh->point_of[tri[2]], points, 3 * n, 64, err,
                                      sizeof err),
                 err);
        CHECK(texopt_camera_zoom(&paper, ring_density(mesh, t)) <= TEXOPT_CAMERA_MAX_ZOOM);
        CHECK(same_camera(&paper, &raster->camera));
    }
    texopt_uvraster_destroy(raster);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}
