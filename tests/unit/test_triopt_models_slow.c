/* test_triopt_models_slow.c - the triangle-wise stage on real glTF models (tests/data). */
#include <stdlib.h>

#include "gltf_io.h"
#include "mesh.h"
#include "test.h"
#include "triopt.h"

/* Runs stage 1 on every `stride`-th triangle of the first domain of `file` and checks every
 * output is finite, in its domain and feasible. */
static void check_model(const char *file, uint32_t stride, int iterations)
{
    char path[1024], err[256] = "";
    snprintf(path, sizeof path, "%s/%s", TEXOPT_TEST_DATA_DIR, file);
    texopt_model *model = NULL;
    texopt_mesh *mesh = NULL;
    CHECK_OK(texopt_model_load(&model, path, NULL, err, sizeof err), err);
    CHECK(model->domain_count >= 1);
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    texopt_triangle_target *out = calloc(mesh->triangle_count, sizeof *out);
    CHECK(out);
    texopt_triopt_options opt = {.iterations = iterations, .threads = 2, .stride = stride};
    texopt_triopt_report rep;
    CHECK_OK(texopt_triopt_run(model, mesh, &opt, out, &rep, NULL, err, sizeof err), err);
    size_t searched = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const texopt_triangle_target *o = &out[t];
        CHECK_MSG(isfinite(o->alpha) && isfinite(o->beta) && isfinite(o->lambda1) && isfinite(o->lambda2) &&
                      isfinite(o->loss) && isfinite(o->w_rotation) && isfinite(o->w_stretch),
                  "%s triangle %zu has a non-finite field", file, t);
        CHECK(o->lambda1 >= 0.1 - 1e-12 && o->lambda1 <= 1.0 + 1e-12);
        CHECK(o->lambda2 >= 0.1 - 1e-12 && o->lambda2 <= 1.0 + 1e-12);
        CHECK(o->w_rotation >= 0 && o->w_stretch >= 0);
        CHECK_MSG(o->loss >= 0 && o->loss < 0.01, "%s triangle %zu: E = %g", file, t, o->loss);
        if (o->evaluations > 0)
            searched++;
    }
    CHECK_EQ_INT(searched + rep.skipped, mesh->triangle_count);
    CHECK_EQ_INT(searched, rep.optimised);
    CHECK(rep.optimised >= mesh->triangle_count / stride - 2);
    CHECK(isfinite(rep.mean_objective) && rep.mean_area_scale > 0 && rep.mean_area_scale <= 1);
    printf("%s: %zu triangles in %.2f s (%.1f/s), mean E %.5f, mean l1l2 %.3f, mean f %.3f\n", file, rep.optimised,
           rep.seconds, rep.optimised / rep.seconds, rep.mean_loss, rep.mean_area_scale, rep.mean_objective);
    free(out);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(spot_every_20th_triangle_is_finite_and_feasible)
{
    check_model("spot/spot.glb", 20, 30);
}

TEST(fox_every_10th_triangle_is_finite_and_feasible)
{
    check_model("Fox/Fox.glb", 10, 30);
}
