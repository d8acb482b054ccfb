/* fixtures.h - textured models generated in memory for the unit tests.
 *
 * Every fixture is a complete texopt_model with no glTF document: one primitive, one
 * material whose base colour (TEXCOORD_0, REPEAT/REPEAT) is one RGB image, and texture
 * domains already built with texopt_model_build_domains. Free it with texopt_model_destroy.
 * Each returns NULL when an argument is out of range, the pattern name is unknown, or
 * memory runs out.
 *
 * Conventions (see engine/core/image.h and engine/model/mesh.h): the texel position of UV (u, v) in a
 * W x H texture is (W u, H v); image row y holds v in [y/H, (y+1)/H). All generated UV
 * triangles have positive signed area in (u, v) and their 3D winding is counter-clockwise
 * seen from outside, so a fixture has no flipped triangle unless a test makes one.
 *
 * Texture patterns (3 channels, values in [0,1], defined per texel (x, y)):
 *   "flat"      one colour (0.6, 0.4, 0.2) everywhere.
 *   "half"      left half (x < W/2) flat (0.6, 0.4, 0.2); right half dense detail: black
 *               text-like strokes, one texel wide, on white, in 8x8 glyph cells chosen by a
 *               fixed hash (horizontal, vertical and diagonal strokes: sharp edges).
 *   "stripes0"  vertical black/white stripes, 4 texels wide (period 8 along x).
 *   "stripes45" diagonal black/white stripes, 4 texels wide along x + y (period 8).
 *   "checker"   8 x 8 board of black/white squares (square side max(1, W/8) x max(1, H/8)).
 *   "gradient"  r = (x + 0.5)/W, g = (y + 0.5)/H, b = 0.25: smooth, no edges.
 *   "play", "orm", "grooves": the maps beyond base colour of map_patterns.h. */
#ifndef TEXOPT_TEST_FIXTURES_H
#define TEXOPT_TEST_FIXTURES_H

#include <stddef.h>
#include <stdint.h>

#include "image.h"
#include "model.h"

/* Text-like glyph strokes: 1 where texel (x, y) is ink. The strokes of an 8x8 cell come from
 * a fixed hash of the cell, and row/column 7 stay blank as spacing between glyphs. */
int fixture_glyph_ink(int x, int y);

/* Fills an allocated image (any size, 3 or more channels; channel 4 is set to 1) with the
 * named pattern. Returns 0, or -1 when the pattern is unknown or the image has fewer than
 * 3 channels. */
int fixture_fill_pattern(texopt_image *img, const char *pattern);

/* Gives an RGB image an alpha channel holding the luma of the named pattern (RGB kept):
 * "stripes0" cuts 4-texel columns, "checker" blocks of an eighth of the side. Returns 0, or -1
 * when the pattern is unknown, the image is not RGB or memory runs out (img unchanged). */
int fixture_add_alpha(texopt_image *img, const char *pattern);

/* A tangent-space normal map with edges in X and in Y (at different periods, so a quarter
 * turn changes which channel carries which stripes), encoded in [0, 1], unit length; any
 * size, 3 or more channels. */
void fixture_fill_normal_map(texopt_image *img);

/* Appends a side x side RGB image (zeros) to the model and binds it to `slot` of material 0;
 * returns it (valid until the next addition), or NULL. Domains are not rebuilt. */
texopt_image *fixture_add_slot_image(texopt_model *m, texopt_slot slot, int side);

/* Re-bakes ref->images[image] (read over ref's UVs, repeat wrap) into cand->images[image]
 * (over cand's UVs, allocated with its size and ref's channels); both models must share
 * their vertex and triangle lists. normal_map: turn the tangent-space XY with each triangle
 * (rebake.h). Returns 0, or -1 on any failure. */
int fixture_rebake(const texopt_model *ref, texopt_model *cand, int image, int normal_map);

/* A model from raw arrays (copied): positions (3 per vertex), uvs (2 per vertex),
 * triangles (3 per triangle), with one tex_w x tex_h RGB texture of `pattern`. The building
 * block of the other fixtures, and the way a test builds an odd layout (mirrored, flipped,
 * wrapped, degenerate). Indices are not checked against vertex_count: tests of bad input
 * can build bad models. */
texopt_model *fixture_model_from_arrays(const float *positions, const float *uvs, size_t vertex_count,
                                        const uint32_t *triangles, size_t triangle_count, int tex_w, int tex_h,
                                        const char *pattern);

/* The unit square z = 0, positions (x, y, 0) with UV = (x, y): 4 vertices (0,0), (1,0),
 * (1,1), (0,1) in that order, 2 triangles (0,1,2) and (0,2,3), covering the whole
 * tex_size x tex_size texture. */
texopt_model *fixture_textured_quad(int tex_size, const char *pattern);

/* Splits m's one primitive in two: triangles from `first` on become a second primitive of a
 * copy of its material (material 1); rebuilds the domains. Returns 0 on success. */
int fixture_split_primitive(texopt_model *m, size_t first);

/* An n x n grid of quads over [0,1]^2 (z = 0, UV = (x, y)): (n+1)^2 vertices, 2 n^2
 * triangles, one chart covering the whole texture. Vertex (i, j) (i along x) is
 * j * (n + 1) + i; quad (i, j) gives triangles 2(j n + i) and 2(j n + i) + 1. */
texopt_model *fixture_grid(int n, int tex_size, const char *pattern);

/* The unit cube [0,1]^3 exported the way glTF exporters do: 6 faces x 4 vertices (24 model
 * vertices, 12 triangles), so the weld must find 8 points. UV layout with 3 charts, each
 * face a 1/4 x 1/4 square of UV:
 *   - a strip of the 4 side faces front (+Z), right (+X), back (-Z), left (-X) at
 *     u in [0,1], v in [0.375, 0.625], neighbours sharing UV edges (10 UV vertices; the
 *     left face's far edge and the front face's near edge are the same 3D edge at u = 1 and
 *     u = 0: a seam);
 *   - top (+Y) alone at u in [0.125, 0.375], v in [0.75, 1];
 *   - bottom (-Y) alone at u in [0.625, 0.875], v in [0, 0.25].
 * So 18 UV vertices, 8 points, 3 charts, covered fraction 6/16 = 0.375 (exact in texels
 * when tex_size is a multiple of 8). Texture pattern "checker". Faces are in the order
 * front, right, back, left, top, bottom; face f owns triangles 2f, 2f + 1. */
texopt_model *fixture_cube_with_seams(int tex_size);

/* A unit-radius UV sphere centred at the origin, poles on the y axis: `segments` around
 * (>= 3), `rings` from pole to pole (>= 2). u = s / segments, v = r / rings (v = 0 at the
 * north pole y = +1); the u = 0 and u = 1 columns are a seam (same positions, bit-exact).
 * Pole rows are fans of one triangle per segment with their own pole vertex at
 * u = (s + 0.5) / segments, so no triangle is degenerate. Counts: 2 segments (rings - 1)
 * triangles; (segments + 1)(rings - 1) + 2 segments vertices; segments (rings - 1) + 2
 * points; one chart. Texture pattern "checker". */
texopt_model *fixture_uv_sphere(int segments, int rings, int tex_size);

#endif
