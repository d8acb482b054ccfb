/* map_patterns.h - texture patterns for the maps beyond base colour (issue 45): an emissive
 * "PLAY button" with sharp edges and small labels, an occlusion-roughness-metallic image with
 * fine scratches and cracks, and a normal map with the same scratches as grooves.
 *
 * Each pattern is defined per texel (x, y) of a w x h image from the texel's position in
 * [0,1]^2, so it looks the same at any size; lines are about w / 512 texels wide (at least
 * one), so at 512 and above they are as sharp as the image allows. Every edge is hard (no
 * anti-aliasing): the worst case for ringing. Deterministic (fixed generators).
 *   "play"      emissive: black; a red disc (0.9, 0.15, 0.1) centred at (0.5, 0.4) of radius
 *               0.2 holding a white right-pointing triangle; a label of cyan (0.2, 0.9, 1.0)
 *               glyph strokes (fixtures.c's "half" glyphs, 16 texels per glyph at 512) in
 *               the band v in [0.68, 0.8], u in [0.2, 0.8].
 *   "orm"       R occlusion 1 with three jagged dark cracks (0.25), G roughness 0.55 and B
 *               metallic 1 with 90 thin scratches (G 0.1, B 0) inside the "visor" disc
 *               centred at (0.6, 0.4) of radius 0.3; outside the disc no detail.
 *   "grooves"   tangent-space normal map, flat (0.5, 0.5, 1) but for the same scratches as
 *               grooves: each side of a scratch tilts 0.45 across it, unit length.
 * Does not: build models or files (grid_glb.h, tests/tools/make_fixture.c do). */
#ifndef TEXOPT_TEST_MAP_PATTERNS_H
#define TEXOPT_TEST_MAP_PATTERNS_H

/* The RGB of pattern `pattern` at texel (x, y) of a w x h image; 0, or -1 when the name is
 * none of the above. */
int map_pattern_texel(const char *pattern, int x, int y, int w, int h, float rgb[3]);

#endif
