/* image.c - allocation of texopt_image. Decoding and encoding live in io/image_io. */
#include "image.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

texopt_status texopt_image_create(texopt_image *img, int width, int height, int channels, char *err, size_t err_len)
{
    memset(img, 0, sizeof *img);
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "image size %dx%d with %d channels is not valid",
                           width, height, channels);
    size_t count = (size_t)width * (size_t)height;
    if (count > SIZE_MAX / sizeof(float) / (size_t)channels)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "image %dx%d is too large", width, height);
    img->pixels = calloc(count * (size_t)channels, sizeof(float));
    if (!img->pixels)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %dx%d image", width, height);
    img->width = width;
    img->height = height;
    img->channels = channels;
    return TEXOPT_OK;
}

void texopt_image_destroy(texopt_image *img)
{
    if (!img)
        return;
    free(img->pixels);
    memset(img, 0, sizeof *img);
}
