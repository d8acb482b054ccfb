// resize.cpp - texopt_image_resize through OpenImageIO's ImageBufAlgo::resize.
//
// The buffers are wrapped, not copied: src is read in place and the result is written
// straight into the new texopt_image. Values are clamped back to [0,1] because the
// filter's negative lobes overshoot at edges and image.h promises [0,1].
#include "resize.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cstring>

texopt_status texopt_image_resize(const texopt_image *src, int width, int height, texopt_image *dst, char *err,
                                  size_t err_len)
{
    if (!dst)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no output image");
    std::memset(dst, 0, sizeof *dst);
    if (!src || !src->pixels || src->width <= 0 || src->height <= 0 || src->channels < 1 || src->channels > 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "resize: empty source image");
    texopt_status st = texopt_image_create(dst, width, height, src->channels, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    try {
        OIIO::ImageSpec in_spec(src->width, src->height, src->channels, OIIO::TypeDesc::FLOAT);
        OIIO::ImageSpec out_spec(width, height, src->channels, OIIO::TypeDesc::FLOAT);
        OIIO::ImageBuf in(in_spec, src->pixels);
        OIIO::ImageBuf out(out_spec, dst->pixels);
        // One thread: the engine's callers already spread work over the cores.
        if (!OIIO::ImageBufAlgo::resize(out, in, "", 0.0f, OIIO::ROI(), 1)) {
            std::string msg = out.geterror();
            texopt_image_destroy(dst);
            return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "resize to %dx%d failed: %s", width, height,
                               msg.c_str());
        }
    } catch (const std::exception &e) {
        texopt_image_destroy(dst);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "resize to %dx%d failed: %s", width, height, e.what());
    }
    size_t n = (size_t)width * (size_t)height * (size_t)src->channels;
    for (size_t i = 0; i < n; i++)
        dst->pixels[i] = std::min(1.0f, std::max(0.0f, dst->pixels[i]));
    return TEXOPT_OK;
}
