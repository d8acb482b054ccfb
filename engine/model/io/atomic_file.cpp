/* atomic_file.cpp - temp file + fsync + rename (see atomic_file.h). C++ only because the
 * build compiles engine/io as C++17; it uses nothing but POSIX. */
#include "atomic_file.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace
{

std::string directory_of(const std::string &path)
{
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos)
        return ".";
    if (slash == 0)
        return "/";
    return path.substr(0, slash);
}

bool write_all(int fd, const unsigned char *bytes, size_t len)
{
    while (len > 0) {
        ssize_t n = write(fd, bytes, len);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return false;
        }
        bytes += n;
        len -= (size_t)n;
    }
    return true;
}

/* A rename is only durable once the directory entry is on disk too. Some file systems
 * refuse fsync on directories (EINVAL); the data itself is already safe then. */
void sync_directory(const std::string &dir)
{
    int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

} // namespace

extern "C" texopt_status texopt_write_file_atomic(const char *path, const void *bytes, size_t len, char *err,
                                                  size_t err_len)
{
    if (!path || !*path || (!bytes && len > 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "no path or no bytes to write");
    std::string tmpl = std::string(path) + ".tmp.XXXXXX";
    int fd = mkstemp(&tmpl[0]);
    if (fd < 0)
        return texopt_fail(err, err_len, TEXOPT_E_IO, "cannot create a temporary file for %s: %s", path,
                           strerror(errno));
    bool ok = write_all(fd, static_cast<const unsigned char *>(bytes), len);
    int saved = errno;
    if (ok && fsync(fd) != 0) {
        ok = false;
        saved = errno;
    }
    if (close(fd) != 0 && ok) {
        ok = false;
        saved = errno;
    }
    /* mkstemp makes 0600 files; outputs are meant to be read by others like any file. */
    if (ok)
        (void)chmod(tmpl.c_str(), 0644);
    if (ok && rename(tmpl.c_str(), path) != 0) {
        ok = false;
        saved = errno;
    }
    if (!ok) {
        unlink(tmpl.c_str());
        return texopt_fail(err, err_len, TEXOPT_E_IO, "cannot write %s: %s", path, strerror(saved));
    }
    sync_directory(directory_of(path));
    return TEXOPT_OK;
}
