/* test_meshwise_loss.c - per-triangle loss under a finished layout (engine/stage2/meshwise_loss.c):
 * the share of triangles with E <= eps after the mesh-wise stage (paper Fig. 16). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "mesh.h"
#include "meshwise_loss.h"
#include "test.h"

typedef struct grid_fixture {
    texopt_model *model;
    texopt_mesh *mesh;
    double *layout;
} grid_fixture;

static int grid_open(grid_fixture *f, int n, int tex, const char *pattern)
{
    char err[256] = "";
    memset(f, 0, sizeof *f);
    f->model = fixture_grid(n, tex, pattern);
    if (!f->model || texopt_mesh_create(&f->mesh, f->model, 0, err, sizeof err) != TEXOPT_OK)
        return 0;
    f->layout = malloc(2 * f->mesh->vertex_count * sizeof *f->layout);
    return f->layout != NULL;
}

static void grid_close(grid_fixture *f)
{
    free(f->layout);
    texopt_mesh_destroy(f->mesh);
    texopt_model_destroy(f->model);
}

/* The layout scaled by s about the origin, then moved by a whole texel offset. */
static void scaled_layout(grid_fixture *f, double s)
{
    for (size_t i = 0; i < 2 * f->mesh->vertex_count; i++)
        f->layout[i] = s * f->mesh->texel[i] + 7.0;
}

TEST(unchanged_layout_loses_nothing)
{
    grid_fixture f;
    CHECK(grid_open(&f, 6, 64, "half"));
    scaled_layout(&f, 1.0);
    texopt_loss_share share;
    char err[256] = "";
    CHECK_OK(
        texopt_meshwise_loss_share(f.model, f.mesh, f.layout, NULL, 0.01, 1, 0, NULL, &share, NULL, err, sizeof err),
        err);
    CHECK_EQ_INT(share.evaluated, f.mesh->triangle_count);
    CHECK_EQ_INT(share.within, share.evaluated);
    CHECK_NEAR(share.share, 1.0, 0.0);
    CHECK_NEAR(share.max_loss, 0.0, 1e-6);
    grid_close(&f);
}

TEST(shrinking_detail_fails_where_the_texture_is_detailed)
{
    /* "half": left half flat, right half one-texel strokes. Shrunk to 0.3, the flat half
     * still meets eps and the detailed half does not. */
    grid_fixture f;
    CHECK(grid_open(&f, 8, 128, "half"));
    scaled_layout(&f, 0.3);
    size_t n = f.mesh->triangle_count;
    double *loss = malloc(n * sizeof *loss);
    texopt_loss_share share;
    char err[256] = "";
    CHECK_OK(
        texopt_meshwise_loss_share(f.model, f.mesh, f.layout, NULL, 0.01, 2, 0, loss, &share, NULL, err, sizeof err),
        err);
    size_t flat_ok = 0, flat = 0, detail_bad = 0, detail = 0;
    for (size_t t = 0; t < n; t++) {
        const uint32_t *tri = f.mesh->triangle + 3 * t;
        double cx = (f.mesh->texel[2 * tri[0]] + f.mesh->texel[2 * tri[1]] + f.mesh->texel[2 * tri[2]]) / 3;
        double cy = (f.mesh->texel[2 * tri[0] + 1] + f.mesh->texel[2 * tri[1] + 1] + f.mesh->texel[2 * tri[2] + 1]) / 3;
        /* Only triangles whose one-ring stays off the texture border: at the border the
         * REPEAT wrap and the mesh boundary mix in other signal. */
        if (cx < 24 || cy < 24 || cx > f.mesh->width - 24 || cy > f.mesh->height - 24)
            continue;
        if (cx < 0.5 * f.mesh->width - 24) { /* inside the flat half, one-ring too */
            flat++;
            flat_ok += loss[t] <= 0.01;
        } else if (cx > 0.5 * f.mesh->width + 16) {
            detail++;
            detail_bad += loss[t] > 0.01;
        }
    }
    CHECK(flat > 0 && detail > 0);
    CHECK_EQ_INT(flat_ok, flat);
    CHECK_EQ_INT(detail_bad, detail);
    CHECK(share.share > 0.2 && share.share < 0.8);
    CHECK(share.max_loss > 0.01);
    /* The same losses with one thread: the thread count decides nothing. */
    double *again = malloc(n * sizeof *again);
    texopt_loss_share share1;
    CHECK_OK(
        texopt_meshwise_loss_share(f.model, f.mesh, f.layout, NULL, 0.01, 1, 0, again, &share1, NULL, err, sizeof err),
        err);
    CHECK(memcmp(loss, again, n * sizeof *loss) == 0);
    CHECK_EQ_INT(share1.within, share.within);
    free(again);
    free(loss);
    grid_close(&f);
}

TEST(loss_share_refuses_bad_arguments)
{
    grid_fixture f;
    CHECK(grid_open(&f, 2, 32, "flat"));
    scaled_layout(&f, 1.0);
    texopt_loss_share share;
    char err[256] = "";
    CHECK_EQ_INT(
        texopt_meshwise_loss_share(f.model, f.mesh, f.layout, NULL, 0.0, 1, 0, NULL, &share, NULL, err, sizeof err),
        TEXOPT_E_INVALID_ARGUMENT);
    CHECK_EQ_INT(
        texopt_meshwise_loss_share(f.model, f.mesh, NULL, NULL, 0.01, 1, 0, NULL, &share, NULL, err, sizeof err),
        TEXOPT_E_INVALID_ARGUMENT);
    f.layout[0] = NAN;
    CHECK_EQ_INT(
        texopt_meshwise_loss_share(f.model, f.mesh, f.layout, NULL, 0.01, 1, 0, NULL, &share, NULL, err, sizeof err),
        TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle") != NULL);
    grid_close(&f);
}
