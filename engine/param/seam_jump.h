/* seam_jump.h - how far an input texture jumps across one seam of its layout.
 *
 * Two triangles that share a 3D edge but not its texel corners (an input seam) each read
 * the texture along that edge through their own UVs. Where the artist painted the two
 * sides as one surface the readings agree; where each island was painted apart (colour
 * regions cut at seams, as low-poly models do) they jump. A new chart that grows across a
 * seam that jumps puts the jump inside one chart, where the re-bake resamples it onto its
 * texel grid (a blurred, stair-stepped edge), so rechart.h's region growing asks this.
 * Does not: decide a tolerance, or read other triangles than the two. */
#ifndef TEXOPT_SEAM_JUMP_H
#define TEXOPT_SEAM_JUMP_H

#include <stdint.h>

#include "image.h"
#include "mesh.h"

/* The mean absolute difference (over 8 points along the 3D edge triangles t and u share
 * and over the first three channels, values as stored, 1 = full range) between image
 * read bilinearly through t's texel corners and through u's (the mesh's frame scaled to
 * the image's size, its wrap modes). 0 when the two share no edge or its texel corners. */
double texopt_seam_jump(const texopt_mesh *mesh, const texopt_image *image, uint32_t t, uint32_t u);

#endif
