/* compare.h - q_r-c_r curves of several layout methods.
 *
 * Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen",
 * section 5.1 (figures of loss against relative cost): every method (params.h: perceptual,
 * input, ssp, tewari, arap) is run through the product's own pipeline (pipeline.h) at every
 * requested relative cost c_r, its output is loaded back and evaluated against the input
 * with the whole-mesh loss q (evaluate.h). One pipeline job per method: its targets (stage 1)
 * are computed once, and each cost repeats only the per-budget part (allocation, stage 2,
 * packing, re-bake), which gives the same output as a separate run at that cost. With
 * reuse_layout, a layout method is laid out once, at the largest cost, and the smaller costs
 * resample that output's re-baked textures (the "input" method applied to it): faster still
 * but pessimistic (filtered twice, gutters scaled rather than re-padded, the allocation made
 * for the largest budget; on Fox at c_r = 0.3 the resampled points had 28-77 % more loss
 * than full runs before the allocation existed), so per-cost layouts are the default and the
 * figures of record. A method the pipeline refuses (not available yet,
 * unsupported model) leaves its points marked failed with the pipeline's message; the other
 * methods still run.
 *
 * Does not: draw anything (report.h), parse command lines. */
#ifndef TEXOPT_COMPARE_H
#define TEXOPT_COMPARE_H

#include <stddef.h>
#include <stdint.h>

#include "evaluate.h"
#include "model.h"
#include "monitor.h"
#include "params.h"
#include "status.h"

#define TEXOPT_COMPARE_MAX_COSTS 16

/* The measures a point can hold: one per texture (texture_keys.h: the core slots, then the
 * extensions' textures), then the lit luma of all maps (evaluate.h `lit`) at index
 * TEXOPT_COMPARE_LIT, named "lit". */
#define TEXOPT_COMPARE_LIT TEXOPT_TEXTURE_KEY_COUNT
#define TEXOPT_COMPARE_MEASURES (TEXOPT_TEXTURE_KEY_COUNT + 1)

typedef struct texopt_compare_point {
    double cost_requested;                        /* c_r asked of the pipeline */
    double cost_achieved;                         /* covered texels of the output / of the input */
    double q;                                     /* whole-mesh loss against the input */
    double q_by_texture[TEXOPT_COMPARE_MEASURES]; /* q of each measure the result measured
                                                  (texopt_compare_result.texture_measured; the
                                                  headline measure's entry is q); NAN
                                                  elsewhere */
    uint64_t texture_pixels;                      /* texture memory of the output */
    double packing_efficiency;
    double seconds_optimize, seconds_evaluate;
    texopt_status status; /* TEXOPT_OK, or why this point is missing */
    char message[200];
} texopt_compare_point;

typedef struct texopt_compare_curve {
    texopt_method method;
    int point_count;
    texopt_compare_point points[TEXOPT_COMPARE_MAX_COSTS];
    /* The output at the showcase cost, loaded (NULL when that run failed), its per-triangle
     * mean absolute luma error (evaluate.h triangle_error) and its evaluation in q's measure
     * (per-view GMSD; view_count 0 without a showcase), for the report. */
    texopt_model *showcase;
    double *showcase_triangle_error;
    texopt_evaluation showcase_evaluation;
} texopt_compare_curve;

typedef struct texopt_compare_options {
    texopt_params params;         /* base parameters; method, budget and lookups (those of
                                      `evaluate`) are set per run */
    const texopt_method *methods; /* method_count entries */
    int method_count;
    const double *costs; /* cost_count relative costs in (0, 4] */
    int cost_count;
    double showcase_cost;             /* the cost whose outputs are kept for the report; 0 ->
                                      the listed cost closest to 0.3 */
    texopt_evaluate_options evaluate; /* resolution, threads, lookups and the texture or lit
                                         that q measures (triangle_error ignored) */
    const char *work_dir;             /* temporary outputs; NULL -> $TMPDIR or /tmp */
    int reuse_layout;                 /* nonzero: each layout once, smaller costs resampled (fast,
                                      pessimistic for layout methods); 0: one run per point */
    int every_texture;                /* nonzero: besides q's measure, q of every other texture
                                      the input's materials bind (q_by_texture, extension
                                      textures too), and lit when it has a map besides base
                                      colour: the methods lay out for different signals (ssp
                                      and tewari read base colour, perceptual every texture),
                                      so one texture's q does not rank them on a model with
                                      several maps */
    const texopt_monitor *monitor;    /* cancel flag; progress as stage "compare" (per method) */
    /* NULL, or method_count entries: a non-NULL one is an existing output of that method at
     * costs[0] (e.g. a service job's result), measured instead of running the pipeline again;
     * only with cost_count == 1 and without reuse_layout. */
    const char *const *given_outputs;
} texopt_compare_options;

typedef struct texopt_compare_result {
    int curve_count;
    texopt_compare_curve curves[TEXOPT_METHOD_COUNT];
    int resolution;                                /* evaluation screen side */
    int mipmapped;                                 /* evaluated with mip-mapped lookups (evaluate.h) */
    int measure;                                   /* what q measured: a texture (texture_keys.h; base colour by
                                 default) or TEXOPT_COMPARE_LIT */
    int texture_measured[TEXOPT_COMPARE_MEASURES]; /* nonzero for the measures in the points'
                                                   q_by_texture: `measure`, and with
                                                   every_texture each other texture the
                                                   input binds, and lit (texopt_lit_has_maps) */
    double showcase_cost;
    texopt_cost input_cost;
    texopt_model *input; /* the input, loaded */
} texopt_compare_result;

/* Runs every method at every cost on the model at input_path. *out is filled on success
 * (even when some points failed: see their status) and freed with
 * texopt_compare_result_destroy. Fails only on bad options, an input that cannot be loaded,
 * cancellation or memory. */
texopt_status texopt_compare(const char *input_path, const texopt_compare_options *opt, texopt_compare_result *out,
                             char *err, size_t err_len);

void texopt_compare_result_destroy(texopt_compare_result *result);

/* The name of measure m of q_by_texture: the texture's (texopt_texture_key_name), or "lit". */
const char *texopt_compare_measure_name(int m);

/* Writes the curves as JSON (temp + fsync + rename). */
texopt_status texopt_compare_write_json(const texopt_compare_result *result, const char *path, char *err,
                                        size_t err_len);

/* The relative cost at which a curve reaches loss q_goal, by linear interpolation of q in
 * log(c_r) between its successful points (sorted by achieved cost); -1 when the curve never
 * gets that low or has fewer than one point. The "pixels at equal loss" figure. */
double texopt_compare_cost_at_loss(const texopt_compare_curve *curve, double q_goal);

#endif
