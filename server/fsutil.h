/* fsutil.h - the few filesystem operations the job store needs, done crash-safely.
 *
 * Does: atomic whole-file writes (temporary file in the same directory, fsync, rename,
 * fsync of the directory), recursive directory creation and removal, reading a small file.
 * Does not: lock files against other processes (one texoptd owns one data directory). */
#ifndef TEXOPT_SERVER_FSUTIL_H
#define TEXOPT_SERVER_FSUTIL_H

#include <stddef.h>

/* Writes len bytes to path so that path is either the old content or the new one, even
 * after a crash. Returns 0, or -1 with errno set. */
int fs_write_atomic(const char *path, const void *data, size_t len);

/* Makes dir and its missing parents (mode 0750). Returns 0, or -1 with errno set. */
int fs_mkdir_p(const char *dir);

/* Removes path and everything under it; a missing path is not an error. Returns 0 or -1. */
int fs_remove_tree(const char *path);

/* Reads the whole file into a new NUL-terminated buffer (caller frees) when it is at most
 * max_len bytes. Returns NULL with errno set otherwise. */
char *fs_read_small(const char *path, size_t max_len, size_t *len_out);

/* fsyncs the directory that holds path, so a rename or create inside it is durable. */
int fs_sync_parent(const char *path);

#endif
