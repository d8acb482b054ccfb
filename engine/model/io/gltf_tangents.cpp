/* gltf_tangents.cpp - TANGENT lookup in the kept glTF document (see gltf_tangents.h). */
#include "gltf_tangents.h"

#include "gltf_document.hpp"

extern "C" int texopt_primitive_has_tangents(const texopt_model *model, int primitive)
{
    if (!model || !model->document || primitive < 0 || primitive >= model->primitive_count)
        return 0;
    const tinygltf::Model &g = model->document->gltf;
    const texopt_primitive &p = model->primitives[primitive];
    if (p.gltf_mesh < 0 || static_cast<size_t>(p.gltf_mesh) >= g.meshes.size())
        return 0;
    const tinygltf::Mesh &mesh = g.meshes[static_cast<size_t>(p.gltf_mesh)];
    if (p.gltf_primitive < 0 || static_cast<size_t>(p.gltf_primitive) >= mesh.primitives.size())
        return 0;
    const auto &attributes = mesh.primitives[static_cast<size_t>(p.gltf_primitive)].attributes;
    return attributes.find("TANGENT") != attributes.end() ? 1 : 0;
}
