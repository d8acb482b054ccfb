/* store_pg_schema.h - the PostgreSQL schema of the shared job store, as numbered migrations.
 *
 * texoptd creates and upgrades the schema itself at start-up (store_pg.c, under an advisory
 * lock so that nodes starting together apply each step once). The schema's version is the
 * number of migrations applied, kept in texopt_schema. A database from a newer texoptd is
 * refused rather than used half-understood. Adding a step is appending to the list; a step
 * once released is never edited.
 * Does not: connect (pure data and a plan, unit-tested without a server). */
#ifndef TEXOPT_SERVER_STORE_PG_SCHEMA_H
#define TEXOPT_SERVER_STORE_PG_SCHEMA_H

#include <stddef.h>

/* The number of migrations: the version this texoptd writes. */
int pg_schema_latest(void);

/* The SQL of migration `version` (1 .. latest), or NULL. */
const char *pg_schema_migration(int version);

/* The versions to apply to a database at `current`: *first .. latest (none when *first >
 * latest). -1 with a message when current is newer than this texoptd or negative. */
int pg_schema_plan(int current, int *first, char *err, size_t err_len);

#endif
