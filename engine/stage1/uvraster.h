/* uvraster.h - the one-ring of a triangle rasterised once into a buffer of input texel
 * positions, the "render once, transform per candidate" buffer of the triangle-wise stage.
 *
 * Sun et al. 2022 render the deformed one-ring for every candidate Jacobian J. Because J is
 * one linear map on the whole one-ring and the camera does not move, the screen position of
 * a surface point never changes: only the texel it reads does, p(q) = J p_hat(q). So we store
 * per pixel q the input texel position p_hat(q) and the face covering q, and every candidate
 * is arithmetic on this buffer (see triloss.h).
 *
 * The rasteriser is plain C (pixel centres, barycentric coverage, depth test with the point
 * closest to the camera winning, ties to the earlier face of the one-ring with the triangle
 * itself first; then the triangle drawn again over its ring when ring faces in front hide
 * more than TEXOPT_UVRASTER_HIDDEN_SHARE of its pixels). Each face interpolates its own UV
 * vertices, so a UV seam inside the one-ring shows each side's own texels. BENCHMARKS.md@9f788a8,
 * "Stage 1", compares it with an OSMesa float-target render of the same buffer. */
#ifndef TEXOPT_UVRASTER_H
#define TEXOPT_UVRASTER_H

#include <stddef.h>
#include <stdint.h>

#include "camera.h"
#include "mesh.h"
#include "status.h"

/* Where texopt_camera_limit_zoom narrows the window, the one-ring fills it edge to edge and
 * every evaluation would bake and compare all size^2 pixels, 2-4x what the paper's window
 * shows of the same ring. A narrowed raster therefore keeps only the max_covered covered
 * pixels nearest the triangle (screen distance to its projection; the triangle's own pixels
 * always kept); the others are uncovered exactly like
 * pixels outside the ring, so the bake, the GMSD mask and the loss follow. Rings the paper's
 * window shows at or under the limit are rasterised as before, whole. BENCHMARKS.md@9f788a8,
 * "Stage 1", for the value. */
#define TEXOPT_UVRASTER_MAX_COVERED 1400

/* The share of a triangle's pixels that ring faces in front of it may hide before it is drawn
 * over them (a bulge seen from behind its face; BENCHMARKS.md@9f788a8 "The triangle its ring hides"). */
#define TEXOPT_UVRASTER_HIDDEN_SHARE 0.2

typedef struct texopt_uvraster {
    int size;           /* viewport side */
    double max_zoom;    /* input texels a pixel may show (camera.h texopt_camera_limit_zoom);
                           TEXOPT_CAMERA_MAX_ZOOM from create, 0 keeps the paper's window */
    size_t max_covered; /* pixels a narrowed window keeps, those nearest the triangle;
                           TEXOPT_UVRASTER_MAX_COVERED from create, 0 keeps every pixel */
    int paper_window;   /* non-zero: the camera frames the triangle's own corners (Sun et al.
                           appendix A), not its one-ring, and the triangle is never redrawn
                           over ring faces that hide it; set max_zoom and max_covered to 0 */
    texopt_camera camera;
    size_t covered; /* pixels covered by the one-ring */
    double *texel;  /* 2 per pixel, row-major from the top: p_hat(q); 0 where uncovered */
    int32_t *face;  /* per pixel: covering mesh triangle, -1 where uncovered */
    /* scratch, reused across triangles */
    double *depth;
    double *nearest; /* squared distances of the covered pixels, for the selection */
    uint32_t *ring;
    size_t ring_cap;
    double *ring_points;
} texopt_uvraster;

/* Allocates a raster of size x size pixels (2 <= size <= 4096). Free with
 * texopt_uvraster_destroy. */
texopt_status texopt_uvraster_create(texopt_uvraster **out, int size, char *err, size_t err_len);

void texopt_uvraster_destroy(texopt_uvraster *raster);

/* Builds the camera of `triangle` and rasterises its one-ring (texopt_mesh_one_ring) into
 * the buffer, trimmed to max_covered pixels where the camera's zoom was limited. Fails with
 * TEXOPT_E_INVALID_ARGUMENT for a triangle index out of range or a degenerate triangle;
 * allocates only when a one-ring is larger than any seen before. */
texopt_status texopt_uvraster_render(texopt_uvraster *raster, const texopt_mesh *mesh, uint32_t triangle, char *err,
                                     size_t err_len);

/* The same one-ring through a given window of the triangle's camera instead of the
 * zoom-limited one: window = {x0, y0, side} in the camera's (R, U) frame relative to the
 * centroid (texopt_camera.window_x0, window_y0, window_side). A close-up of part of a large
 * triangle (triloss.h): covered pixels beyond max_covered are uncovered from the viewport's
 * rim inwards. Fails as texopt_uvraster_render, and for a side that is not positive. */
texopt_status texopt_uvraster_render_window(texopt_uvraster *raster, const texopt_mesh *mesh, uint32_t triangle,
                                            const double window[3], char *err, size_t err_len);

#endif
