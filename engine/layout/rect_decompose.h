/* rect_decompose.h - rectangles of an axis-aligned chart and their packing (Liu et al. 2019, 3.2).
 *
 * An axis-aligned chart (a simple counter-clockwise polygon whose edges are all parallel to
 * the axes) is cut into rectangles by a motorcycle graph (Eppstein et al. 2008): from each
 * reflex corner, one or both of its two inward axis directions (the continuation of its
 * incoming edge, the reversed continuation of its outgoing one) carries a motorcycle; all
 * move at the same speed and each stops where it reaches the boundary or a trail another
 * has already left (ties go to the lower index, which passes). With at least one per reflex
 * corner every face is a rectangle. Different choices give different decompositions; the
 * candidate score of eq. 11 picks among random ones: PE - 0.1 BL1 / BL0 (PE: packing
 * efficiency of the rectangles, BL0 / BL1: boundary length before / after), candidates with
 * a rectangle of aspect ratio above 20 or a PE below the bound discarded.
 * The packer is a skyline bottom-left packer (rectangles by decreasing height, each where
 * its bottom is lowest, then leftmost) over a few strip widths, keeping the one with the
 * smallest bounding box; each rectangle is padded by `padding` on its right and top and is
 * never turned (rectpack2D, the paper's packer, may turn them: an L's two rectangles 20x10
 * and 10x20 fill a square only so).
 * The trails themselves are given too, for cutting a triangle mesh along them (chart_cut.h).
 * Not here: cutting the triangle mesh along the trails, the flattening that makes a
 * deformed chart exactly axis-aligned (axis_deform.h stops short of it), the fall-backs of
 * the paper when no candidate reaches the bound, and distortion reduction (3.3). */
#ifndef TEXOPT_RECT_DECOMPOSE_H
#define TEXOPT_RECT_DECOMPOSE_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

typedef struct texopt_rect {
    double x0, y0, x1, y1;
} texopt_rect;

/* Reflex corners of the polygon (n points, 2 each), in point order. */
size_t texopt_rect_reflex_corners(const double *xy, size_t n);

/* Decomposes the polygon; choice[k] for the k-th reflex corner: bit 0 traces the incoming
 * edge's continuation, bit 1 the outgoing edge's reversed continuation (0 counts as 3).
 * *rects (caller frees) gets *count rectangles tiling the polygon. Fails on a polygon that
 * is not axis-aligned, counter-clockwise and simple. */
texopt_status texopt_rect_decompose(const double *xy, size_t n, const uint8_t *choice, texopt_rect **rects,
                                    size_t *count, char *err, size_t err_len);

/* Packs n rectangles (w[i] x h[i], each padded by `padding` on its right and top) into a
 * strip; x, y get the lower left corners, *width x *height the bounding box. Returns the
 * packing efficiency sum(w h) / (width height). */
double texopt_rect_pack(const double *w, const double *h, size_t n, double padding, double *x, double *y, double *width,
                        double *height);

typedef struct texopt_rect_trail {
    size_t corner;         /* the polygon point (a reflex corner) the motorcycle left from */
    double x0, y0, x1, y1; /* the trail: from the corner to where it stopped */
    double time;           /* its length, the time it stopped */
} texopt_rect_trail;

/* The trails of the decomposition texopt_rect_decompose makes with the same choice, one per
 * motorcycle (*trails: caller frees). */
texopt_status texopt_rect_trails(const double *xy, size_t n, const uint8_t *choice, texopt_rect_trail **trails,
                                 size_t *count, char *err, size_t err_len);

typedef struct texopt_rect_choice {
    double score, efficiency, boundary_ratio; /* eq. 11 and its parts, BL1 / BL0 */
    size_t rect_count;
    int candidates_kept; /* of those drawn, passing both filters */
} texopt_rect_choice;

/* Draws `candidates` random motorcycle choices for the polygon (seeded), scores each by
 * eq. 11 with the rectangles packed alone (padding as above) and writes the best one's
 * choice bytes into best_choice (reflex-corner count of them). Fails when no candidate
 * passes the aspect and efficiency filters. */
texopt_status texopt_rect_choose(const double *xy, size_t n, int candidates, uint64_t seed, double padding,
                                 double efficiency_bound, uint8_t *best_choice, texopt_rect_choice *out, char *err,
                                 size_t err_len);

#endif
