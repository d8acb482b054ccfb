/* gltf_access.hpp - bounds-checked reading of glTF accessors and buffer views.
 *
 * tinygltf parses the JSON but trusts every offset, count and stride it finds; these helpers
 * check each one against the real buffer sizes before a byte is read, and convert the data
 * (float, normalized or plain integers of KHR_mesh_quantization) to float or uint32.
 * Does not: read sparse accessors (refused as unsupported) or decode compressed data.
 * Internal to engine/io; the format is the Khronos glTF 2.0 specification, section 3.6. */
#ifndef TEXOPT_GLTF_ACCESS_HPP
#define TEXOPT_GLTF_ACCESS_HPP

#include <cstdint>
#include <vector>

#include <tiny_gltf.h>

extern "C" {
#include "status.h"
}

/* Checks that buffer view `index` lies inside its buffer. */
texopt_status gltf_check_buffer_view(const tinygltf::Model &m, int index, char *err, size_t err_len);

/* Checks that accessor `index` (all count elements at its stride) lies inside its buffer
 * view, that its type and component type are known, and that a sparse part is in range. */
texopt_status gltf_check_accessor(const tinygltf::Model &m, int index, char *err, size_t err_len);

/* Reads accessor `index` of the given tinygltf type (TINYGLTF_TYPE_VEC2, ...) into out as
 * floats (count * components), refusing NaN and infinities. what names the use in messages
 * ("mesh 0 primitive 1 POSITION"). */
texopt_status gltf_read_floats(const tinygltf::Model &m, int index, int type, const char *what, std::vector<float> *out,
                               char *err, size_t err_len);

/* Reads a SCALAR unsigned-integer accessor (u8, u16, u32) into out. */
texopt_status gltf_read_indices(const tinygltf::Model &m, int index, const char *what, std::vector<uint32_t> *out,
                                char *err, size_t err_len);

/* The element count of accessor `index` (which must exist). */
size_t gltf_accessor_count(const tinygltf::Model &m, int index);

#endif
