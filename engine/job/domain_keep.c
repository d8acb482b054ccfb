/* domain_keep.c - when a layout method keeps a domain's input layout, and why
 * (domain_keep.h). */
#include "domain_keep.h"
#include "domain_rechart.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "input_method.h"
#include "layout_check.h"

/* Whether every triangle of the mesh is degenerate in 3D (mesh.h). */
static int flat_in_3d(const texopt_mesh *mesh)
{
    for (size_t t = 0; t < mesh->triangle_count; t++)
        if (!(mesh->flags[t] & TEXOPT_TRI_DEGENERATE_3D))
            return 0;
    return 1;
}

int job_keep_if_flat(job_domain *jd, texopt_domain_stats *ds)
{
    if (!flat_in_3d(jd->mesh))
        return 0;
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "its %zu triangles have no area in 3D (every vertex on a line or a point), so nothing of it can be "
             "seen and no layout judged",
             jd->mesh->triangle_count);
    jd->kept = DOMAIN_KEPT_AS_IS;
    return 1;
}

int job_keep_if_no_texels(const texopt_domain *dom, job_domain *jd, texopt_domain_stats *ds)
{
    if (jd->input_coverage.covered_texels != 0)
        return 0;
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "its layout covers no texel centre of its %dx%d texture, so it has no texels to lay out (a texture "
             "of one texel, or UVs inside one texel)",
             dom->width, dom->height);
    jd->kept = DOMAIN_KEPT_AS_IS;
    return 1;
}

int job_keep_if_nearest(const texopt_model *model, const texopt_domain *dom, job_domain *jd, texopt_domain_stats *ds)
{
    if (dom->nearest_image < 0)
        return 0;
    /* The loader names an image without URI or name "image N": said once, not twice. */
    const char *name = model->image_names ? model->image_names[dom->nearest_image] : NULL;
    char label[160];
    snprintf(label, sizeof label, name && strncmp(name, "image ", 6) != 0 ? "image %d (%s)" : "image %d",
             dom->nearest_image, name);
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "its %s is magnified NEAREST (sampler magFilter, pixel art): its texels show as blocks, which a new "
             "layout would resample off their grid, blurred and misaligned",
             label);
    jd->kept = DOMAIN_KEPT_AS_IS;
    return 1;
}

/* How many times over a domain's layout reads its texels: the texel area its triangles pay
 * for (texel_share.h: mirrored twins and folds pay once) over the texels they cover. 1.000 to
 * 1.005 on the sample assets; a texture tiled 4 x 4 times gives 16. */
static double layout_repeats(const job_domain *jd)
{
    double paid_area = 0;
    for (size_t t = 0; t < jd->mesh->triangle_count; t++)
        paid_area += fabs(jd->mesh->area_texel[t]) * (jd->paid ? jd->paid[t] : 1.0);
    return paid_area / (double)jd->input_coverage.covered_texels;
}

/* A domain whose layout reads its texels more than this many times over keeps its input
 * layout (DOMAIN_INPUT_RESIZED): unrolled into an atlas, a texture tiled R times needs R times
 * its texels for the same look, so at an equal budget every layout method's result is far
 * worse than the tiling (a 64x64 checker tiled 4 x 4 at c_r 0.5: q 0.0160 laid out anew,
 * 0.0009 resized in its layout). */
#define REPEATS_LIMIT 1.5

int job_keep_if_tiling(const texopt_domain *dom, job_domain *jd, texopt_domain_stats *ds)
{
    double repeats = layout_repeats(jd);
    if (!(repeats > REPEATS_LIMIT))
        return 0;
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "its UVs repeat its %dx%d texture %.1f times over (a tiling texture): a layout without repeats "
             "would need that many times its texels; the input layout is kept, its images resized to the "
             "budget",
             dom->width, dom->height, repeats);
    jd->kept = DOMAIN_INPUT_RESIZED;
    return 1;
}

texopt_status job_check_something_laid_out(const texopt_job *job, char *err, size_t err_len)
{
    int n = job->model->domain_count;
    for (int d = 0; d < n; d++)
        if (job->domains[d].kept != DOMAIN_KEPT_AS_IS)
            return TEXOPT_OK;
    return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "%sdomain 0: %s", n > 1 ? "no domain can be laid out; " : "",
                       job->stats.domains[0].input_layout_kept);
}

void job_keep_domain(const texopt_model *model, int d, texopt_domain_stats *ds)
{
    const texopt_domain *dom = &model->domains[d];
    ds->output_width = dom->width;
    ds->output_height = dom->height;
    ds->cost_input = ds->cost_output = ds->relative_cost = 0;
    ds->packing_efficiency_input = ds->packing_efficiency = 0;
    ds->repacked = 0;
    for (int i = 0; i < ds->image_count; i++) {
        ds->images[i].output_width = ds->images[i].input_width;
        ds->images[i].output_height = ds->images[i].input_height;
        ds->images[i].rewritten = 0;
    }
}

/* Charts of a few texels or less (a palette's colour spots, each face an island of its own)
 * pack mostly gutter: such a layout's texture can take many times the pixels of the input
 * layout's at the same budget (a 64x64 palette of 4,212 spots at c_r 0.3: 28x3056 against
 * 35x35, BENCHMARKS.md@9f788a8 "Palette models"), or fit a texture size at no scale. The domain then
 * keeps its input layout, its images resized to the budget as by method "input": a budget met
 * with over twice the pixels the input layout needs for it is not what was asked for. The
 * sample assets' perceptual layouts take 0.62-1.06 times the input layout's pixels at c_r 0.1,
 * where gutter weighs most. */
#define WASTED_PIXELS_LIMIT 2.0

int job_input_layout_packs_better(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *p,
                                  const texopt_budget_result *br, texopt_status st, texopt_domain_stats *ds)
{
    int ow, oh;
    job_input_frame(&model->domains[mesh->domain], p, &ow, &oh);
    if (st == TEXOPT_E_LIMIT && br->no_fit) {
        snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
                 "the new layout fits %dx%d at no scale (%zu chart%s); the input layout is kept, its images resized "
                 "to %dx%d",
                 ow, oh, mesh->chart_count, mesh->chart_count == 1 ? "" : "s", ow, oh);
        return 1;
    }
    double ratio = (double)br->width * br->height / ((double)ow * oh);
    if (st != TEXOPT_OK || ratio <= WASTED_PIXELS_LIMIT)
        return 0;
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "the new layout packs its %zu chart%s into %dx%d, %.1fx the pixels the input layout needs at this "
             "budget (%dx%d), mostly gutter; the input layout is kept, its images resized to %dx%d",
             mesh->chart_count, mesh->chart_count == 1 ? "" : "s", br->width, br->height, ratio, ow, oh, ow, oh);
    return 1;
}

int job_layout_fails_check(const texopt_job *job, const layout_run *run, int d, const texopt_mesh *laid,
                           const double *packed, const texopt_budget_result *br, texopt_status *st, char *err,
                           size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    texopt_domain_stats *ds = &run->domains[d];
    const texopt_triangle_target *targets = job_run_targets(run, jd, d);
    texopt_layout_check *c = &ds->layout_check;
    ds->has_layout_check = 1;
    double t0 = job_now_seconds();
    /* a cut layout has no sharing groups (budget_layout.c keeps cuts only without them) */
    const uint32_t *groups = jd->share && laid == job_layout_mesh(jd) ? jd->share->primary_of : NULL;
    *st = texopt_layout_check_run(laid, packed, br->width, br->height, groups, targets, c, err, err_len);
    ds->seconds_layout_check = job_now_seconds() - t0;
    if (*st != TEXOPT_OK || c->failed == TEXOPT_LAYOUT_PASSED)
        return 0;
    int ow, oh;
    job_input_frame(&job->model->domains[d], run->p, &ow, &oh);
    snprintf(ds->input_layout_kept, sizeof ds->input_layout_kept,
             "the new layout failed the layout check (%s: %zu triangles, model triangle %u first); the input layout "
             "is kept, its images resized to %dx%d",
             texopt_layout_failure_name(c->failed),
             c->failed == TEXOPT_LAYOUT_OVERLAP    ? c->overlapping
             : c->failed == TEXOPT_LAYOUT_FOLDOVER ? c->folded
                                                   : c->oversized,
             c->triangles[0], ow, oh);
    return 1;
}
