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
texopt_status texopt_image_create(texopt_image *img, int width, int height, int channels, char *err, size_t err_len);

/* Frees the pixels and empties *img. Accepts NULL and empty images. */
void texopt_image_destroy(texopt_image *img);

static inline float *texopt_image_at(const texopt_image *img, int x, int y)
{
    return img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}

/* The channel of an image with `channels` channels that holds glTF channel c (0..3 for R, G,
 * B, A) as a sampler reads it: a grey image gives R = G = B, and alpha is absent (reads 1)
 * without a channel of its own; -1 then. */
static inline int texopt_image_channel_of(int channels, int c)
{
    if (c < 3)
        return channels >= 3 ? c : 0;
    return channels == 4 ? 3 : channels == 2 ? 1 : -1;
}

#endif
