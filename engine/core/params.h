/* params.h - what a user asks of one optimisation job.
 *
 * A zero-initialised texopt_params means the defaults (the paper's, where it has one):
 * perceptual method, relative cost 1.0, epsilon 0.03 (not the paper's 0.01: below), 100
 * iterations, lambda_min 0.1, all cores, seed 0, no evaluation, 4 refinement rounds, no chart
 * reshaping. texopt_params_resolve fills the zeros; texopt_params_validate says which field
 * is out of range. */
#ifndef TEXOPT_PARAMS_H
#define TEXOPT_PARAMS_H

#include <stdint.h>

#include "status.h"

/* Stage 1's loss threshold when the user gives none. Every job has a texel budget that the
 * targets are rescaled to (target_allocation.h), so epsilon does not fix how much each triangle loses,
 * only the targets' relative areas: the larger it is, the further triangles whose loss rises
 * slowly (shading, mild gradients) shrink next to those whose loss rises steeply (edges,
 * text), which then get a larger share of any budget. The paper's 0.01 gave edges too small
 * a share at low costs; 0.02-0.05 measured better, 0.03 (the plateau's middle) below 0.01 at
 * 40 of the 48 points of the eight benchmark models (BENCHMARKS.md@9f788a8, "Stage 1's loss
 * threshold"). */
#define TEXOPT_DEFAULT_EPSILON 0.03

/* Method paper's loss threshold when the user gives none: the paper's own (its section 5). */
#define TEXOPT_PAPER_EPSILON 0.01

/* Rounds of the closed-loop refinement when the user gives none (job_refine.c). Two
 * were chosen on Fox, spot and Duck at epsilon 0.01; at 0.03 four are better at most points of
 * the small models and of WaterBottle, level on DamagedHelmet, whose whole job stays under
 * 60 s on two idle cores (BENCHMARKS.md@9f788a8 "Correction (lead, ninth session)"). */
#define TEXOPT_DEFAULT_REFINEMENTS 4

/* The floor under stage 1's targets when the user gives none: a triangle whose area scale is
 * below that of this factor times tewari's target (tewari.h, the Hessian metric) takes that
 * target scaled by it. Stage 1 judges a triangle on its one-ring's pixels, where a sliver
 * with sharp detail (Duck's eyes) weighs little; the Hessian metric sees its texels alone. At
 * 0.5 q fell at 21 of the 48 points of the eight benchmark models by over 5% (Duck 0.32-0.76x,
 * DamagedHelmet to 0.76x) and rose at 5 by over 5% (spot 1.22x, Fox 1.08-1.14x, CesiumMan
 * 1.07x, all at c_r 0.1-0.5); perceptual below tewari at 46 of 48 against 40 (BENCHMARKS.md@9f788a8
 * "A floor at half the Hessian metric's targets, re-measured"). */
#define TEXOPT_DEFAULT_HESSIAN_FLOOR 0.5

/* Liu et al. 2019's packing-efficiency bound PE_bound (their default), which packing
 * "refine" holds its packings to. */
#define TEXOPT_DEFAULT_PACKING_EFFICIENCY 0.8

typedef enum texopt_method {
    TEXOPT_METHOD_PERCEPTUAL = 0, /* stage 1 + stage 2 (the paper) */
    TEXOPT_METHOD_INPUT,          /* the input layout, textures resized to the budget */
    TEXOPT_METHOD_SSP,            /* Sander et al. 2002 signal-stretch targets */
    TEXOPT_METHOD_TEWARI,         /* Tewari et al. 2004 targets */
    TEXOPT_METHOD_ARAP,           /* isometric local-global layout */
    TEXOPT_METHOD_PAPER,          /* Sun et al. 2022 as written (docs/method.md) */
    TEXOPT_METHOD_COUNT
} texopt_method;

typedef enum texopt_budget {
    TEXOPT_BUDGET_RELATIVE_COST = 0, /* covered texels of the output / of the input */
    TEXOPT_BUDGET_TEXTURE_SIZE,      /* output texture width x height */
    TEXOPT_BUDGET_TARGET_LOSS,       /* smallest cost whose whole-mesh loss is at most this */
    TEXOPT_BUDGET_COUNT
} texopt_budget;

/* Which charts a job lays out (issue 41): the input's (keep) or new disk charts cut from the
 * mesh and parameterized anew (param/rechart.h), re-baked from the input's texture through
 * the input's UVs. */
typedef enum texopt_charts { TEXOPT_CHARTS_KEEP = 0, TEXOPT_CHARTS_NEW, TEXOPT_CHARTS_COUNT } texopt_charts;

/* How new charts are laid out (param/param_*.h); ABF, the zero value, kept L2 stretch
 * nearest 1 on every sample model (docs/benchmarks.md "New charts with each
 * parameterization method"). */
typedef enum texopt_parameterizer {
    TEXOPT_PARAMETERIZER_ABF = 0,
    TEXOPT_PARAMETERIZER_LSCM,
    TEXOPT_PARAMETERIZER_TUTTE,
    TEXOPT_PARAMETERIZER_SQUARE,
    TEXOPT_PARAMETERIZER_COUNT
} texopt_parameterizer;

typedef struct texopt_params {
    texopt_method method;
    texopt_budget budget;
    double relative_cost; /* (0, 4]; 0 -> 1.0 */
    int texture_width;    /* with TEXOPT_BUDGET_TEXTURE_SIZE */
    int texture_height;
    double target_loss; /* with TEXOPT_BUDGET_TARGET_LOSS */
    double epsilon;     /* loss threshold of stage 1; 0 -> TEXOPT_DEFAULT_EPSILON
                           (TEXOPT_PAPER_EPSILON for method paper) */
    int iterations;     /* most Bayesian-optimisation polish iterations per triangle (the
                               polish stops earlier once it stops paying); 0 -> 100 */
    double lambda_min;  /* smallest singular value stage 1 may choose; 0 -> 0.1 */
    int threads;        /* 0 -> every core */
    uint64_t seed;
    int evaluate;                       /* non-zero: run the whole-mesh evaluation after the bake */
    int eval_resolution;                /* evaluation screen side in pixels; 0 -> automatic */
    int refinements;                    /* perceptual: most rounds of the closed-loop refinement of the
                               kept layout by its on-screen error (job_refine.c);
                               0 -> TEXOPT_DEFAULT_REFINEMENTS, -1 -> none */
    int refine_lit;                     /* perceptual: 1: the refinement's screen is the lit render
                               (evaluate.h `lit`, every image baked each round) when the
                               material has a map a light reads besides base colour; -1: base
                               colour's (job_refine.c); 0 -> 1 */
    int mipmapped;                      /* non-zero: the texture lookups the layout is tuned for and its q
                               is measured with (the perceptual candidates' choice, the
                               refinement's screens, `evaluate`, the target_loss search) are
                               prefiltered (mip-mapped, anisotropic; evaluate.h), as real-time
                               renderers draw; 0: bilinear, the paper's setting */
    double packing_efficiency;          /* [0, 1): the bound PE_bound of packing "refine" (Liu et al.
                               2019): the rectangle decompositions must reach it and the
                               distortion reduction may not lower a packing below it; a value
                               given turns refine on; 0 -> TEXOPT_DEFAULT_PACKING_EFFICIENCY
                               with refine, else 0 */
    double hessian_floor;               /* perceptual: (0, 1], the floor's factor under stage 1's targets
                               (TEXOPT_DEFAULT_HESSIAN_FLOOR); 0 -> that default, -1 -> none */
    int metric_candidates;              /* perceptual: 1: the signal metrics' targets (tewari.h, ssp.h),
                               solved as they are, are candidate layouts beside stage 1's
                               (job_candidates.c); 0 -> 1, -1 -> not made */
    int resize_check;                   /* perceptual: 1: a domain whose new layout does not beat its
                               input layout resized or re-baked at the same pixels writes
                               that instead (resize_check.h); 0 -> 1, -1 -> never */
    int lossless_textures;              /* non-zero: replaced textures are written as PNG even where the
                               input's were JPEG (texopt_model_edit.lossless), so that a q
                               measured from the file is the layout's and not the encoding's
                               (compare.h sets it); 0: a JPEG stays a JPEG */
    int bijective;                      /* non-zero: stage 2 solves with scaffold triangles around each
                               chart (layout/scaffold.h), so no chart overlaps itself;
                               TEXOPT_CHARTS_NEW resolves to 1 */
    int packing_refine;                 /* non-zero ("refine"): each chart of the new layout is deformed
                               toward an axis-aligned shape before packing (layout/
                               atlas_refine.h), and the tighter of the two packings kept;
                               0 ("plain"): packed as stage 2 left it */
    texopt_charts charts;               /* keep the input's charts (default) or cut new ones */
    texopt_parameterizer parameterizer; /* with TEXOPT_CHARTS_NEW: how each new chart is laid out */
} texopt_params;

const char *texopt_method_name(texopt_method method);

/* "keep", "new"; and back (-1 for an unknown name). */
const char *texopt_charts_name(texopt_charts charts);
int texopt_charts_from_name(const char *name);

/* "abf", "lscm", "tutte", "square" (NULL out of range); and back (-1 for an unknown name). */
const char *texopt_parameterizer_name(texopt_parameterizer p);
int texopt_parameterizer_from_name(const char *name);
/* Returns TEXOPT_METHOD_COUNT for an unknown name. */
texopt_method texopt_method_from_name(const char *name);

/* Replaces zero fields by their defaults. */
void texopt_params_resolve(texopt_params *params);

/* The refinement's measure as users name it: "baseColor" or "lit" (texopt_params.refine_lit:
 * -1, or 1 or the default 0), and back: 0 for "baseColor", 1 for "lit", -1 for an unknown
 * name; texopt_refine_lit_of turns that 0 or 1 into refine_lit's -1 or 1. */
const char *texopt_refine_measure_name(int refine_lit);
int texopt_refine_measure_from_name(const char *name);
int texopt_refine_lit_of(int measure);

/* The lookups as users name them: "bilinear" or "mipmapped" (texopt_params.mipmapped), and
 * back; -1 for an unknown name. */
const char *texopt_lookup_name(int mipmapped);
int texopt_lookup_from_name(const char *name);

/* The packing as users name it: "plain" or "refine" (texopt_params.packing_refine), and
 * back; -1 for an unknown name. */
const char *texopt_packing_name(int refine);
int texopt_packing_from_name(const char *name);

/* Refinement rounds as users count them (0: none), from and into the field's encoding, where
 * 0 is the default and -1 none. The getter reads a resolved params struct. */
int texopt_params_refinement_rounds(const texopt_params *params);
void texopt_params_set_refinement_rounds(texopt_params *params, int rounds);

/* The Hessian floor's factor as users give it, in [0, 1] (0: none), from and into the field's
 * encoding; the getter reads a resolved params struct. */
double texopt_params_hessian_floor(const texopt_params *params);
void texopt_params_set_hessian_floor(texopt_params *params, double factor);

/* Checks a resolved params struct; the message names the offending field. */
texopt_status texopt_params_validate(const texopt_params *params, char *err, size_t err_len);

#endif
