/* texel_fit.h - least-squares texel values for bilinear reconstruction.
 *
 * Does: given, for some texels of an image, reference values at four sub-texel points (the
 * centres of the texel's 2x2 quarters, offsets (+-1/4, +-1/4) texel from its centre), find
 * the texel values whose bilinear reconstruction (texel centres at i + 0.5, as a renderer
 * samples) best matches those references:
 *     x = argmin sum_samples |bilinear(x, s) - ref(s)|^2 + ridge |x - x0|^2
 * over the texels the samples touch and the caller did not fix; x0 is the image as given
 * (e.g. a prefiltered bake), which the ridge keeps texels that few samples see close to.
 * Four samples per texel make the problem well posed wherever texels are sampled: a plain
 * point sample at each texel centre would give x = ref and the renderer's second bilinear
 * interpolation would blur the signal again, which is what this fit undoes. The minimum is
 * taken subject to bounds: every texel stays within the range of the input under it (the range
 * callback; a texel no sample of its own sees takes the union of the ranges of the sampled
 * texels whose samples it takes part in; [0, 1] without a callback). Unbounded, the fit of a
 * sharp edge overshoots on both sides (it inverts a blur, as any sharpening does): a glowing
 * shape would get a dark halo and a bright rim no input texel holds.
 * Solved by conjugate gradients with a Jacobi preconditioner on the 3x3-stencil normal
 * equations; then, up to three times, the texels outside their bounds are clamped and held
 * there, and the others solved again with those held (an active set that only grows); a final
 * clamp holds what is still outside. Rows are shared among threads in fixed blocks and every
 * sum is taken in block order, so the result does not depend on the thread count. Memory:
 * 2 + 4 + (12 + 2) * channels bytes per texel besides the image, and 36 per free texel next
 * to a chart border.
 * Does not: decide where the references come from or which texels to fix (rebake.h does).
 *
 * Implements the "least-squares fit for bilinear reconstruction" alternative of the re-bake
 * step of Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen" (the same principle as their eq. 11, applied to the whole
 * texture). */
#ifndef TEXOPT_TEXEL_FIT_H
#define TEXOPT_TEXEL_FIT_H

#include <stddef.h>
#include <stdint.h>

#include "image.h"
#include "status.h"

/* Sub-samples per texel, in the order (-,-), (+,-), (-,+), (+,+) of (dx, dy) = +-1/4. */
#define TEXOPT_TEXEL_FIT_SAMPLES 4

/* Writes the four references of sampled texel (x, y): 4 * channels floats, sample-major.
 * Called from several threads at once, about 1.1 times per sampled texel (rows at the
 * borders of the fit's row blocks are asked twice), so the references never all sit in
 * memory: at 4096² that would be a gigabyte. */
typedef void (*texopt_texel_reference_fn)(void *user, int x, int y, float *out);

/* Writes the range of the input under sampled texel (x, y): per channel the lowest value
 * into lo and the highest into hi (channels floats each), e.g. of every input texel its
 * square's lookups read. Called as the reference callback is. */
typedef void (*texopt_texel_range_fn)(void *user, int x, int y, float *lo, float *hi);

typedef struct texopt_texel_fit_problem {
    texopt_image *image;    /* in: x0 at every texel; out: fitted values where changeable */
    const uint8_t *sampled; /* per texel: non-zero when its four sub-samples take part */
    texopt_texel_reference_fn reference;
    texopt_texel_range_fn range; /* NULL: every texel's range is [0, 1] */
    void *user;                  /* passed to reference and range */
    const uint8_t *fixed;        /* per texel: non-zero keeps its value (NULL: none fixed) */
    double ridge;                /* > 0: weight of |x - x0|^2 (e.g. 1e-3) */
    double tolerance;            /* stop when the preconditioned residual fell by this factor */
    int max_iterations;          /* > 0 */
    int threads;                 /* 0 -> 1 */
} texopt_texel_fit_problem;

typedef struct texopt_texel_fit_report {
    size_t unknowns; /* texels the fit could change */
    int iterations;
    double residual_ratio; /* final / initial preconditioned residual norm */
} texopt_texel_fit_report;

/* Fits in place. changed (may be NULL; width * height bytes) gets 1 for every texel the fit
 * could change, others untouched. report may be NULL. Samples whose bilinear footprint
 * leaves the image are ignored. */
texopt_status texopt_texel_fit(const texopt_texel_fit_problem *problem, uint8_t *changed,
                               texopt_texel_fit_report *report, char *err, size_t err_len);

#endif
