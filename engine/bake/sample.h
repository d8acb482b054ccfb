/* sample.h - bilinear texture lookup in texel coordinates with glTF wrap modes.
 *
 * Texel coordinates: texel (i, j) covers [i, i+1) x [j, j+1) and its centre is at
 * (i + 0.5, j + 0.5); x grows to the right, y downwards (row 0 is the first image row,
 * v = 0 in glTF). A lookup at (x, y) blends the four texels whose centres surround the
 * point, as OpenGL's GL_LINEAR does; the wrap mode decides which texel stands beyond an
 * edge: REPEAT tiles, CLAMP (CLAMP_TO_EDGE) repeats the edge texel, MIRROR
 * (MIRRORED_REPEAT) reflects with period 2*size. This is the lookup the paper's renderer
 * does (Sun et al. 2022, eq. 11 uses its weights as the bake matrix). */
#ifndef TEXOPT_SAMPLE_H
#define TEXOPT_SAMPLE_H

#include "image.h"
#include "model.h"

/* The four texels and weights of a bilinear lookup at (x, y). index[k] = row * width + col
 * after wrapping, in the order (x0,y0), (x1,y0), (x0,y1), (x1,y1); weights are
 * non-negative and sum to 1. Two entries may name the same texel (at a clamped edge or on
 * a one-texel-wide texture); callers must add, not assign. width, height > 0. Non-finite
 * x or y are treated as 0. */
void texopt_bilinear_footprint(int width, int height, texopt_wrap wrap_s, texopt_wrap wrap_t, double x, double y,
                               int index[4], double weight[4]);

/* The same lookup as wrapped columns and rows: the four texels are (col[0],row[0]),
 * (col[1],row[0]), (col[0],row[1]), (col[1],row[1]) with weights in that order. Cheaper for
 * callers that need the texel's row and column (no division). */
void texopt_bilinear_cells(int width, int height, texopt_wrap wrap_s, texopt_wrap wrap_t, double x, double y,
                           int col[2], int row[2], double weight[4]);

/* Bilinear lookup of all channels of img at (x, y) into out[img->channels]. */
void texopt_sample_bilinear(const texopt_image *img, texopt_wrap ws, texopt_wrap wt, double x, double y, float *out);

/* Luma of one pixel: BT.601 0.299 R + 0.587 G + 0.114 B for 3-4 channels (the weights the
 * GMSD reference converts colour with); the first channel for 1-2 channel images. */
float texopt_luma(const float *rgb, int channels);

#endif
