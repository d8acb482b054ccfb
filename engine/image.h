/* image.h - a decoded texture in memory.
 *
 * Pixels are floats in [0,1], rows top to bottom (row 0 is v = 0 in glTF), channels
 * interleaved. Values stay as encoded in the file (sRGB-encoded for colour textures,
 * linear for data textures such as normal or metallic-roughness maps): texopt never
 * linearises. Perceptual losses are meant to see displayed values, and keeping one
 * encoding end to end means a round trip changes nothing. Alpha is unassociated. */
#ifndef TEXOPT_IMAGE_H
#define TEXOPT_IMAGE_H

#include "status.h"

typedef struct texopt_image {
    int width, height;
    int channels;  /* 1..4 */
    float *pixels; /* width * height * channels */
} texopt_image;

/* Allocates a zero-filled image into *img. On failure *img is left empty. */
texopt_status texopt_image_create(texopt_image *img, int width, int height, int channels,
                                  char *err, size_t err_len);

/* Frees the pixels and empties *img. Accepts NULL and empty images. */
void texopt_image_destroy(texopt_image *img);

static inline float *texopt_image_at(const texopt_image *img, int x, int y)
{
    return img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}

#endif
