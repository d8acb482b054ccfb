/* texel_map.h - the affine map of one triangle between two texel layouts, its rotation, and
 * the turn that rotation gives a tangent-space normal map's encoded XY.
 *
 * The re-bake (rebake.h) turns a normal map's XY by the rotation of each triangle's map so
 * that a renderer deriving tangents from the new UVs shades as before; the evaluation
 * (evaluate.h) turns the candidate's XY back by the same rotation to compare both maps in
 * the reference's tangent frame. Both compute it here so that one undoes the other exactly.
 * Texel positions are image-frame (x right, y down); normal XY follow glTF (X = +u, Y = -v),
 * encoded in [0, 1]. Does not: sample images, or decide whether a map must turn (that
 * depends on stored tangents: io/gltf_tangents.h). */
#ifndef TEXOPT_TEXEL_MAP_H
#define TEXOPT_TEXEL_MAP_H

/* m = d from / d to (row-major 2x2), the linear part of the affine map taking the triangle
 * `to` onto `from`, and 1; or 0, m not written, when twice the signed area of `to` is not
 * finite or about 0 (|.| <= 1e-12). area2 (may be NULL) receives that doubled area. */
int texopt_texel_map(const double from[3][2], const double to[3][2], double m[4], double *area2);

/* (cos, sin) of the rotation part of m (its polar decomposition when det m > 0). */
void texopt_texel_map_rotation(const double m[4], double *c, double *s);

/* Turns an encoded normal's XY (xy[0], xy[1] in [0, 1]) by the rotation (c, s):
 * (a, b) -> (c a - s b, s a + c b) on the decoded components; Z and any other channel stay.
 * With the rotation of m = d input / d output this is the re-bake's turn (rebake.h says
 * why); (c, -s) undoes it. */
void texopt_normal_turn(double c, double s, float *xy);

#endif
