/* image_io.cpp - OpenImageIO behind the C API of image_io.h.
 *
 * Does: decode from memory through an IOMemReader (so the glTF loader never writes temporary
 * files), check the header's size before decoding, encode 8-bit PNG through an IOVecOutput.
 * Does not: convert colour spaces or premultiply (see the colour-space note in image_io.h).
 * Supports the texture handling of Sun et al. 2022; implements no part of the method. */
#include "image_io.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "atomic_file.h"

namespace
{

const char *display_name(const char *name)
{
    return name && *name ? name : "image";
}

/* OpenImageIO picks the reader from the file name's extension when reading from a proxy;
 * the magic number is more trustworthy than whatever name the glTF gave the image. */
std::string pseudo_filename(const unsigned char *b, size_t len, const char *name)
{
    if (len >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0)
        return "image.png";
    if (len >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF)
        return "image.jpg";
    if (len >= 12 && memcmp(b, "RIFF", 4) == 0 && memcmp(b + 8, "WEBP", 4) == 0)
        return "image.webp";
    std::string n = name ? name : "";
    size_t dot = n.find_last_of('.');
    if (dot != std::string::npos && n.find('/', dot) == std::string::npos)
        return "image" + n.substr(dot);
    return "image.png";
}

/* Image size read straight from a PNG IHDR or JPEG SOF header. OpenImageIO's open() of a
 * progressive JPEG already decodes every scan (libjpeg's start_decompress), so the pixel cap
 * must be checked before OpenImageIO sees the bytes, and probing a JPEG is cheaper here. */
struct header_size {
    int width = 0, height = 0;
    int components = 0;        /* JPEG only: colour components in the frame */
    int precision = 0;         /* bits per sample */
    int chroma_subsampled = 0; /* JPEG only: a colour component sampled below the first's */
};

uint32_t be16(const unsigned char *p)
{
    return (uint32_t)p[0] << 8 | p[1];
}

uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

bool png_header_size(const unsigned char *b, size_t len, header_size *hs)
{
    if (len < 33 || memcmp(b, "\x89PNG\r\n\x1a\n", 8) != 0 || memcmp(b + 12, "IHDR", 4) != 0)
        return false;
    uint32_t w = be32(b + 16), h = be32(b + 20);
    if (w == 0 || h == 0 || w > INT32_MAX || h > INT32_MAX)
        return false;
    hs->width = (int)w;
    hs->height = (int)h;
    hs->precision = b[24];
    return true;
}

/* Walks the JPEG marker segments up to the first start-of-frame. */
bool jpeg_header_size(const unsigned char *b, size_t len, header_size *hs)
{
    if (len < 4 || b[0] != 0xFF || b[1] != 0xD8)
        return false;
    size_t at = 2;
    while (at + 4 <= len) {
        if (b[at] != 0xFF)
            return false;
        unsigned char marker = b[at + 1];
        if (marker == 0xFF) { /* fill byte */
            at++;
            continue;
        }
        if (marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {
            at += 2;
            continue;
        }
        uint32_t seg = be16(b + at + 2);
        if (seg < 2 || at + 2 + seg > len)
            return false;
        bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
        if (sof) {
            if (seg < 8)
                return false;
            hs->precision = b[at + 4];
            hs->height = (int)be16(b + at + 5);
            hs->width = (int)be16(b + at + 7);
            hs->components = b[at + 9];
            for (int c = 1; c < hs->components && 8u + 3u * (unsigned)c + 3u <= seg; c++)
                hs->chroma_subsampled |= b[at + 11 + 3 * c] != b[at + 11];
            return hs->width > 0 && hs->height > 0;
        }
        if (marker == 0xDA || marker == 0xD9)
            return false; /* scan data before any frame header */
        at += 2 + seg;
    }
    return false;
}

texopt_status check_header_cap(const unsigned char *b, size_t len, uint64_t max_pixels, const char *name, char *err,
                               size_t err_len)
{
    header_size hs;
    if (max_pixels == 0 || !(png_header_size(b, len, &hs) || jpeg_header_size(b, len, &hs)))
        return TEXOPT_OK; /* OpenImageIO's own header is checked after open() */
    if ((uint64_t)hs.width * (uint64_t)hs.height > max_pixels)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "%s: %dx%d image exceeds the limit of %llu pixels",
                           name && *name ? name : "image", hs.width, hs.height, (unsigned long long)max_pixels);
    return TEXOPT_OK;
}

/* Straight alpha: OpenImageIO would premultiply PNG/TGA alpha otherwise. */
OIIO::ImageSpec read_config()
{
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    return config;
}

struct opened_image {
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    std::unique_ptr<OIIO::ImageInput> input;
};

texopt_status open_memory(opened_image *oi, const void *bytes, size_t len, const char *name, char *err, size_t err_len)
{
    if (!bytes || len == 0)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: no image data", display_name(name));
    const unsigned char *b = static_cast<const unsigned char *>(bytes);
    oi->proxy.reset(new OIIO::Filesystem::IOMemReader(bytes, len));
    OIIO::ImageSpec config = read_config();
    /* OpenImageIO 2.4 only honours the proxy when the config names it too. */
    void *proxy = oi->proxy.get();
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    oi->input = OIIO::ImageInput::open(pseudo_filename(b, len, name), &config, oi->proxy.get());
    if (!oi->input) {
        std::string why = OIIO::geterror();
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: cannot decode image: %s", display_name(name),
                           why.empty() ? "unknown format" : why.c_str());
    }
    const OIIO::ImageSpec &spec = oi->input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: image header claims %dx%dx%d with %d channels",
                           display_name(name), spec.width, spec.height, spec.depth, spec.nchannels);
    return TEXOPT_OK;
}

void fill_info(texopt_image_info *info, const OIIO::ImageInput &in)
{
    const OIIO::ImageSpec &spec = in.spec();
    memset(info, 0, sizeof *info);
    info->width = spec.width;
    info->height = spec.height;
    info->channels = spec.nchannels < 4 ? spec.nchannels : 4;
    info->bits_per_channel = (int)spec.format.size() * 8;
    int bits = spec.get_int_attribute("oiio:BitsPerSample", 0);
    if (bits > 0)
        info->bits_per_channel = bits;
    snprintf(info->format, sizeof info->format, "%s", in.format_name());
}

} // namespace

extern "C" texopt_status texopt_image_probe_memory(texopt_image_info *info, const void *bytes, size_t len,
                                                   const char *name, char *err, size_t err_len)
{
    if (!info)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no image info to fill");
    memset(info, 0, sizeof *info);
    header_size hs;
    if (bytes && jpeg_header_size(static_cast<const unsigned char *>(bytes), len, &hs) &&
        (hs.components == 1 || hs.components == 3) && hs.precision == 8) {
        info->width = hs.width;
        info->height = hs.height;
        info->channels = hs.components;
        info->bits_per_channel = 8;
        info->chroma_subsampled = hs.chroma_subsampled;
        snprintf(info->format, sizeof info->format, "jpeg");
        return TEXOPT_OK;
    }
    opened_image oi;
    texopt_status st = open_memory(&oi, bytes, len, name, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    fill_info(info, *oi.input);
    return TEXOPT_OK;
}

extern "C" texopt_status texopt_image_decode_memory(texopt_image *out, const void *bytes, size_t len,
                                                    uint64_t max_pixels, const char *name, char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no image to fill");
    memset(out, 0, sizeof *out);
    if (bytes) {
        texopt_status cap =
            check_header_cap(static_cast<const unsigned char *>(bytes), len, max_pixels, name, err, err_len);
        if (cap != TEXOPT_OK)
            return cap;
    }
    opened_image oi;
    texopt_status st = open_memory(&oi, bytes, len, name, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const OIIO::ImageSpec &spec = oi.input->spec();
    uint64_t pixels = (uint64_t)spec.width * (uint64_t)spec.height;
    if (max_pixels > 0 && pixels > max_pixels)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "%s: %dx%d image exceeds the limit of %llu pixels",
                           display_name(name), spec.width, spec.height, (unsigned long long)max_pixels);
    int channels = spec.nchannels < 4 ? spec.nchannels : 4;
    st = texopt_image_create(out, spec.width, spec.height, channels, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    if (!oi.input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, out->pixels)) {
        std::string why = oi.input->geterror();
        texopt_image_destroy(out);
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: corrupt image data: %s", display_name(name),
                           why.c_str());
    }
    /* Floating-point formats may hold anything; the engine's contract is [0,1]. */
    size_t n = (size_t)out->width * (size_t)out->height * (size_t)channels;
    for (size_t i = 0; i < n; i++) {
        float v = out->pixels[i];
        out->pixels[i] = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN -> 0 */
    }
    return TEXOPT_OK;
}

extern "C" texopt_status texopt_image_read(texopt_image *out, const char *path, char *err, size_t err_len)
{
    if (!out || !path)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no image or no path");
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    if (!f)
        return texopt_fail(err, err_len, TEXOPT_E_IO, "cannot open %s: %s", path, strerror(errno));
    std::vector<unsigned char> bytes;
    unsigned char chunk[65536];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0)
        bytes.insert(bytes.end(), chunk, chunk + n);
    bool failed = ferror(f) != 0;
    fclose(f);
    if (failed)
        return texopt_fail(err, err_len, TEXOPT_E_IO, "cannot read %s", path);
    return texopt_image_decode_memory(out, bytes.data(), bytes.size(), 0, path, err, err_len);
}

extern "C" texopt_status texopt_image_encode_png(const texopt_image *img, unsigned char **bytes, size_t *len, char *err,
                                                 size_t err_len)
{
    return texopt_image_encode_png_bits(img, 8, bytes, len, err, err_len);
}

namespace
{

/* Encodes img with spec by OpenImageIO's writer for `file` ("image.png": its extension picks
 * the format) into a malloc'ed buffer; `format` names it in messages. */
texopt_status encode_image(const texopt_image *img, const char *file, const OIIO::ImageSpec &spec, const char *format,
                           unsigned char **bytes, size_t *len, char *err, size_t err_len)
{
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput proxy(encoded);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(file, &proxy);
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "OpenImageIO has no %s writer: %s", format,
                           OIIO::geterror().c_str());
    if (!out->open(file, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, img->pixels) || !out->close())
        return texopt_fail(err, err_len, TEXOPT_E_INTERNAL, "%s encoding failed: %s", format, out->geterror().c_str());
    unsigned char *copy = static_cast<unsigned char *>(malloc(encoded.size() ? encoded.size() : 1));
    if (!copy)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a %zu-byte %s", encoded.size(), format);
    memcpy(copy, encoded.data(), encoded.size());
    *bytes = copy;
    *len = encoded.size();
    return TEXOPT_OK;
}

} // namespace

extern "C" texopt_status texopt_image_encode_png_bits(const texopt_image *img, int bits, unsigned char **bytes,
                                                      size_t *len, char *err, size_t err_len)
{
    if (!bytes || !len)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no output buffer for PNG");
    if (bits != 8 && bits != 16)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "PNG depth %d is not 8 or 16", bits);
    *bytes = nullptr;
    *len = 0;
    if (!img || !img->pixels || img->width <= 0 || img->height <= 0 || img->channels < 1 || img->channels > 4)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "cannot encode an empty or invalid image");
    OIIO::ImageSpec spec(img->width, img->height, img->channels,
                         bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    return encode_image(img, "image.png", spec, "PNG", bytes, len, err, err_len);
}

extern "C" texopt_status texopt_image_encode_jpeg(const texopt_image *img, int quality, int subsample_chroma,
                                                  unsigned char **bytes, size_t *len, char *err, size_t err_len)
{
    if (!bytes || !len)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no output buffer for JPEG");
    *bytes = nullptr;
    *len = 0;
    if (!img || !img->pixels || img->width <= 0 || img->height <= 0 || (img->channels != 1 && img->channels != 3) ||
        quality < 1 || quality > 100)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "cannot encode a JPEG of %d channels at quality %d",
                           img ? img->channels : 0, quality);
    OIIO::ImageSpec spec(img->width, img->height, img->channels, OIIO::TypeDesc::UINT8);
    spec.attribute("Compression", "jpeg:" + std::to_string(quality));
    spec.attribute("jpeg:subsampling", subsample_chroma ? "4:2:0" : "4:4:4");
    return encode_image(img, "image.jpg", spec, "JPEG", bytes, len, err, err_len);
}

extern "C" texopt_status texopt_image_write_png(const texopt_image *img, const char *path, char *err, size_t err_len)
{
    unsigned char *bytes = nullptr;
    size_t len = 0;
    texopt_status st = texopt_image_encode_png(img, &bytes, &len, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    st = texopt_write_file_atomic(path, bytes, len, err, err_len);
    free(bytes);
    return st;
}
