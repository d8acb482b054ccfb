/* image_io.h - decoding and encoding texopt_image with OpenImageIO.
 *
 * Does: read PNG, JPEG and whatever else OpenImageIO reads (from a file or from memory, with
 * the size checked from the header before decoding); write PNG to a file or to memory.
 * Does not: resample, convert colour spaces or touch alpha.
 *
 * Colour space, decided once for all of texopt: pixel values stay exactly as encoded in the
 * file. Colour textures are therefore sRGB-encoded values, data textures (normal,
 * metallic-roughness, occlusion) linear values; nothing is ever linearised or gamma-encoded
 * (engine/core/image.h says the same), so a decode/encode round trip changes nothing but
 * quantisation. Alpha is unassociated (straight) on read and write: OpenImageIO premultiplies
 * PNG alpha unless told not to, which would change the colour of every half-transparent
 * texel. Values are floats in [0,1]; 8-bit input maps v -> v / 255, 16-bit v -> v / 65535.
 * Used by the texture pipeline of Sun et al. 2022, "Efficient Texture Parameterization Driven
 * by Perceptual-Loss-on-Screen"; this file implements no part of the paper's method. */
#ifndef TEXOPT_IMAGE_IO_H
#define TEXOPT_IMAGE_IO_H

#include <stddef.h>
#include <stdint.h>

/* The engine's C headers carry no linkage guards; wrap them for the C++ shims. */
#ifdef __cplusplus
extern "C" {
#endif

#include "image.h"
#include "status.h"

/* What an image header says, read without decoding the pixels. */
typedef struct texopt_image_info {
    int width, height, channels;
    int bits_per_channel;  /* 8 or 16 for PNG, 8 for JPEG; the file's own depth */
    char format[16];       /* OpenImageIO's format name: "png", "jpeg", ... */
    int chroma_subsampled; /* JPEG: its colour planes are stored below the luma's resolution */
} texopt_image_info;

/* Reads the header of an encoded image held in memory. name is used in messages only (may
 * be NULL). TEXOPT_E_MALFORMED when the bytes are not an image OpenImageIO can read. */
texopt_status texopt_image_probe_memory(texopt_image_info *info, const void *bytes, size_t len, const char *name,
                                        char *err, size_t err_len);

/* Decodes an encoded image held in memory into *out (which the caller then owns and frees
 * with texopt_image_destroy). max_pixels caps width*height (0 = no cap): a larger header is
 * refused with TEXOPT_E_LIMIT before any pixel is decoded. On failure *out is empty. */
texopt_status texopt_image_decode_memory(texopt_image *out, const void *bytes, size_t len, uint64_t max_pixels,
                                         const char *name, char *err, size_t err_len);

/* Reads the image file at path into *out, as texopt_image_decode_memory (no pixel cap). */
texopt_status texopt_image_read(texopt_image *out, const char *path, char *err, size_t err_len);

/* Encodes img as an 8-bit PNG (values clamped to [0,1] and rounded) with img->channels
 * channels, into a malloc'ed buffer (*bytes, *len) that the caller frees with free(). */
texopt_status texopt_image_encode_png(const texopt_image *img, unsigned char **bytes, size_t *len, char *err,
                                      size_t err_len);

/* The same with `bits` (8 or 16) bits per channel: a 16-bit input (a normal map exported
 * at 16 bits) keeps its depth when it is re-baked. */
texopt_status texopt_image_encode_png_bits(const texopt_image *img, int bits, unsigned char **bytes, size_t *len,
                                           char *err, size_t err_len);

/* Encodes img (1 or 3 channels) as a baseline JPEG of `quality` (1-100) into a malloc'ed
 * buffer (*bytes, *len) that the caller frees with free(): a JPEG input's re-baked texture
 * stays a JPEG, at a tenth of a PNG's bytes. subsample_chroma: the colour planes at half
 * the resolution each way (4:2:0), else at full resolution (4:4:4), as the input had them:
 * a metallic-roughness map keeps its G and B detail only at full resolution. */
texopt_status texopt_image_encode_jpeg(const texopt_image *img, int quality, int subsample_chroma,
                                       unsigned char **bytes, size_t *len, char *err, size_t err_len);

/* Writes img as an 8-bit PNG at path (temporary file, fsync, rename). */
texopt_status texopt_image_write_png(const texopt_image *img, const char *path, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
