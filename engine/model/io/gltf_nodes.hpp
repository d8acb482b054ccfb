/* gltf_nodes.hpp - world transforms of glTF nodes. Internal to engine/io.
 *
 * Composes each node's matrix or T * R * S with its ancestors' (glTF 2.0, section 3.5),
 * refusing children out of range, nodes with two parents and cycles. Does not: evaluate
 * animations or skins. Feeds the world-space positions Sun et al. 2022 renders. */
#ifndef TEXOPT_GLTF_NODES_HPP
#define TEXOPT_GLTF_NODES_HPP

#include <array>
#include <vector>

#include <tiny_gltf.h>

extern "C" {
#include "status.h"
}

typedef std::array<double, 16> gltf_mat4; /* column-major, as glTF */

/* World matrices of all nodes of g, in node order. */
texopt_status gltf_world_transforms(const tinygltf::Model &g, std::vector<gltf_mat4> *world, char *err, size_t err_len);

/* Determinant of the upper-left 3x3 block: negative for a mirroring transform. */
double gltf_determinant3(const gltf_mat4 &m);

#endif
