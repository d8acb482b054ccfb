/* gltf_files.cpp - confined file access for tinygltf (see gltf_files.hpp). */
#include "gltf_files.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <sys/stat.h>

namespace
{

int hex_value(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

/* URIs are percent-encoded (glTF 2.0 section 3.2); "my%20tex.png" names "my tex.png". */
bool percent_decode(const std::string &in, std::string *out)
{
    out->clear();
    for (size_t i = 0; i < in.size(); i++) {
        if (in[i] == '%') {
            if (i + 2 >= in.size())
                return false;
            int hi = hex_value(in[i + 1]), lo = hex_value(in[i + 2]);
            if (hi < 0 || lo < 0)
                return false;
            char c = (char)(hi * 16 + lo);
            if (c == '\0')
                return false;
            out->push_back(c);
            i += 2;
        } else {
            out->push_back(in[i]);
        }
    }
    return true;
}

bool has_scheme(const std::string &uri)
{
    size_t colon = uri.find(':');
    if (colon == std::string::npos || colon == 0)
        return false;
    for (size_t i = 0; i < colon; i++) {
        char c = uri[i];
        bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                  (i > 0 && ((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.'));
        if (!ok)
            return false;
    }
    return true;
}

bool has_parent_component(const std::string &rel)
{
    size_t start = 0;
    while (start <= rel.size()) {
        size_t end = rel.find('/', start);
        if (end == std::string::npos)
            end = rel.size();
        if (rel.compare(start, end - start, "..") == 0)
            return true;
        start = end + 1;
    }
    return false;
}

/* Maps the path tinygltf built (search directory + "/" + URI) to a real file inside the
 * model's directory, or records why it may not be read. tinygltf also tries "./URI" after
 * the base directory; that second candidate is silently not found. */
bool resolve_inside(gltf_load_context *ctx, const std::string &joined, std::string *real_out)
{
    std::string prefix = ctx->base_dir + "/";
    if (ctx->base_dir.empty() || joined.compare(0, prefix.size(), prefix) != 0) {
        if (ctx->base_dir.empty()) {
            std::string uri = joined.compare(0, 2, "./") == 0 ? joined.substr(2) : joined;
            ctx->refuse(TEXOPT_E_MALFORMED,
                        "external URI \"" + uri + "\" cannot be resolved: the model was given without a directory");
        }
        return false;
    }
    std::string uri = joined.substr(prefix.size());
    std::string rel;
    if (uri.compare(0, 5, "http:") == 0 || uri.compare(0, 6, "https:") == 0 || uri.compare(0, 4, "ftp:") == 0 ||
        uri.compare(0, 2, "//") == 0) {
        ctx->refuse(TEXOPT_E_MALFORMED, "URI \"" + uri + "\" points to the network; texopt never fetches it");
        return false;
    }
    if (has_scheme(uri)) {
        ctx->refuse(TEXOPT_E_MALFORMED, "URI \"" + uri + "\" has a scheme; only relative file names are read");
        return false;
    }
    if (uri.empty() || uri[0] == '/' || !percent_decode(uri, &rel) || rel.empty() || rel[0] == '/' ||
        rel.find('\\') != std::string::npos || has_parent_component(rel)) {
        ctx->refuse(TEXOPT_E_MALFORMED, "URI \"" + uri + "\" leaves the model's directory");
        return false;
    }
    std::string candidate = prefix + rel;
    char *real = realpath(candidate.c_str(), nullptr);
    if (!real)
        return false; /* not found: tinygltf reports it, or we do for images */
    std::string resolved(real);
    free(real);
    if (resolved.compare(0, prefix.size(), prefix) != 0) {
        ctx->refuse(TEXOPT_E_MALFORMED, "URI \"" + uri + "\" resolves (through a link) outside the model's directory");
        return false;
    }
    *real_out = resolved;
    return true;
}

bool fs_file_exists(const std::string &path, void *user)
{
    std::string real;
    if (!resolve_inside(static_cast<gltf_load_context *>(user), path, &real))
        return false;
    struct stat sb;
    return stat(real.c_str(), &sb) == 0 && S_ISREG(sb.st_mode);
}

std::string fs_expand_path(const std::string &path, void *)
{
    return path; /* tinygltf's default runs wordexp() on file names: never */
}

} // namespace

texopt_status gltf_read_file_limited(const std::string &path, uint64_t max_bytes, std::vector<unsigned char> *out,
                                     std::string *why)
{
    FILE *f = fopen(path.c_str(), "rb");
    if (!f) {
        *why = "cannot open " + path + ": " + strerror(errno);
        return TEXOPT_E_IO;
    }
    struct stat sb;
    if (fstat(fileno(f), &sb) != 0 || !S_ISREG(sb.st_mode)) {
        fclose(f);
        *why = path + " is not a regular file";
        return TEXOPT_E_IO;
    }
    if ((uint64_t)sb.st_size > max_bytes) {
        fclose(f);
        *why = path + " has " + std::to_string((long long)sb.st_size) + " bytes, more than the limit of " +
               std::to_string((unsigned long long)max_bytes);
        return TEXOPT_E_LIMIT;
    }
    try {
        out->resize((size_t)sb.st_size);
    } catch (const std::bad_alloc &) {
        fclose(f);
        *why = "no memory to read " + path;
        return TEXOPT_E_NOMEM;
    }
    size_t got = out->empty() ? 0 : fread(out->data(), 1, out->size(), f);
    fclose(f);
    if (got != out->size()) {
        *why = "cannot read " + path;
        return TEXOPT_E_IO;
    }
    return TEXOPT_OK;
}

namespace
{

bool fs_read_whole_file(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *user)
{
    gltf_load_context *ctx = static_cast<gltf_load_context *>(user);
    std::string real, why;
    if (!resolve_inside(ctx, path, &real))
        return false;
    texopt_status st = gltf_read_file_limited(real, ctx->max_file_bytes, out, &why);
    if (st != TEXOPT_OK) {
        ctx->refuse(st, why);
        if (err)
            *err += why;
        return false;
    }
    return true;
}

bool fs_write_whole_file(std::string *err, const std::string &, const std::vector<unsigned char> &, void *)
{
    if (err)
        *err += "texopt never writes through tinygltf";
    return false;
}

} // namespace

tinygltf::FsCallbacks gltf_confined_fs(gltf_load_context *ctx)
{
    tinygltf::FsCallbacks fs = {&fs_file_exists, &fs_expand_path, &fs_read_whole_file, &fs_write_whole_file, ctx};
    return fs;
}

std::string gltf_absolute_directory(const char *dir)
{
    char *real = realpath(dir, nullptr);
    if (!real)
        return std::string();
    std::string r(real);
    free(real);
    while (r.size() > 1 && r.back() == '/')
        r.pop_back();
    return r == "/" ? std::string() : r; /* a model at the root may not read the whole disk */
}
