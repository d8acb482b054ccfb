/* build_info.h - which texopt a binary is: its version and the source revision it was built
 * from, for `texopt --version` and the JSON the tools write, so that a measurement can be
 * traced to the code that made it.
 *
 * The revision is `git describe --always --dirty` of the source tree at build time
 * (cmake/revision.cmake): a commit, "<commit>-dirty" for a tree with uncommitted changes, or
 * "unknown" outside a git checkout. Not a build timestamp: the same tree gives the same
 * string. */
#ifndef TEXOPT_BUILD_INFO_H
#define TEXOPT_BUILD_INFO_H

/* "0.1.0": the project version (CMakeLists.txt). */
const char *texopt_version(void);

/* The source revision, as above. */
const char *texopt_build_revision(void);

struct cJSON;

/* Adds {"version": ..., "revision": ...} to the JSON object `parent` as member "texopt". */
void texopt_build_info_add_json(struct cJSON *parent);

#endif
