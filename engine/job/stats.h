/* stats.h - the statistics of one optimisation job and their JSON form.
 *
 * Does: hold what the pipeline measured (stage timings, costs in and out, relative cost
 * reached, packing efficiency, texture sizes, stage-1 loss statistics, stage-2 energy and
 * distortion) and write them as one JSON document with cJSON, atomically.
 * Does not: measure anything itself (the job, engine/job/, fills the struct, file_cost.c the written
 * file's costs).
 *
 * The numbers are those Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen", report: cost c = covered texels (eq. 20), relative cost c_r
 * (eq. 21), symmetric Dirichlet distortion (eq. 24), share of triangles with E <= eps
 * (Fig. 16). A value that was not measured (for example stage 1 under method "input") is
 * left out of the JSON rather than written as 0. */
#ifndef TEXOPT_STATS_H
#define TEXOPT_STATS_H

#include <stddef.h>

#include "atlas_quality.h"
#include "atlas_refine.h"
#include "chart_unfold.h"
#include "distortion.h"
#include "distortion_reduce.h"
#include "layout_check.h"
#include "map_check.h"
#include "params.h"
#include "status.h"

typedef struct texopt_image_stats {
    int image;        /* index into the model's images */
    const char *name; /* URI or name, may be NULL */
    const char *slot; /* "baseColor", "normal", ... (first material slot using it) */
    int input_width, input_height;
    int output_width, output_height;
    int rewritten; /* 0 when the original bytes were kept */
} texopt_image_stats;

/* What the resize check (resize_check.h) wrote for a domain. */
typedef enum texopt_resize_check_kept {
    TEXOPT_RESIZE_CHECK_LAYOUT = 0, /* the new layout */
    TEXOPT_RESIZE_CHECK_RESIZE,     /* the input layout, its images resized with Lanczos-3 */
    TEXOPT_RESIZE_CHECK_INPUT_FIT   /* the input layout, images re-baked by the fit where it won */
} texopt_resize_check_kept;

#define ATLAS_REFINE_KEPT_CUT 2
#define ATLAS_REFINE_KEPT_REDUCED 3
#define ATLAS_REFINE_KEPT_DIRECT 4

typedef struct texopt_domain_stats {
    int domain;
    size_t triangles, charts;
    size_t new_charts;             /* params.charts new: the domain's new charts (0: the input's kept) ... */
    size_t new_chart_fallbacks;    /* ... of which laid out by Tutte because the parameterizer failed */
    int input_width, input_height; /* texel frame */
    int output_width, output_height;
    double cost_input, cost_output;  /* unique covered texels; cost_output, relative_cost and
                                        packing_efficiency are those of the written file
                                        (file_cost.h), as `texopt info` measures them */
    double relative_cost_requested;  /* < 0 when the budget was a texture size */
    double relative_cost;            /* cost_output / cost_input */
    double packing_efficiency_input; /* covered texels / frame texels */
    double packing_efficiency;
    int has_atlas_quality;                               /* the written file's layout ... */
    texopt_atlas_quality atlas_quality;                  /* ... by Liu et al. 2019's measures (atlas_quality.h) */
    int repacked;                                        /* 1 when charts were packed anew */
    char input_layout_kept[320];                         /* a layout method's domain that kept its input layout:
                                        why ("" when it was laid out anew) */
    int has_resize_check;                                /* perceptual: its new layout against its input layout
                                        resized to the same pixels (resize_check.c
                                        job_keep_resize_if_better) ... */
    int resize_check_kept;                               /* ... which was written: texopt_resize_check_kept */
    double q_resize_check_layout, q_resize_check_resize; /* on the choice's 12 views, of the
                                        measure that decided (map_check.h) */
    int resize_check_decided_by;                         /* that measure: a texture key, or TEXOPT_MAP_LIT */
    texopt_map_q resize_check_maps_layout, resize_check_maps_resize; /* every measure's q */
    int resize_check_has_input_fit;           /* the input layout re-baked by the fit was measured */
    texopt_map_q resize_check_maps_input_fit; /* ... every measure's q of its mix (resize_check.h) */
    int resize_check_input_fit_images;        /* ... the images the mix takes from the fit */
    double seconds_resize_check;              /* the resize and the evaluation of both */
    int image_count;
    texopt_image_stats *images;

    int has_stage1;
    double loss_mean, loss_max, area_scale_mean, within_epsilon_share;
    long long evaluations;
    size_t close_up_triangles;
    size_t hessian_floor_triangles; /* targets raised to the Hessian floor (params.h) */

    int has_stage2;
    int stage2_iterations;
    double energy_initial, energy_final;
    size_t flipped;
    int has_scaffold; /* params.bijective: stage 2 with scaffolds (scaffold.h) */
    int scaffold_rounds;
    size_t scaffold_charts, scaffold_skipped_charts, scaffold_triangles;
    texopt_unfold_report unfold; /* params.bijective: charts overlapping themselves in the input
                                    layout, laid out anew or left (chart_unfold.h) */
    int has_atlas_refine;        /* params.packing_refine: charts deformed before packing (atlas_refine.h) */
    int atlas_refine_kept;       /* the refined layout packed tighter and was kept; ATLAS_REFINE_KEPT_CUT:
                                    its cut (chart_cut.h) packed tighter still and was kept;
                                    ATLAS_REFINE_KEPT_REDUCED: the reduced one (below) was;
                                    ATLAS_REFINE_KEPT_DIRECT: the reduced one as it is */
    double packing_efficiency_unrefined, packing_efficiency_refined; /* of the two packings */
    double packing_efficiency_cut; /* the refined charts cut (chart_cut.h) and packed */
    texopt_atlas_refine_report atlas_refine;
    int has_reduce; /* every chart deformed, cut, packed, reduced (distortion_reduce.h), packed again */
    size_t reduce_charts_refined, reduce_pieces;
    double reduce_boundary; /* boundary length of the reduced layout scaled to stage 2's area
                               (texels of stage 2's layout) */
    double packing_efficiency_deformed, packing_efficiency_reduced; /* before and after the reduction */
    double packing_efficiency_direct; /* the reduced layout as it is in the deformed packing's frame */
    double reduce_direct_gap;         /* its pieces' smallest distance there, texels (chart_gap.h) */
    texopt_distortion_reduce_report reduce;
    int has_loss_share; /* loss of every triangle under the solved layout */
    double solved_within_epsilon_share, solved_loss_mean, solved_loss_max;
    int has_distortion;
    double distortion_input, distortion_output;      /* symmetric Dirichlet, mean */
    texopt_distortion distortion_in, distortion_out; /* every metric (distortion.h) */
    int has_allocation;                              /* targets rescaled to the budget (target_allocation.h) */
    double allocation_scale;                         /* the common factor s on the singular values */
    double allocation_capped_share;                  /* triangles at input density (a cap reached) */
    double allocation_lossless_share;                /* targets grown as lossless (target_allocation.h) */
    int has_layout_check;                            /* a new layout was checked (layout_check.h) ... */
    texopt_layout_check layout_check;                /* ... with this result; failed: the input layout kept */
    double budget_scale;                             /* with repacked: the uniform scale budget.h applied after
                                        stage 2 (output texels per solved texel); near 1 when
                                        the allocation predicted the cost well */

    double seconds_mesh, seconds_stage1, seconds_stage2, seconds_pack, seconds_bake;
    double seconds_loss_share;   /* the per-triangle losses under the solved layout */
    double seconds_layout_check; /* the last layout check (layout_check.h) */
} texopt_domain_stats;

typedef struct texopt_job_stats {
    const char *method;
    const char *budget;                /* "relative_cost", "texture_size" or "target_loss" */
    double relative_cost;              /* requested, or the one the target_loss search chose */
    int texture_width, texture_height; /* requested, with the texture_size budget */
    double epsilon, lambda_min;
    int iterations, threads;
    unsigned long long seed;
    int refinements;           /* rounds asked for (0: none) */
    int refine_lit;            /* the refinement asked to read the lit render */
    int mipmapped;             /* the lookups tuned for and measured with were mip-mapped */
    double packing_efficiency; /* packing refine's bound as resolved (0: plain) */
    int bijective;             /* stage 2 with scaffolds was asked for */
    int packing_refine;        /* packing "refine" was asked for */
    double hessian_floor;      /* perceptual's floor factor (0: none) */
    int metric_candidates;     /* perceptual makes the metric candidates */
    int resize_check;          /* perceptual checks its layouts against the input layout resized */
    texopt_charts charts;      /* keep the input's or new (then parameterizer) */
    texopt_parameterizer parameterizer;
    size_t vertices_split; /* charts new: model vertices copied where a new chart boundary runs */
    double seconds_load, seconds_save, seconds_total;
    int has_search;            /* budget target_loss: the search over the relative cost */
    double target_loss;        /* the q asked for */
    int target_reached;        /* 0 when even the largest cost searched missed it */
    int search_evaluations;    /* layouts baked and evaluated by the search */
    double search_cost_below;  /* largest cost tried that missed the target (0: none) */
    double search_q_below;     /* its q */
    int has_allocation_choice; /* perceptual: q of the candidate layouts (job_candidates.c), on the
                                    choice's 12 icosahedron views, not on q's 20 */
    double q_allocated, q_allocated_dense, q_uniform, q_hessian, q_signal_stretch;
    int allocation_dense_made;                      /* 0: no target met the cap at input density, so the dense
                                    candidate would have been the allocated one */
    int metric_candidates_made;                     /* the hessian and signal_stretch candidates were made
                                    (params.h metric_candidates) */
    const char *allocation_chosen;                  /* a candidate_name of job_candidates.c (static) */
    double seconds_choice_evaluate;                 /* the evaluation pass of the candidates */
    double seconds_other_candidate;                 /* the discarded candidates' stage 2, packing and bake */
    int refinement_rounds;                          /* closed-loop rounds tried on the kept candidate ... */
    int refinement_kept;                            /* ... and kept (each lowered q_refinement) */
    int refinement_lit;                             /* the rounds' screen: lit (evaluate.h), else base colour */
    double q_refinement_before, q_refinement_after; /* on the refinement's 12 cameras */
    double seconds_refinement;                      /* its renders and rounds, and those of the candidate refined
                                    beside it (job_candidates.c refine_best) */
    int has_evaluation;                             /* params.evaluate: whole-mesh loss of the result */
    double q;                                       /* evaluate.h: mean GMSD over the 20 views */
    int eval_resolution;
    double seconds_evaluate;
    int has_q_maps;                         /* with has_evaluation and a statistics file: ... */
    texopt_map_q q_maps;                    /* ... q of every map the materials bind and lit, same views */
    int has_file_cost;                      /* the written file measured (file_cost.h) ... */
    double seconds_file_cost;               /* ... in this time */
    unsigned long long file_texture_pixels; /* sum of width x height over its images */
    unsigned long long file_texture_bytes;  /* their encoded sizes */
    unsigned long long file_bytes;          /* the whole file */
    int domain_count;
    texopt_domain_stats *domains;
} texopt_job_stats;

/* Frees the per-domain arrays the pipeline allocated. Accepts NULL. */
void texopt_job_stats_destroy(texopt_job_stats *stats);

/* The JSON document as a malloc'ed NUL-terminated string (caller frees with free()). */
texopt_status texopt_stats_to_json(const texopt_job_stats *stats, char **json, char *err, size_t err_len);

/* Writes the JSON document to path (temporary file, fsync, rename). */
texopt_status texopt_stats_write(const texopt_job_stats *stats, const char *path, char *err, size_t err_len);

#endif
