/* stats.c - the job statistics as JSON with cJSON (see stats.h for what each field means). */
#include "stats.h"

#include <cjson/cJSON.h>
#include <stdlib.h>

#include "atomic_file.h"
#include "build_info.h"
#include "params.h"

void texopt_job_stats_destroy(texopt_job_stats *stats)
{
    if (!stats)
        return;
    for (int d = 0; d < stats->domain_count; d++)
        free(stats->domains[d].images);
    free(stats->domains);
    stats->domains = NULL;
    stats->domain_count = 0;
}

static cJSON *size_array(int w, int h)
{
    int v[2] = {w, h};
    return cJSON_CreateIntArray(v, 2);
}

static void add_images(cJSON *dom, const texopt_domain_stats *d)
{
    cJSON *arr = cJSON_AddArrayToObject(dom, "images");
    for (int i = 0; i < d->image_count; i++) {
        const texopt_image_stats *s = &d->images[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "image", s->image);
        if (s->name)
            cJSON_AddStringToObject(o, "name", s->name);
        if (s->slot)
            cJSON_AddStringToObject(o, "slot", s->slot);
        cJSON_AddItemToObject(o, "input_size", size_array(s->input_width, s->input_height));
        cJSON_AddItemToObject(o, "output_size", size_array(s->output_width, s->output_height));
        cJSON_AddBoolToObject(o, "rewritten", s->rewritten);
        cJSON_AddItemToArray(arr, o);
    }
}

/* The new layout against its input layout resized to the same pixels (resize_check.c
 * job_keep_resize_if_better). */
static void add_resize_check(cJSON *o, const texopt_domain_stats *d)
{
    cJSON *r = cJSON_AddObjectToObject(o, "resize_check");
    cJSON_AddStringToObject(r, "views", "icosahedron");
    cJSON_AddNumberToObject(r, "q_layout", d->q_resize_check_layout);
    cJSON_AddNumberToObject(r, "q_resize", d->q_resize_check_resize);
    static const char *const kept[] = {"layout", "resize", "input_fit"};
    cJSON_AddStringToObject(r, "kept", kept[d->resize_check_kept]);
    if (d->resize_check_has_input_fit)
        cJSON_AddNumberToObject(r, "input_fit_images", d->resize_check_input_fit_images);
    cJSON_AddStringToObject(r, "decided_by", texopt_map_measure_name(d->resize_check_decided_by));
    cJSON *maps = cJSON_AddObjectToObject(r, "maps");
    for (int m = 0; m < TEXOPT_MAP_MEASURES; m++) {
        if (!d->resize_check_maps_layout.measured[m])
            continue;
        cJSON *q = cJSON_AddObjectToObject(maps, texopt_map_measure_name(m));
        cJSON_AddNumberToObject(q, "q_layout", d->resize_check_maps_layout.q[m]);
        cJSON_AddNumberToObject(q, "q_resize", d->resize_check_maps_resize.q[m]);
        if (d->resize_check_has_input_fit)
            cJSON_AddNumberToObject(q, "q_input_fit", d->resize_check_maps_input_fit.q[m]);
    }
    cJSON_AddNumberToObject(r, "seconds", d->seconds_resize_check);
}

static void add_stage_stats(cJSON *dom, const texopt_domain_stats *d)
{
    if (d->has_stage1) {
        cJSON *s1 = cJSON_AddObjectToObject(dom, "stage1");
        cJSON_AddNumberToObject(s1, "loss_mean", d->loss_mean);
        cJSON_AddNumberToObject(s1, "loss_max", d->loss_max);
        cJSON_AddNumberToObject(s1, "area_scale_mean", d->area_scale_mean);
        cJSON_AddNumberToObject(s1, "within_epsilon_share", d->within_epsilon_share);
        cJSON_AddNumberToObject(s1, "evaluations", (double)d->evaluations);
        cJSON_AddNumberToObject(s1, "close_up_triangles", (double)d->close_up_triangles);
        cJSON_AddNumberToObject(s1, "hessian_floor_triangles", (double)d->hessian_floor_triangles);
    }
    if (d->has_stage2) {
        cJSON *s2 = cJSON_AddObjectToObject(dom, "stage2");
        cJSON_AddNumberToObject(s2, "iterations", d->stage2_iterations);
        cJSON_AddNumberToObject(s2, "energy_initial", d->energy_initial);
        cJSON_AddNumberToObject(s2, "energy_final", d->energy_final);
        cJSON_AddNumberToObject(s2, "flipped_triangles", (double)d->flipped);
        if (d->has_scaffold) {
            cJSON *sc = cJSON_AddObjectToObject(s2, "scaffold");
            cJSON_AddNumberToObject(sc, "rounds", d->scaffold_rounds);
            cJSON_AddNumberToObject(sc, "charts", (double)d->scaffold_charts);
            cJSON_AddNumberToObject(sc, "skipped_charts", (double)d->scaffold_skipped_charts);
            cJSON_AddNumberToObject(sc, "triangles", (double)d->scaffold_triangles);
            cJSON_AddNumberToObject(sc, "overlapping_input_charts", (double)d->unfold.overlapping);
            cJSON_AddNumberToObject(sc, "unfolded_charts", (double)d->unfold.unfolded);
            cJSON_AddNumberToObject(sc, "unfolded_by_tutte", (double)d->unfold.tutte);
            cJSON_AddNumberToObject(sc, "kept_shared_charts", (double)d->unfold.kept);
            cJSON_AddNumberToObject(sc, "shared_charts_on_primary", (double)d->unfold.followed);
            cJSON_AddNumberToObject(sc, "kept_mirrored_charts", (double)d->unfold.mirrored);
            cJSON_AddNumberToObject(sc, "kept_charts_not_disks", (double)d->unfold.not_disks);
        }
        if (d->has_loss_share) {
            cJSON_AddNumberToObject(s2, "within_epsilon_share", d->solved_within_epsilon_share);
            cJSON_AddNumberToObject(s2, "loss_mean", d->solved_loss_mean);
            cJSON_AddNumberToObject(s2, "loss_max", d->solved_loss_max);
        }
    }
    if (d->has_allocation) {
        cJSON *a = cJSON_AddObjectToObject(dom, "allocation");
        cJSON_AddNumberToObject(a, "scale", d->allocation_scale);
        cJSON_AddNumberToObject(a, "capped_share", d->allocation_capped_share);
        cJSON_AddNumberToObject(a, "lossless_share", d->allocation_lossless_share);
    }
    if (d->has_distortion) {
        cJSON *ds = cJSON_AddObjectToObject(dom, "distortion");
        cJSON_AddNumberToObject(ds, "symmetric_dirichlet_input", d->distortion_input);
        cJSON_AddNumberToObject(ds, "symmetric_dirichlet_output", d->distortion_output);
        cJSON_AddItemToObject(ds, "input", texopt_distortion_json(&d->distortion_in));
        cJSON_AddItemToObject(ds, "output", texopt_distortion_json(&d->distortion_out));
    }
}

static void add_atlas_refine(cJSON *o, const texopt_domain_stats *d)
{
    const texopt_atlas_refine_report *r = &d->atlas_refine;
    cJSON *a = cJSON_AddObjectToObject(o, "atlas_refine");
    cJSON_AddStringToObject(a, "kept",
                            d->atlas_refine_kept == ATLAS_REFINE_KEPT_DIRECT    ? "direct"
                            : d->atlas_refine_kept == ATLAS_REFINE_KEPT_REDUCED ? "reduced"
                            : d->atlas_refine_kept == ATLAS_REFINE_KEPT_CUT     ? "cut"
                            : d->atlas_refine_kept                              ? "refined"
                                                                                : "plain");
    cJSON_AddNumberToObject(a, "charts", (double)r->charts_refined);
    cJSON_AddNumberToObject(a, "skipped_charts", (double)r->charts_skipped);
    cJSON_AddNumberToObject(a, "too_distorted_charts", (double)r->charts_too_distorted);
    cJSON_AddNumberToObject(a, "kept_angle_charts", (double)r->charts_kept_angle);
    cJSON_AddNumberToObject(a, "packing_efficiency_before", d->packing_efficiency_unrefined);
    cJSON_AddNumberToObject(a, "packing_efficiency_after", d->packing_efficiency_refined);
    cJSON_AddNumberToObject(a, "boundary_length_before", r->boundary_before);
    cJSON_AddNumberToObject(a, "boundary_length_after", r->boundary_after);
    cJSON_AddNumberToObject(a, "charts_cut", (double)r->charts_cut);
    cJSON_AddNumberToObject(a, "pieces", (double)r->pieces);
    cJSON_AddNumberToObject(a, "cuts", (double)r->cuts);
    cJSON_AddNumberToObject(a, "vertices_split", (double)r->vertices_split);
    cJSON_AddNumberToObject(a, "boundary_length_cut", r->boundary_cut);
    cJSON_AddNumberToObject(a, "packing_efficiency_cut", d->packing_efficiency_cut);
    cJSON_AddNumberToObject(a, "cut_seconds", r->cut_seconds);
    cJSON_AddNumberToObject(a, "distortion", r->distortion);
    cJSON_AddNumberToObject(a, "max_angle_error", r->max_angle_error);
    cJSON_AddNumberToObject(a, "seconds", r->seconds);
    if (!d->has_reduce)
        return;
    const texopt_distortion_reduce_report *q = &d->reduce;
    cJSON *b = cJSON_AddObjectToObject(a, "reduction");
    cJSON_AddNumberToObject(b, "charts", (double)d->reduce_charts_refined);
    cJSON_AddNumberToObject(b, "pieces", (double)d->reduce_pieces);
    cJSON_AddNumberToObject(b, "boundary_length", d->reduce_boundary);
    cJSON_AddNumberToObject(b, "packing_efficiency_before", d->packing_efficiency_deformed);
    cJSON_AddNumberToObject(b, "packing_efficiency_after", d->packing_efficiency_reduced);
    cJSON_AddNumberToObject(b, "packing_efficiency_direct", d->packing_efficiency_direct);
    cJSON_AddNumberToObject(b, "direct_gap", d->reduce_direct_gap);
    cJSON_AddBoolToObject(b, "refused", q->refused);
    cJSON_AddNumberToObject(b, "unboxed_charts", (double)q->charts_unboxed);
    cJSON_AddNumberToObject(b, "charts_without_gap", (double)q->charts_without_gap);
    cJSON_AddNumberToObject(b, "rounds", q->rounds);
    cJSON_AddNumberToObject(b, "scale", q->scale);
    cJSON_AddNumberToObject(b, "distortion_before", q->distortion_start);
    cJSON_AddNumberToObject(b, "distortion_after", q->distortion);
    cJSON_AddNumberToObject(b, "box_efficiency_before", q->efficiency_start);
    cJSON_AddNumberToObject(b, "box_efficiency_after", q->efficiency);
    cJSON_AddNumberToObject(b, "seconds", q->seconds);
}

static cJSON *domain_json(const texopt_domain_stats *d)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "domain", d->domain);
    cJSON_AddNumberToObject(o, "triangles", (double)d->triangles);
    cJSON_AddNumberToObject(o, "charts", (double)d->charts);
    if (d->new_charts) {
        cJSON *nc = cJSON_AddObjectToObject(o, "new_charts");
        cJSON_AddNumberToObject(nc, "charts", (double)d->new_charts);
        cJSON_AddNumberToObject(nc, "tutte_fallbacks", (double)d->new_chart_fallbacks);
    }
    cJSON_AddItemToObject(o, "input_size", size_array(d->input_width, d->input_height));
    cJSON_AddItemToObject(o, "output_size", size_array(d->output_width, d->output_height));
    cJSON_AddNumberToObject(o, "cost_input", d->cost_input);
    cJSON_AddNumberToObject(o, "cost_output", d->cost_output);
    if (d->relative_cost_requested > 0)
        cJSON_AddNumberToObject(o, "relative_cost_requested", d->relative_cost_requested);
    cJSON_AddNumberToObject(o, "relative_cost", d->relative_cost);
    cJSON_AddNumberToObject(o, "packing_efficiency_input", d->packing_efficiency_input);
    cJSON_AddNumberToObject(o, "packing_efficiency", d->packing_efficiency);
    if (d->has_atlas_quality)
        cJSON_AddItemToObject(o, "atlas_quality", texopt_atlas_quality_json(&d->atlas_quality));
    if (d->has_layout_check)
        cJSON_AddItemToObject(o, "layout_check", texopt_layout_check_json(&d->layout_check));
    cJSON_AddBoolToObject(o, "repacked", d->repacked);
    if (d->input_layout_kept[0])
        cJSON_AddStringToObject(o, "input_layout_kept", d->input_layout_kept);
    if (d->has_resize_check)
        add_resize_check(o, d);
    if (d->repacked)
        cJSON_AddNumberToObject(o, "budget_scale", d->budget_scale);
    if (d->has_atlas_refine)
        add_atlas_refine(o, d);
    add_stage_stats(o, d);
    cJSON *t = cJSON_AddObjectToObject(o, "seconds");
    cJSON_AddNumberToObject(t, "mesh", d->seconds_mesh);
    cJSON_AddNumberToObject(t, "stage1", d->seconds_stage1);
    cJSON_AddNumberToObject(t, "stage2", d->seconds_stage2);
    if (d->has_loss_share)
        cJSON_AddNumberToObject(t, "loss_share", d->seconds_loss_share);
    cJSON_AddNumberToObject(t, "pack", d->seconds_pack);
    cJSON_AddNumberToObject(t, "bake", d->seconds_bake);
    if (d->has_layout_check)
        cJSON_AddNumberToObject(t, "layout_check", d->seconds_layout_check);
    add_images(o, d);
    return o;
}

static cJSON *job_json(const texopt_job_stats *s)
{
    cJSON *root = cJSON_CreateObject();
    texopt_build_info_add_json(root);
    cJSON_AddStringToObject(root, "method", s->method ? s->method : "unknown");
    cJSON *p = cJSON_AddObjectToObject(root, "params");
    cJSON_AddStringToObject(p, "budget", s->budget ? s->budget : "unknown");
    if (s->texture_width > 0)
        cJSON_AddItemToObject(p, "texture_size", size_array(s->texture_width, s->texture_height));
    else if (s->has_search)
        cJSON_AddNumberToObject(p, "target_loss", s->target_loss);
    else
        cJSON_AddNumberToObject(p, "relative_cost", s->relative_cost);
    cJSON_AddNumberToObject(p, "epsilon", s->epsilon);
    cJSON_AddNumberToObject(p, "lambda_min", s->lambda_min);
    cJSON_AddNumberToObject(p, "iterations", s->iterations);
    cJSON_AddNumberToObject(p, "threads", s->threads);
    cJSON_AddNumberToObject(p, "seed", (double)s->seed);
    cJSON_AddNumberToObject(p, "refinements", s->refinements);
    cJSON_AddStringToObject(p, "refine_by", texopt_refine_measure_name(s->refine_lit));
    cJSON_AddStringToObject(p, "lookup", texopt_lookup_name(s->mipmapped));
    cJSON_AddNumberToObject(p, "packing_efficiency", s->packing_efficiency);
    cJSON_AddBoolToObject(p, "bijective", s->bijective);
    cJSON_AddStringToObject(p, "packing", texopt_packing_name(s->packing_refine));
    cJSON_AddNumberToObject(p, "hessian_floor", s->hessian_floor);
    cJSON_AddBoolToObject(p, "metric_candidates", s->metric_candidates);
    cJSON_AddBoolToObject(p, "resize_check", s->resize_check);
    cJSON_AddStringToObject(p, "charts", texopt_charts_name(s->charts));
    if (s->charts == TEXOPT_CHARTS_NEW) {
        cJSON_AddStringToObject(p, "parameterizer", texopt_parameterizer_name(s->parameterizer));
        cJSON_AddNumberToObject(root, "vertices_split", (double)s->vertices_split);
    }
    cJSON *t = cJSON_AddObjectToObject(root, "seconds");
    cJSON_AddNumberToObject(t, "load", s->seconds_load);
    cJSON_AddNumberToObject(t, "save", s->seconds_save);
    if (s->has_file_cost)
        cJSON_AddNumberToObject(t, "file_cost", s->seconds_file_cost);
    cJSON_AddNumberToObject(t, "total", s->seconds_total);
    if (s->has_search) {
        cJSON *q = cJSON_AddObjectToObject(root, "target_search");
        cJSON_AddNumberToObject(q, "target_loss", s->target_loss);
        cJSON_AddBoolToObject(q, "reached", s->target_reached);
        cJSON_AddNumberToObject(q, "relative_cost", s->relative_cost);
        cJSON_AddNumberToObject(q, "q", s->q);
        cJSON_AddNumberToObject(q, "evaluations", s->search_evaluations);
        if (s->search_cost_below > 0) {
            cJSON_AddNumberToObject(q, "relative_cost_below", s->search_cost_below);
            cJSON_AddNumberToObject(q, "q_below", s->search_q_below);
        }
    }
    if (s->has_allocation_choice) {
        cJSON *a = cJSON_AddObjectToObject(root, "allocation_choice");
        cJSON_AddNumberToObject(a, "q_allocated", s->q_allocated);
        if (s->allocation_dense_made)
            cJSON_AddNumberToObject(a, "q_allocated_dense", s->q_allocated_dense);
        cJSON_AddNumberToObject(a, "q_uniform", s->q_uniform);
        if (s->metric_candidates_made) {
            cJSON_AddNumberToObject(a, "q_hessian", s->q_hessian);
            cJSON_AddNumberToObject(a, "q_signal_stretch", s->q_signal_stretch);
        }
        cJSON_AddStringToObject(a, "chosen", s->allocation_chosen ? s->allocation_chosen : "");
        cJSON *t = cJSON_AddObjectToObject(a, "seconds");
        cJSON_AddNumberToObject(t, "evaluate", s->seconds_choice_evaluate);
        cJSON_AddNumberToObject(t, "other_candidate", s->seconds_other_candidate);
        cJSON *r = cJSON_AddObjectToObject(a, "refinement");
        cJSON_AddNumberToObject(r, "rounds", s->refinement_rounds);
        cJSON_AddNumberToObject(r, "kept", s->refinement_kept);
        if (s->refinement_rounds > 0) {
            cJSON_AddStringToObject(r, "measure", s->refinement_lit ? "lit" : "baseColor");
            cJSON_AddNumberToObject(r, "q_before", s->q_refinement_before);
            cJSON_AddNumberToObject(r, "q_after", s->q_refinement_after);
        }
        cJSON_AddNumberToObject(r, "seconds", s->seconds_refinement);
    }
    if (s->has_evaluation) {
        cJSON *e = cJSON_AddObjectToObject(root, "evaluation");
        cJSON_AddNumberToObject(e, "q", s->q);
        cJSON_AddNumberToObject(e, "resolution", s->eval_resolution);
        cJSON_AddStringToObject(e, "lookup", texopt_lookup_name(s->mipmapped));
        cJSON_AddNumberToObject(e, "seconds", s->seconds_evaluate);
        cJSON *maps = s->has_q_maps ? cJSON_AddObjectToObject(e, "q_maps") : NULL;
        for (int m = 0; maps && m < TEXOPT_MAP_MEASURES; m++)
            if (s->q_maps.measured[m])
                cJSON_AddNumberToObject(maps, texopt_map_measure_name(m), s->q_maps.q[m]);
    }
    if (s->has_file_cost) {
        cJSON *f = cJSON_AddObjectToObject(root, "file_cost");
        cJSON_AddNumberToObject(f, "texture_pixels", (double)s->file_texture_pixels);
        cJSON_AddNumberToObject(f, "texture_bytes", (double)s->file_texture_bytes);
        cJSON_AddNumberToObject(f, "bytes", (double)s->file_bytes);
    }
    cJSON *arr = cJSON_AddArrayToObject(root, "domains");
    for (int d = 0; d < s->domain_count; d++)
        cJSON_AddItemToArray(arr, domain_json(&s->domains[d]));
    return root;
}

texopt_status texopt_stats_to_json(const texopt_job_stats *stats, char **json, char *err, size_t err_len)
{
    *json = NULL;
    cJSON *root = job_json(stats);
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the statistics JSON");
    *json = text;
    return TEXOPT_OK;
}

texopt_status texopt_stats_write(const texopt_job_stats *stats, const char *path, char *err, size_t err_len)
{
    char *text;
    texopt_status st = texopt_stats_to_json(stats, &text, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    size_t len = 0;
    while (text[len])
        len++;
    st = texopt_write_file_atomic(path, text, len, err, err_len);
    free(text);
    return st;
}
