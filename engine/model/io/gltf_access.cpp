/* gltf_access.cpp - bounds-checked accessor reads (see gltf_access.hpp). Every offset sum is
 * checked against the buffer size without overflowing, so a hostile file can name any
 * numbers it likes. */
#include "gltf_access.hpp"

#include <cmath>
#include <cstring>

namespace
{

size_t component_bytes(int component_type)
{
    switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

size_t type_components(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

const char *type_name(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    default: return "matrix";
    }
}

/* a + b <= limit, without overflow. */
bool fits(uint64_t a, uint64_t b, uint64_t limit)
{
    return a <= limit && b <= limit - a;
}

/* The bytes of a view: where they start and how many, after gltf_check_buffer_view. */
const unsigned char *view_bytes(const tinygltf::Model &m, const tinygltf::BufferView &bv)
{
    return m.buffers[(size_t)bv.buffer].data.data() + bv.byteOffset;
}

/* Checks count elements of elem_size bytes at offset with stride fit in view_len bytes. */
bool elements_fit(uint64_t offset, uint64_t count, uint64_t stride, uint64_t elem_size, uint64_t view_len)
{
    if (count == 0)
        return offset <= view_len;
    if (!fits(offset, elem_size, view_len))
        return false;
    uint64_t room = view_len - offset - elem_size; /* bytes left after the first element */
    return (count - 1) <= room / stride;
}

double component_value(const unsigned char *p, int component_type, bool normalized)
{
    switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        memcpy(&f, p, 4);
        return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        double v = (int8_t)p[0];
        return normalized ? std::fmax(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        return normalized ? std::fmax(v / 32767.0, -1.0) : v;
    }
    default: { /* UNSIGNED_INT, only allowed for indices */
        uint32_t v;
        memcpy(&v, p, 4);
        return v;
    }
    }
}

} // namespace

size_t gltf_accessor_count(const tinygltf::Model &m, int index)
{
    return m.accessors[(size_t)index].count;
}

texopt_status gltf_check_buffer_view(const tinygltf::Model &m, int index, char *err, size_t err_len)
{
    if (index < 0 || (size_t)index >= m.bufferViews.size())
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "buffer view %d does not exist (%zu views)", index,
                           m.bufferViews.size());
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)index];
    if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "buffer view %d: buffer %d does not exist", index,
                           bv.buffer);
    size_t size = m.buffers[(size_t)bv.buffer].data.size();
    if (!fits(bv.byteOffset, bv.byteLength, size))
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                           "buffer view %d: bytes %zu..%zu lie past the end of buffer %d (%zu bytes)", index,
                           bv.byteOffset, bv.byteOffset + bv.byteLength, bv.buffer, size);
    if (bv.byteStride != 0 && (bv.byteStride < 4 || bv.byteStride > 252 || bv.byteStride % 4 != 0))
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "buffer view %d: byteStride %zu is not valid", index,
                           bv.byteStride);
    return TEXOPT_OK;
}

texopt_status gltf_check_accessor(const tinygltf::Model &m, int index, char *err, size_t err_len)
{
    if (index < 0 || (size_t)index >= m.accessors.size())
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "accessor %d does not exist (%zu accessors)", index,
                           m.accessors.size());
    const tinygltf::Accessor &a = m.accessors[(size_t)index];
    size_t comp = component_bytes(a.componentType);
    size_t ncomp = type_components(a.type);
    if (comp == 0 || ncomp == 0)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "accessor %d: unknown type %d or component type %d", index,
                           a.type, a.componentType);
    if (a.bufferView >= 0) {
        texopt_status st = gltf_check_buffer_view(m, a.bufferView, err, err_len);
        if (st != TEXOPT_OK)
            return st;
        const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
        uint64_t elem = (uint64_t)comp * ncomp;
        uint64_t stride = bv.byteStride ? bv.byteStride : elem;
        if (stride < elem)
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "accessor %d: byteStride %llu of buffer view %d is smaller than an element (%llu bytes)",
                               index, (unsigned long long)stride, a.bufferView, (unsigned long long)elem);
        if (!elements_fit(a.byteOffset, a.count, stride, elem, bv.byteLength))
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "accessor %d: %zu elements at offset %zu run past the end of buffer view %d (%zu bytes)",
                               index, a.count, a.byteOffset, a.bufferView, bv.byteLength);
    }
    if (a.sparse.isSparse) {
        const auto &sp = a.sparse;
        if (sp.count < 0 || (size_t)sp.count > a.count)
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "accessor %d: sparse count %d is not valid", index,
                               sp.count);
        size_t icomp = component_bytes(sp.indices.componentType);
        if (icomp == 0 || sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "accessor %d: sparse indices have a bad component type", index);
        for (int part = 0; part < 2; part++) {
            int view = part == 0 ? sp.indices.bufferView : sp.values.bufferView;
            uint64_t off = (uint64_t)(part == 0 ? sp.indices.byteOffset : sp.values.byteOffset);
            uint64_t elem = part == 0 ? icomp : (uint64_t)comp * ncomp;
            texopt_status st = gltf_check_buffer_view(m, view, err, err_len);
            if (st != TEXOPT_OK)
                return st;
            if (!elements_fit(off, (uint64_t)sp.count, elem, elem, m.bufferViews[(size_t)view].byteLength))
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "accessor %d: sparse %s run past buffer view %d",
                                   index, part == 0 ? "indices" : "values", view);
        }
    }
    return TEXOPT_OK;
}

/* Checks what gltf_read_* need beyond gltf_check_accessor: the type, data present, no sparse. */
static texopt_status check_readable(const tinygltf::Model &m, int index, int type, const char *what, char *err,
                                    size_t err_len)
{
    texopt_status st = gltf_check_accessor(m, index, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const tinygltf::Accessor &a = m.accessors[(size_t)index];
    if (a.type != type)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: accessor %d is %s, expected %s", what, index,
                           type_name(a.type), type_name(type));
    if (a.sparse.isSparse)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "%s: accessor %d is sparse, which texopt does not read",
                           what, index);
    if (a.bufferView < 0 && a.count > 0)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: accessor %d has no buffer view", what, index);
    return TEXOPT_OK;
}

texopt_status gltf_read_floats(const tinygltf::Model &m, int index, int type, const char *what, std::vector<float> *out,
                               char *err, size_t err_len)
{
    texopt_status st = check_readable(m, index, type, what, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const tinygltf::Accessor &a = m.accessors[(size_t)index];
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "%s: accessor %d has unsigned int components", what,
                           index);
    size_t ncomp = type_components(type), comp = component_bytes(a.componentType);
    out->assign(a.count * ncomp, 0.0f);
    if (a.count == 0)
        return TEXOPT_OK;
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
    size_t stride = bv.byteStride ? bv.byteStride : comp * ncomp;
    const unsigned char *base = view_bytes(m, bv) + a.byteOffset;
    for (size_t i = 0; i < a.count; i++) {
        for (size_t k = 0; k < ncomp; k++) {
            double v = component_value(base + i * stride + k * comp, a.componentType, a.normalized);
            if (!std::isfinite(v))
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                                   "%s: accessor %d element %zu is not a finite number", what, index, i);
            (*out)[i * ncomp + k] = (float)v;
        }
    }
    return TEXOPT_OK;
}

texopt_status gltf_read_indices(const tinygltf::Model &m, int index, const char *what, std::vector<uint32_t> *out,
                                char *err, size_t err_len)
{
    texopt_status st = check_readable(m, index, TINYGLTF_TYPE_SCALAR, what, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const tinygltf::Accessor &a = m.accessors[(size_t)index];
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                           "%s: index accessor %d has component type %d, not u8/u16/u32", what, index, a.componentType);
    size_t comp = component_bytes(a.componentType);
    out->assign(a.count, 0);
    if (a.count == 0)
        return TEXOPT_OK;
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
    size_t stride = bv.byteStride ? bv.byteStride : comp;
    const unsigned char *base = view_bytes(m, bv) + a.byteOffset;
    for (size_t i = 0; i < a.count; i++)
        (*out)[i] = (uint32_t)component_value(base + i * stride, a.componentType, false);
    return TEXOPT_OK;
}
