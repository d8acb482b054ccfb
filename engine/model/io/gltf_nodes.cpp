/* gltf_nodes.cpp - world transforms of glTF nodes (see gltf_nodes.hpp). */
#include "gltf_nodes.hpp"

namespace
{

gltf_mat4 identity()
{
    gltf_mat4 m{};
    m[0] = m[5] = m[10] = m[15] = 1.0;
    return m;
}

gltf_mat4 multiply(const gltf_mat4 &a, const gltf_mat4 &b)
{
    gltf_mat4 r{};
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + row] * b[c * 4 + k];
            r[c * 4 + row] = s;
        }
    return r;
}

/* T * R * S, or the node's matrix. */
gltf_mat4 local_transform(const tinygltf::Node &n)
{
    if (n.matrix.size() == 16) {
        gltf_mat4 m;
        for (int i = 0; i < 16; i++)
            m[i] = n.matrix[(size_t)i];
        return m;
    }
    double t[3] = {0, 0, 0}, s[3] = {1, 1, 1}, q[4] = {0, 0, 0, 1};
    if (n.translation.size() == 3)
        for (int i = 0; i < 3; i++)
            t[i] = n.translation[(size_t)i];
    if (n.scale.size() == 3)
        for (int i = 0; i < 3; i++)
            s[i] = n.scale[(size_t)i];
    if (n.rotation.size() == 4)
        for (int i = 0; i < 4; i++)
            q[i] = n.rotation[(size_t)i];
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                   2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                   2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
    gltf_mat4 m{};
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            m[c * 4 + row] = r[c * 3 + row] * s[c];
    m[12] = t[0];
    m[13] = t[1];
    m[14] = t[2];
    m[15] = 1.0;
    return m;
}

} // namespace

texopt_status gltf_world_transforms(const tinygltf::Model &g, std::vector<gltf_mat4> *world, char *err, size_t err_len)
{
    size_t n = g.nodes.size();
    std::vector<int> parent(n, -1);
    for (size_t i = 0; i < n; i++)
        for (int c : g.nodes[i].children) {
            if (c < 0 || (size_t)c >= n)
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "node %zu: child %d does not exist", i, c);
            if (parent[(size_t)c] >= 0 || (size_t)c == i)
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "node %d has more than one parent", c);
            parent[(size_t)c] = (int)i;
        }
    world->assign(n, identity());
    std::vector<char> done(n, 0);
    for (size_t i = 0; i < n; i++) {
        /* Walk up to a computed ancestor (or a root), then down again; a walk longer than
         * the node count means a cycle. */
        std::vector<size_t> chain;
        size_t cur = i;
        while (!done[cur]) {
            chain.push_back(cur);
            if (chain.size() > n)
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "node %zu is part of a cycle", i);
            if (parent[cur] < 0)
                break;
            cur = (size_t)parent[cur];
        }
        for (size_t k = chain.size(); k-- > 0;) {
            size_t node = chain[k];
            gltf_mat4 local = local_transform(g.nodes[node]);
            (*world)[node] = parent[node] >= 0 ? multiply((*world)[(size_t)parent[node]], local) : local;
            done[node] = 1;
        }
    }
    return TEXOPT_OK;
}

double gltf_determinant3(const gltf_mat4 &m)
{
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}
