/* gltf_files.hpp - the only files a glTF may make texopt read. Internal to engine/io.
 *
 * tinygltf resolves buffer and image URIs through file-system callbacks; these confine it to
 * the model's own directory: relative, percent-decoded names only, no "..", no absolute
 * paths, no URI schemes (http:, https:, file: ... are refused, never fetched), no symbolic
 * link leading outside, each file under a size limit. The first refusal is kept in the
 * context, because tinygltf only warns about images it could not read. Does not: parse
 * anything. Format: Khronos glTF 2.0, section 3.2 (URIs); serves Sun et al. 2022's input. */
#ifndef TEXOPT_GLTF_FILES_HPP
#define TEXOPT_GLTF_FILES_HPP

#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

extern "C" {
#include "status.h"
}

/* What tinygltf's callbacks found wrong; tinygltf treats a missing image as a warning, so
 * the first refusal is kept here and wins over whatever tinygltf reports. */
struct gltf_load_context {
    std::string base_dir; /* absolute, no trailing slash; empty: no external files at all */
    uint64_t max_file_bytes = 0;
    tinygltf::Model *model = nullptr;
    texopt_status status = TEXOPT_OK;
    std::string message;

    void refuse(texopt_status st, const std::string &msg)
    {
        if (status == TEXOPT_OK) {
            status = st;
            message = msg;
        }
    }
};

/* File-system callbacks that read only inside ctx->base_dir (empty: refuse every file). */
tinygltf::FsCallbacks gltf_confined_fs(gltf_load_context *ctx);

/* Reads a whole regular file of at most max_bytes; on failure a status and *why. */
texopt_status gltf_read_file_limited(const std::string &path, uint64_t max_bytes, std::vector<unsigned char> *out,
                                     std::string *why);

/* The absolute, symlink-free form of dir without a trailing slash; empty when it does not
 * exist or is the root (a model at the root may not read the whole disk). */
std::string gltf_absolute_directory(const char *dir);

#endif
