/* budget_layout.c - every domain of a job laid out at one budget (budget_layout.h). */
#include "budget_layout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_refine.h"
#include "bake_pool.h"
#include "budget.h"
#include "chart_gap.h"
#include "coverage.h"
#include "distortion_reduce.h"
#include "domain_keep.h"
#include "domain_rechart.h"
#include "input_method.h"
#include "job_stats.h"
#include "meshwise.h"
#include "meshwise_loss.h"
#include "scaffold.h"

/* The perceptual targets' allocation (target_allocation.h), the best of the variants measured with
 * the whole-mesh evaluation (BENCHMARKS.md@9f788a8 "Quality"): lossless optima (flat colour at
 * lambda_min) grow only by sqrt(s) (kept at lambda_min, q rose with the cost). The cap is
 * the candidate's (job_candidates.h). */
static const texopt_allocate_options perceptual_allocation = {1, 1e-6, 1.0, 0.5, NULL};

/* perceptual_allocation for one domain with singular values capped at cap: its triangles
 * lying on texels others pay for (folds, sharing groups) cost nothing, so the targets add up
 * to covered texels, the budget's unit (without it DamagedHelmet's allocation saw half its
 * budget). */
texopt_allocate_options job_domain_allocation(const job_domain *jd, double cap)
{
    texopt_allocate_options o = perceptual_allocation;
    o.cap = cap;
    o.paid = jd->paid;
    return o;
}

/* The run's targets, rescaled to relative cost c_r when run->allocating (target_allocation.h, a
 * perceptual candidate), solved by stage 2 into texel_new (input texel units). The baselines' targets are solved as they are
 * and the budget scales the result uniformly: for ssp and tewari (whose largest targets are
 * normalised to 1, not to "needs input density") the allocation measured worse or no
 * better (BENCHMARKS.md@9f788a8 "Quality"); arap's are isometric. */
static texopt_status solve_layout(texopt_job *job, const layout_run *run, int d, double relative_cost,
                                  double *texel_new, char *err, size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    const texopt_mesh *mesh = job_layout_mesh(jd);
    const texopt_params *params = &job->params;
    texopt_domain_stats *ds = &run->domains[d];
    const texopt_triangle_target *targets = job_source_targets(jd, run->source);
    texopt_triangle_target *allocated = NULL;
    texopt_status st = TEXOPT_OK;
    double t0 = job_now_seconds();
    ds->has_allocation = 0;
    if (run->refined && run->refined[d])
        targets = run->refined[d];
    else if (run->allocating) {
        allocated = malloc((mesh->triangle_count ? mesh->triangle_count : 1) * sizeof *allocated);
        if (!allocated)
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the allocated targets");
        texopt_allocation rep;
        double area = relative_cost * (double)jd->input_coverage.covered_texels;
        texopt_allocate_options o = job_domain_allocation(jd, run->allocating);
        st = texopt_allocate_targets(mesh, targets, area > 0 ? area : 1, &o, allocated, &rep, err, err_len);
        if (st == TEXOPT_OK) {
            size_t n = mesh->triangle_count ? mesh->triangle_count : 1;
            ds->has_allocation = 1;
            ds->allocation_scale = rep.scale;
            ds->allocation_capped_share = (double)rep.capped / (double)n;
            ds->allocation_lossless_share = (double)rep.lossless / (double)n;
            targets = allocated;
        }
    }
    if (st == TEXOPT_OK) {
        texopt_meshwise_options mopt = {0};
        mopt.threads = params->threads > 0 ? params->threads : 2;
        mopt.share = job_sharing(jd);
        texopt_meshwise_report mrep;
        texopt_scaffold_report srep = {0};
        if (params->bijective)
            st =
                texopt_scaffold_solve(mesh, targets, NULL, &mopt, NULL, texel_new, &srep, &job->jm.inner, err, err_len);
        else
            st = texopt_meshwise_solve(mesh, targets, NULL, &mopt, texel_new, &mrep, &job->jm.inner, err, err_len);
        if (st == TEXOPT_OK)
            job_stats_record_stage2(params->bijective ? &srep.meshwise : &mrep, ds);
        if (st == TEXOPT_OK && params->bijective)
            job_stats_record_scaffold(&srep, ds);
    }
    ds->seconds_stage2 = job_now_seconds() - t0;
    free(allocated);
    return st;
}

/* One loss evaluation per triangle: about 1% of stage 1 but the bulk of a baseline's run,
 * so it is measured only for statistics that are written, and for baselines only when the
 * job asks for an evaluation. */
texopt_status job_measure_loss_share(texopt_job *job, int d, const texopt_mesh *cut, const double *texel_new,
                                     texopt_domain_stats *ds, char *err, size_t err_len)
{
    const texopt_params *params = &job->params;
    /* It reads the texture through the layout's own input UVs, which new charts have not
     * (unfolded charts have: their layout keeps the input's vertices, domain_unfold.h). */
    if ((!job->method->chooses && !params->evaluate) || job->domains[d].rechart)
        return TEXOPT_OK;
    texopt_loss_share share;
    double t0 = job_now_seconds();
    texopt_status st =
        texopt_meshwise_loss_share(job->model, cut ? cut : job->domains[d].mesh, texel_new, job->signal_weights,
                                   params->epsilon, params->threads, 0, NULL, &share, &job->jm.inner, err, err_len);
    if (st == TEXOPT_OK) {
        ds->has_loss_share = 1;
        ds->solved_within_epsilon_share = share.share;
        ds->solved_loss_mean = share.mean_loss;
        ds->solved_loss_max = share.max_loss;
        ds->seconds_loss_share = job_now_seconds() - t0;
    }
    return st;
}

/* Texture-size budgets are allocated at the relative cost they are expected to reach: the
 * texture's texels times the packing efficiency budget.h typically achieves (0.61-0.81 on
 * the sample models, BENCHMARKS.md@9f788a8 "End to end"). A miss by more than RESOLVE_RATIO is
 * solved once more at the cost reached. */
#define EXPECTED_PACKING_EFFICIENCY 0.68
/* Texels (input frame) added to each rectangle when the cuts' decompositions are scored:
 * about the packer's gutter, so that a cut must pay for the gap its pieces need. */
#define CUT_PADDING 4.0
#define RESOLVE_RATIO 1.1
/* pack.h's default gutter, and the reduction's gap layer in gutters (Liu et al. 2019's gaps
 * between charts): layers of 3/4 of a gutter keep pieces the gutter apart when squeezed by a
 * quarter, so the reduced layout can be written as it is. */
#define PACK_GUTTER 4.0
#define GAP_LAYER 0.75

static void budget_request(texopt_job *job, const layout_run *run, const job_domain *jd, texopt_budget_request *req)
{
    const texopt_params *p = run->p;
    memset(req, 0, sizeof *req);
    req->kind = p->budget;
    req->relative_cost = p->relative_cost;
    req->texture_width = p->texture_width;
    req->texture_height = p->texture_height;
    req->input_cost = (double)jd->input_coverage.covered_texels;
    req->input_width = jd->mesh->width;
    req->input_height = jd->mesh->height;
    req->targets = job_source_targets(jd, run->source); /* charts free to rotate are turned to their smallest box */
    req->efficiency_bound = p->packing_efficiency;
    req->threads = job_worker_threads(p);
    req->keep_shape = job_sharing(jd) ? jd->share->grouped : NULL;
    req->paid = jd->paid;
    req->monitor = &job->jm.inner;
}

/* A domain's new layout at the budget. */
typedef struct domain_layout {
    double *texel_new;       /* stage 2's, in input texels */
    double *packed;          /* packed, in output texels */
    texopt_budget_result br; /* the packing's frame and cost */
    texopt_mesh *cut;        /* owned: the layout mesh cut into pieces that texel_new and
                                packed are on (packing "refine"), NULL when not cut */
} domain_layout;

/* Per chart of `charts`, 1 when one of its triangles cares about its angle on the texel
 * grid (w_rotation, as budget.h decides which charts it may turn); NULL targets: none. */
static uint8_t *charts_keeping_angle(const texopt_mesh *charts, const texopt_triangle_target *targets)
{
    uint8_t *keep = calloc(charts->chart_count ? charts->chart_count : 1, 1);
    for (size_t t = 0; keep && targets && t < charts->triangle_count; t++)
        if (targets[t].w_rotation != 0)
            keep[charts->chart_of[t]] = 1;
    return keep;
}

/* The refined layout's charts cut into pieces (texopt_atlas_cut) and the pieces packed at
 * the same budget; when that packs tighter than l's layout, and the domain has no sharing
 * groups (whose chart numbering the layout check and the packer's groups hold), the cut
 * layout replaces l's, on l->cut. Its packing efficiency, boundary and split vertices go to
 * the statistics either way. */
static texopt_status cut_if_tighter(const texopt_mesh *charts, const double *refined, const texopt_budget_request *req,
                                    domain_layout *l, texopt_domain_stats *ds, char *err, size_t err_len)
{
    size_t nt = charts->triangle_count ? charts->triangle_count : 1, pieces = 0;
    uint32_t *piece_of = malloc(nt * sizeof *piece_of), *source = NULL;
    texopt_chart_cut_options opt = {.padding = CUT_PADDING, .seed = 1, .efficiency_bound = req->efficiency_bound};
    texopt_mesh *cut = NULL;
    double *texel = NULL, *packed = NULL;
    texopt_status st = piece_of ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the pieces");
    if (st == TEXOPT_OK)
        st = texopt_atlas_cut(charts, refined, req->keep_shape, &opt, piece_of, &pieces, &ds->atlas_refine,
                              req->monitor, err, err_len);
    if (st == TEXOPT_OK && pieces > charts->chart_count)
        st = texopt_mesh_cut_create(charts, piece_of, pieces, &cut, &source, err, err_len);
    if (cut) {
        texel = malloc(2 * cut->vertex_count * sizeof *texel);
        packed = malloc(2 * cut->vertex_count * sizeof *packed);
        if (!texel || !packed)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the cut layout");
    }
    texopt_budget_result br = {0};
    if (st == TEXOPT_OK && cut) {
        for (size_t v = 0; v < cut->vertex_count; v++)
            memcpy(texel + 2 * v, refined + 2 * (size_t)source[v], 2 * sizeof *texel);
        texopt_budget_request r = *req;
        r.keep_shape = NULL; /* sharing groups stay whole: see above */
        st = texopt_budget_fit(cut, texel, &r, packed, &br, err, err_len);
        if (st == TEXOPT_E_LIMIT)
            st = TEXOPT_OK;
        ds->packing_efficiency_cut = br.packing_efficiency;
        ds->atlas_refine.vertices_split = cut->vertex_count - charts->vertex_count;
        ds->atlas_refine.boundary_cut = texopt_atlas_boundary_length(cut, texel);
    }
    if (st == TEXOPT_OK && !cut) {
        ds->packing_efficiency_cut = ds->packing_efficiency_refined;
        ds->atlas_refine.boundary_cut = ds->atlas_refine.boundary_after;
    }
    if (st == TEXOPT_OK && cut && !req->keep_shape && br.packing_efficiency > l->br.packing_efficiency) {
        double *swap = l->texel_new;
        l->texel_new = texel;
        texel = swap;
        swap = l->packed;
        l->packed = packed;
        packed = swap;
        l->br = br;
        l->cut = cut;
        cut = NULL;
        ds->atlas_refine_kept = ATLAS_REFINE_KEPT_CUT;
    }
    texopt_mesh_destroy(cut);
    free(piece_of);
    free(source);
    free(texel);
    free(packed);
    return st;
}

/* The work room of reduce_if_tighter on the charts mesh or its cut: per vertex of `laid`,
 * the refined layout, the reference (stage 2's), the packings and the reduction. */
typedef struct reduce_work {
    texopt_mesh *cut; /* NULL: laid out on the charts mesh itself */
    double *texel, *reference, *packed, *reduced, *repacked, *direct;
} reduce_work;

static void reduce_work_free(reduce_work *w)
{
    texopt_mesh_destroy(w->cut);
    free(w->texel);
    free(w->reference);
    free(w->packed);
    free(w->reduced);
    free(w->repacked);
    free(w->direct);
}

/* Every chart of `charts` at `stage2` deformed without bounds (atlas_refine.h) and cut
 * (texopt_atlas_cut): w's mesh, refined layout and reference on it. */
static texopt_status refine_and_cut_all(const texopt_mesh *charts, const double *stage2,
                                        const texopt_budget_request *req, reduce_work *w, texopt_domain_stats *ds,
                                        char *err, size_t err_len)
{
    size_t nv = charts->vertex_count ? charts->vertex_count : 1,
           nt = charts->triangle_count ? charts->triangle_count : 1;
    double *refined = malloc(2 * nv * sizeof *refined);
    uint32_t *piece_of = malloc(nt * sizeof *piece_of), *source = NULL;
    size_t pieces = 0;
    texopt_chart_cut_options opt = {.padding = CUT_PADDING, .seed = 1, .efficiency_bound = req->efficiency_bound};
    texopt_atlas_refine_report rr = {0};
    texopt_status st =
        refined && piece_of ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the reduction");
    if (st == TEXOPT_OK)
        st = texopt_atlas_refine(charts, stage2, NULL, NULL, 0, refined, &rr, req->monitor, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_atlas_cut(charts, refined, NULL, &opt, piece_of, &pieces, &rr, req->monitor, err, err_len);
    if (st == TEXOPT_OK && pieces > charts->chart_count)
        st = texopt_mesh_cut_create(charts, piece_of, pieces, &w->cut, &source, err, err_len);
    const texopt_mesh *laid = w->cut ? w->cut : charts;
    size_t n = 2 * (laid->vertex_count ? laid->vertex_count : 1);
    if (st == TEXOPT_OK) {
        w->texel = malloc(n * sizeof *w->texel);
        w->reference = malloc(n * sizeof *w->reference);
        w->packed = malloc(n * sizeof *w->packed);
        w->reduced = malloc(n * sizeof *w->reduced);
        w->repacked = malloc(n * sizeof *w->repacked);
        w->direct = malloc(n * sizeof *w->direct);
        if (!w->texel || !w->reference || !w->packed || !w->reduced || !w->repacked || !w->direct)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the reduction");
    }
    for (size_t v = 0; st == TEXOPT_OK && v < laid->vertex_count; v++) {
        size_t from = source ? source[v] : v;
        memcpy(w->texel + 2 * v, refined + 2 * from, 2 * sizeof *w->texel);
        memcpy(w->reference + 2 * v, stage2 + 2 * from, 2 * sizeof *w->reference);
    }
    if (st == TEXOPT_OK) {
        ds->reduce_charts_refined = rr.charts_refined;
        ds->reduce_pieces = w->cut ? pieces : charts->chart_count;
    }
    free(refined);
    free(piece_of);
    free(source);
    return st;
}

/* The reduced layout written as it is: its pieces scaled into the deformed packing's frame
 * less the packer's gutter (placed at half the gutter from the border, as pack.h), into
 * placed; *br that frame and the cost covered there. The smallest distance between two
 * pieces in its texels goes to the statistics. */
static texopt_status place_direct(const texopt_mesh *laid, const double *reduced, double gutter,
                                  const texopt_budget_result *packed, double *placed, texopt_budget_result *br,
                                  texopt_domain_stats *ds, const texopt_budget_request *req, char *err, size_t err_len)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, gap = 0.0;
    for (size_t i = 0; i < laid->vertex_count; i++)
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], reduced[2 * i + d]);
            hi[d] = fmax(hi[d], reduced[2 * i + d]);
        }
    double k = fmin((packed->width - gutter) / (hi[0] - lo[0]), (packed->height - gutter) / (hi[1] - lo[1]));
    if (!(k > 0.0 && isfinite(k)))
        return TEXOPT_OK;
    for (size_t i = 0; i < laid->vertex_count; i++)
        for (int d = 0; d < 2; d++)
            placed[2 * i + d] = (reduced[2 * i + d] - lo[d]) * k + 0.5 * gutter;
    texopt_coverage_options o = {0};
    o.texel = placed;
    o.width = packed->width;
    o.height = packed->height;
    o.use_wraps = 1;
    o.wrap_s = o.wrap_t = TEXOPT_WRAP_CLAMP;
    texopt_coverage c;
    texopt_status st = texopt_coverage_measure(laid, &o, &c, err, err_len);
    if (st == TEXOPT_OK)
        st = texopt_chart_gap(laid, placed, NULL, &gap, err, err_len);
    if (st == TEXOPT_OK) {
        *br = *packed;
        br->scale = packed->scale * k; /* from the reduced layout in input texels */
        br->cost = (double)c.covered_texels;
        br->relative_cost = req->input_cost > 0 ? br->cost / req->input_cost : 0.0;
        br->packing_efficiency = br->cost / ((double)br->width * br->height);
        br->packings = 0;
        ds->packing_efficiency_direct = br->packing_efficiency;
        ds->reduce_direct_gap = gap;
    }
    return st;
}

/* The paper's pipeline (Liu et al. 2019): every chart but a sharing group's deformed however
 * far or turned, cut, packed with room for gap layers, its distortion reduced toward stage
 * 2's layout `stage2` in a fixed box with a gap layer around each piece (distortion_reduce.h),
 * then written as it is when its pieces keep the gutter apart, else packed again (pieces
 * without a layer may come to touch: the packer puts the gutters back); kept, on l->cut when
 * cut, when tighter than l's layout.
 * The deformed packing unreduced is no candidate: its distortion is what the bounds of
 * refine_if_tighter keep out. */
static texopt_status reduce_if_tighter(const texopt_mesh *charts, const double *stage2,
                                       const texopt_budget_request *req, domain_layout *l, texopt_domain_stats *ds,
                                       char *err, size_t err_len)
{
    if (req->keep_shape) /* sharing groups: their chart numbering must stay (cut_if_tighter) */
        return TEXOPT_OK;
    reduce_work w = {0};
    texopt_status st = refine_and_cut_all(charts, stage2, req, &w, ds, err, err_len);
    const texopt_mesh *laid = w.cut ? w.cut : charts;
    double gutter = req->pack.gutter > 0 ? req->pack.gutter : PACK_GUTTER;
    texopt_budget_request r = *req, reserved = *req;
    reserved.pack.gutter = (int)ceil(2.0 * GAP_LAYER * gutter) + 2; /* room for two layers */
    texopt_budget_result packed = {0}, repacked = {0}, direct = {0};
    if (st == TEXOPT_OK)
        st = texopt_budget_fit(laid, w.texel, &reserved, w.packed, &packed, err, err_len);
    if (st == TEXOPT_E_LIMIT) {
        reduce_work_free(&w);
        return TEXOPT_OK;
    }
    for (size_t i = 0; st == TEXOPT_OK && i < 2 * laid->vertex_count; i++)
        w.reference[i] *= packed.scale; /* the texel allocation at the budget's scale */
    texopt_distortion_reduce_options o = {0};
    o.threads = req->threads;
    o.gap_layer = GAP_LAYER * gutter;
    o.min_efficiency = req->efficiency_bound;
    if (st == TEXOPT_OK)
        st = texopt_distortion_reduce(laid, w.reference, w.packed, &o, w.reduced, &ds->reduce, req->monitor, err,
                                      err_len);
    if (st == TEXOPT_OK && !ds->reduce.refused)
        st = place_direct(laid, w.reduced, gutter, &packed, w.direct, &direct, ds, req, err, err_len);
    if (st == TEXOPT_OK && !ds->reduce.refused)
        st = texopt_budget_fit(laid, w.reduced, &r, w.repacked, &repacked, err, err_len);
    if (st == TEXOPT_E_LIMIT)
        st = TEXOPT_OK;
    if (st == TEXOPT_OK) {
        ds->has_reduce = 1;
        ds->packing_efficiency_deformed = packed.packing_efficiency;
        ds->packing_efficiency_reduced = repacked.packing_efficiency;
        ds->reduce_boundary =
            texopt_atlas_boundary_length(laid, w.reduced) *
            sqrt(texopt_layout_area(laid, w.reference, NULL) / texopt_layout_area(laid, w.reduced, NULL)) /
            packed.scale;
    }
    /* Written as it is when no piece was left out of the box and all keep the gutter apart. */
    int direct_ok = st == TEXOPT_OK && ds->reduce.charts_unboxed == 0 && ds->reduce_direct_gap >= gutter &&
                    direct.packing_efficiency > repacked.packing_efficiency;
    if (direct_ok) {
        double *swap = w.repacked;
        w.repacked = w.direct;
        w.direct = swap;
        repacked = direct;
    }
    if (st == TEXOPT_OK && repacked.packing_efficiency > l->br.packing_efficiency) {
        for (size_t i = 0; i < 2 * laid->vertex_count; i++)
            w.reduced[i] /= packed.scale; /* back to input texels, as stage 2's */
        free(l->texel_new);
        free(l->packed);
        texopt_mesh_destroy(l->cut);
        l->texel_new = w.reduced;
        l->packed = w.repacked;
        l->br = repacked;
        l->cut = w.cut;
        w.reduced = w.repacked = NULL;
        w.cut = NULL;
        ds->atlas_refine_kept = direct_ok ? ATLAS_REFINE_KEPT_DIRECT : ATLAS_REFINE_KEPT_REDUCED;
    }
    reduce_work_free(&w);
    return st;
}

/* Packing "refine": the charts of l->texel_new deformed toward axis-aligned shapes
 * (atlas_refine.h) and packed at the same budget; the tighter of the two packings (the
 * higher packing efficiency: fewer texture texels at a relative cost, more covered ones at
 * a texture size) replaces l's. A refined layout the budget cannot fit is not kept. */
static texopt_status refine_if_tighter(const texopt_mesh *charts, const texopt_budget_request *req, domain_layout *l,
                                       texopt_domain_stats *ds, char *err, size_t err_len)
{
    size_t n = 2 * (charts->vertex_count ? charts->vertex_count : 1);
    double *refined = malloc(n * sizeof *refined), *packed = malloc(n * sizeof *packed);
    double *stage2 = malloc(n * sizeof *stage2);
    uint8_t *keep_angle = charts_keeping_angle(charts, req->targets);
    texopt_budget_result br = {0};
    if (stage2)
        memcpy(stage2, l->texel_new, n * sizeof *stage2);
    texopt_status st = refined && packed && keep_angle && stage2
                           ? TEXOPT_OK
                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the refined layout");
    if (st == TEXOPT_OK)
        st = texopt_atlas_refine(charts, l->texel_new, req->keep_shape, keep_angle, TEXOPT_ATLAS_REFINE_MAX_DISTORTION,
                                 refined, &ds->atlas_refine, req->monitor, err, err_len);
    if (st == TEXOPT_OK) {
        st = texopt_budget_fit(charts, refined, req, packed, &br, err, err_len);
        if (st == TEXOPT_E_LIMIT) {
            st = TEXOPT_OK;
            br.packing_efficiency = 0;
        }
    }
    if (st == TEXOPT_OK) {
        ds->has_atlas_refine = 1;
        ds->packing_efficiency_unrefined = l->br.packing_efficiency;
        ds->packing_efficiency_refined = br.packing_efficiency;
        ds->atlas_refine_kept = br.packing_efficiency > l->br.packing_efficiency;
    }
    if (st == TEXOPT_OK && ds->atlas_refine_kept) {
        memcpy(l->texel_new, refined, n * sizeof *refined);
        memcpy(l->packed, packed, n * sizeof *packed);
        l->br = br;
    }
    if (st == TEXOPT_OK)
        st = cut_if_tighter(charts, refined, req, l, ds, err, err_len);
    if (st == TEXOPT_OK)
        st = reduce_if_tighter(charts, stage2, req, l, ds, err, err_len);
    free(refined);
    free(packed);
    free(stage2);
    free(keep_angle);
    return st;
}

/* Allocation, stage 2, budget + pack: the packed layout in output texels; progress of stage
 * 2 over [from, split], of the packing over [split, to]. */
static texopt_status layout_for_budget(texopt_job *job, const layout_run *run, int d, domain_layout *l, double from,
                                       double split, double to, char *err, size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    const texopt_params *p = run->p;
    texopt_domain_stats *ds = &run->domains[d];
    job_monitor *jm = &job->jm;
    double cost = p->relative_cost;
    if (p->budget == TEXOPT_BUDGET_TEXTURE_SIZE)
        cost = (double)p->texture_width * p->texture_height * EXPECTED_PACKING_EFFICIENCY /
               (double)(jd->input_coverage.covered_texels ? jd->input_coverage.covered_texels : 1);
    texopt_budget_request req;
    budget_request(job, run, jd, &req);
    texopt_status st = TEXOPT_OK;
    for (int round = 0; round < 2 && st == TEXOPT_OK; round++) {
        texopt_mesh_destroy(l->cut); /* texel_new and packed stay large enough for the mesh */
        l->cut = NULL;
        job_stage(jm, "stage2", from, split);
        st = solve_layout(job, run, d, cost, l->texel_new, err, err_len);
        if (st == TEXOPT_OK)
            st = job_check_cancel(jm, err, err_len);
        if (st != TEXOPT_OK)
            break;
        job_stage(jm, "pack", split, to);
        double t0 = job_now_seconds();
        /* a sharing group packs as one chart, its secondaries on the primary's texels */
        const texopt_mesh *charts = job_sharing(jd) ? &jd->share->view : job_layout_mesh(jd);
        st = texopt_budget_fit(charts, l->texel_new, &req, l->packed, &l->br, err, err_len);
        if (st == TEXOPT_OK && p->packing_refine)
            st = refine_if_tighter(charts, &req, l, ds, err, err_len);
        ds->seconds_pack = job_now_seconds() - t0;
        if (st != TEXOPT_OK || p->budget != TEXOPT_BUDGET_TEXTURE_SIZE || !run->allocating ||
            fabs(log(l->br.relative_cost / cost)) <= log(RESOLVE_RATIO) || !(l->br.relative_cost > 0))
            break;
        cost = l->br.relative_cost;
    }
    if (st == TEXOPT_OK) {
        ds->budget_scale = l->br.scale;
        job_stage_done(jm, "pack");
    }
    return st;
}

/* The layout methods at one budget: allocation, stage 2, budget + pack, re-bake; or the
 * input layout resized (the per-budget keep rules, domain_keep.h). */
static texopt_status run_layout_method(texopt_job *job, const layout_run *run, int d, double from, double to, char *err,
                                       size_t err_len)
{
    const job_domain *jd = &job->domains[d];
    const texopt_mesh *mesh = job_layout_mesh(jd);
    texopt_domain_stats *ds = &run->domains[d];
    job_output *out = run->out;
    const stage_weights *w = job->method->weights;
    double span = (to - from) / (w->stage2 + w->pack + w->bake);
    double pack_from = from + span * w->stage2, bake_from = pack_from + span * w->pack;
    size_t n = 2 * (mesh->vertex_count ? mesh->vertex_count : 1);
    domain_layout l = {malloc(n * sizeof(double)), malloc(n * sizeof(double)), {0}, NULL};
    texopt_status st =
        l.texel_new && l.packed ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the new layout");
    ds->input_layout_kept[0] = '\0';
    if (st == TEXOPT_OK)
        st = layout_for_budget(job, run, d, &l, from, pack_from, bake_from, err, err_len);
    ds->has_layout_check = 0;
    const texopt_mesh *laid = l.cut ? l.cut : mesh; /* the mesh texel_new and packed are on */
    if (job_input_layout_packs_better(job->model, laid, run->p, &l.br, st, ds) ||
        (st == TEXOPT_OK && job_layout_fails_check(job, run, d, laid, l.packed, &l.br, &st, err, err_len))) {
        free(l.texel_new);
        free(l.packed);
        texopt_mesh_destroy(l.cut);
        ds->repacked = 0;
        return job_run_input_method(job, run, d, bake_from, to, err, err_len);
    }
    if (st == TEXOPT_OK && run->with_stats)
        st = job_measure_loss_share(job, d, l.cut, l.texel_new, ds, err, err_len);
    if (st == TEXOPT_OK) {
        job_stats_record_distortion(laid, l.texel_new, ds);
        ds->output_width = l.br.width;
        ds->output_height = l.br.height;
        ds->cost_input = (double)jd->input_coverage.covered_texels;
        ds->cost_output = l.br.cost;
        ds->relative_cost = l.br.relative_cost;
        ds->packing_efficiency_input = jd->input_coverage.packing_efficiency;
        ds->packing_efficiency = l.br.packing_efficiency;
        ds->repacked = 1;
        double t0 = job_now_seconds();
        int size[2] = {l.br.width, l.br.height};
        st = job_rebake_domain(job, run, d, l.cut ? l.cut : jd->layout, l.packed, size, bake_from, to, err, err_len);
        ds->seconds_bake = job_now_seconds() - t0;
    }
    if (st == TEXOPT_OK && l.cut)
        st = job_output_write_cut_uvs(job->model, l.cut, l.packed, l.br.width, l.br.height, out, err, err_len);
    else if (st == TEXOPT_OK)
        job_output_write_uvs(job->model, mesh, l.packed, l.br.width, l.br.height, out->uvs);
    if (st == TEXOPT_OK && out->solved) {
        out->solved[d] = l.texel_new;
        l.texel_new = NULL;
        out->packed[d] = l.packed;
        l.packed = NULL;
        out->cut[d] = l.cut;
        l.cut = NULL;
        out->packed_size[2 * d] = l.br.width;
        out->packed_size[2 * d + 1] = l.br.height;
    }
    free(l.texel_new);
    free(l.packed);
    texopt_mesh_destroy(l.cut);
    return st;
}

double job_domain_weight(const texopt_job *job, int d)
{
    const texopt_model *model = job->model;
    if (!job->method->targets)
        return (double)model->domains[d].width * model->domains[d].height;
    double n = 0;
    for (int i = 0; i < model->domains[d].primitive_count; i++)
        n += (double)model->primitives[model->domains[d].primitives[i]].triangle_count;
    return n;
}

double job_total_domain_weight(const texopt_job *job)
{
    double total = 0;
    for (int d = 0; d < job->model->domain_count; d++)
        total += job_domain_weight(job, d);
    return total;
}

texopt_status job_run_budget(texopt_job *job, const layout_run *run, double from, double to, char *err, size_t err_len)
{
    const texopt_model *model = job->model;
    const texopt_params *p = run->p;
    texopt_status st = job_output_alloc(model, job->method->targets != NULL, run->out, err, err_len);
    double total = job_total_domain_weight(job), at = from;
    for (int d = 0; d < model->domain_count && st == TEXOPT_OK; d++) {
        double share = total > 0 ? (to - from) * job_domain_weight(job, d) / total : 0;
        texopt_domain_stats *ds = &run->domains[d];
        ds->relative_cost_requested = p->budget == TEXOPT_BUDGET_RELATIVE_COST ? p->relative_cost : -1;
        st = job_check_cancel(&job->jm, err, err_len);
        if (st == TEXOPT_OK && job->domains[d].kept == DOMAIN_KEPT_AS_IS)
            job_keep_domain(model, d, ds);
        else if (st == TEXOPT_OK && (!job->method->targets || job->domains[d].kept == DOMAIN_INPUT_RESIZED))
            st = job_run_input_method(job, run, d, at, at + share, err, err_len);
        else if (st == TEXOPT_OK)
            st = run_layout_method(job, run, d, at, at + share, err, err_len);
        at += share;
    }
    return st;
}
