/* gmsd.h - Gradient Magnitude Similarity Deviation (Xue, Zhang, Mou, Bovik 2013, "Gradient
 * Magnitude Similarity Deviation: A Highly Efficient Perceptual Image Quality Index").
 *
 * Exactly the authors' MATLAB reference on luma images in [0, 1] (values on the 0..255
 * scale give the same result, T is scaled accordingly):
 *   1. 2x2 mean filter, conv2 'same' (zero beyond the last row/column), keep every second
 *      pixel starting with the first: the downsampled image has ceil(w/2) x ceil(h/2)
 *      pixels, pixel (i, j) = mean of source pixels (2i..2i+1, 2j..2j+1), zeros outside.
 *   2. Prewitt gradients dx = [1 0 -1; 1 0 -1; 1 0 -1]/3, dy = dx', conv2 'same' with zero
 *      padding; gradient magnitude m = sqrt(gx^2 + gy^2).
 *   3. GMS = (2 m1 m2 + T) / (m1^2 + m2^2 + T), T = 170 / 255^2.
 *   4. GMSD = standard deviation of the GMS map with N-1 normalisation (MATLAB std2).
 *
 * Mask rule (our extension; the reference has none). mask[i] != 0 marks a covered source
 * pixel. A downsampled pixel is "covered" when all of its in-image 2x2 source pixels are
 * covered. A downsampled pixel enters the deviation when it and every in-image pixel of its
 * 3x3 Prewitt support are covered. So a GMS value never sees an uncovered pixel: background
 * cannot create fake edges. Out-of-image neighbours are zero padding exactly as in the
 * reference, so an all-covered mask gives the same value as mask == NULL. Fewer than two
 * counted pixels give 0 (no deviation to measure). GMSD(x, x) is exactly 0.
 *
 * Not here: colour to luma (sample.h texopt_luma), rendering. */
#ifndef TEXOPT_GMSD_H
#define TEXOPT_GMSD_H

typedef struct texopt_gmsd_workspace texopt_gmsd_workspace;

/* A workspace for images of up to max_width x max_height; NULL on bad size or no memory. */
texopt_gmsd_workspace *texopt_gmsd_workspace_create(int max_width, int max_height);

/* Accepts NULL. */
void texopt_gmsd_workspace_destroy(texopt_gmsd_workspace *ws);

/* GMSD of two width x height luma images (row-major) with an optional mask (NULL = every
 * pixel). Uses ws's buffers (the image must fit the workspace). Returns NaN on bad
 * arguments (NULL images, sizes <= 0 or beyond the workspace). */
double texopt_gmsd_ws(texopt_gmsd_workspace *ws, const float *reference, const float *distorted,
                      const unsigned char *mask, int width, int height);

/* The reference side prepared once for many distorted images under one mask (the stage-1
 * loss compares every candidate with the same reference): which downsampled pixels count
 * and the reference's gradient magnitude there. texopt_gmsd_against then returns exactly
 * (bit for bit) what texopt_gmsd_ws returns for the same images and mask, at about half the
 * cost. */
typedef struct texopt_gmsd_reference texopt_gmsd_reference;

/* For images of up to max_width x max_height; NULL on bad size or no memory. */
texopt_gmsd_reference *texopt_gmsd_reference_create(int max_width, int max_height);

/* Accepts NULL. */
void texopt_gmsd_reference_destroy(texopt_gmsd_reference *ref);

/* Prepares `reference` (width x height, mask as in texopt_gmsd_ws, NULL = every pixel).
 * Returns 0 on bad arguments, 1 otherwise. */
int texopt_gmsd_reference_set(texopt_gmsd_reference *ref, const float *reference, const unsigned char *mask, int width,
                              int height);

/* GMSD of the prepared reference and `distorted` (same size); ws must hold that size.
 * NaN on bad arguments. */
double texopt_gmsd_against(texopt_gmsd_workspace *ws, const texopt_gmsd_reference *ref, const float *distorted);

/* Where the last texopt_gmsd_against(ws, ref, ...) found the gradients alike: per source
 * pixel (ref's width x height, row-major) the GMS value of the downsampled pixel it falls
 * in, or -1 where that pixel did not enter the deviation. GMSD is the deviation of these
 * values over the downsampled pixels (each appears in up to 2 x 2 source pixels). */
void texopt_gmsd_similarity_map(const texopt_gmsd_workspace *ws, const texopt_gmsd_reference *ref, float *map);

/* The same with a temporary workspace (allocates; NaN also when out of memory). */
double texopt_gmsd(const float *reference, const float *distorted, const unsigned char *mask, int width, int height);

#endif
