/* test_store_shared.c - the parts of the shared (PostgreSQL) job store that need no server:
 * reading --store, hiding its password, the lease rules (heartbeat period, what becomes of a
 * job whose lease ran out, when a lease counts as lost), the schema's migration plan, the new
 * flags, and choosing the store from the configuration. tests/integration/service_nodes.sh
 * runs the store itself against a throw-away PostgreSQL cluster. */
#define _DEFAULT_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "fsutil.h"
#include "store.h"
#include "store_backend.h"
#include "store_lease.h"
#include "store_pg_schema.h"
#include "store_url.h"
#include "test.h"

TEST(store_url_tells_disk_postgres_and_nonsense_apart)
{
    CHECK(store_url_kind(NULL) == STORE_URL_DISK);
    CHECK(store_url_kind("") == STORE_URL_DISK);
    CHECK(store_url_kind("postgresql://db.example/texopt") == STORE_URL_POSTGRES);
    CHECK(store_url_kind("postgres:///texopt?host=/run/postgresql") == STORE_URL_POSTGRES);
    CHECK(store_url_kind("mysql://db/texopt") == STORE_URL_INVALID);
    CHECK(store_url_kind("/var/lib/texopt") == STORE_URL_INVALID);
    CHECK(store_url_kind("postgresql:") == STORE_URL_INVALID);
}

TEST(store_url_redact_hides_only_the_password)
{
    char out[256];
    store_url_redact("postgresql://texopt:s3cret@db:5432/jobs", out, sizeof out);
    CHECK(strcmp(out, "postgresql://texopt:***@db:5432/jobs") == 0);
    store_url_redact("postgres://texopt@db/jobs", out, sizeof out);
    CHECK(strcmp(out, "postgres://texopt@db/jobs") == 0);
    /* An @ after the path is not user-info. */
    store_url_redact("postgresql://db:5432/jobs?user=a@b", out, sizeof out);
    CHECK(strcmp(out, "postgresql://db:5432/jobs?user=a@b") == 0);
    store_url_redact("postgresql:///jobs?host=/tmp/s&port=5", out, sizeof out);
    CHECK(strcmp(out, "postgresql:///jobs?host=/tmp/s&port=5") == 0);
}

TEST(heartbeat_is_a_third_of_the_lease_at_most_a_second)
{
    CHECK_EQ_INT(lease_heartbeat_ms(30), 1000);
    CHECK_EQ_INT(lease_heartbeat_ms(3), 1000);
    CHECK_EQ_INT(lease_heartbeat_ms(2), 666);
}

TEST(an_expired_lease_reruns_until_the_attempts_are_spent)
{
    CHECK(lease_expired_outcome(1, 3, 0) == JOB_QUEUED);
    CHECK(lease_expired_outcome(2, 3, 0) == JOB_QUEUED);
    CHECK(lease_expired_outcome(3, 3, 0) == JOB_FAILED);
    CHECK(lease_expired_outcome(7, 3, 0) == JOB_FAILED);
    CHECK(lease_expired_outcome(1, 1, 0) == JOB_FAILED);
    /* A cancel asked of a node that died is honoured, not re-run. */
    CHECK(lease_expired_outcome(1, 3, 1) == JOB_CANCELED);
    CHECK(lease_expired_outcome(3, 3, 1) == JOB_CANCELED);
    job_problem p;
    lease_exhausted_problem(3, &p);
    CHECK_EQ_INT(p.status, 500);
    CHECK(strcmp(p.type, "urn:texopt:problem:attempts-exhausted") == 0);
    CHECK(strstr(p.detail, "3 times") != NULL);
    lease_exhausted_problem(1, &p);
    CHECK(strstr(p.detail, "1 time ") != NULL);
}

TEST(a_lease_is_lost_only_when_held_before_the_heartbeat)
{
    CHECK(lease_lost(0, 1000, 2000) == 1);
    CHECK(lease_lost(0, 2500, 2000) == 0); /* leased while the heartbeat ran */
    CHECK(lease_lost(1, 1000, 2000) == 0);
}

TEST(progress_is_published_on_a_new_stage_a_step_or_a_pause)
{
    CHECK(store_progress_worth_publishing(1, 0.1, 0.1, 1000, 1000) == 1);
    CHECK(store_progress_worth_publishing(0, 0.106, 0.1, 1000, 1000) == 1);
    CHECK(store_progress_worth_publishing(0, 0.102, 0.1, 1100, 1000) == 0);
    CHECK(store_progress_worth_publishing(0, 0.102, 0.1, 1250, 1000) == 1);
}

TEST(schema_plan_applies_what_is_missing_and_refuses_the_future)
{
    int latest = pg_schema_latest(), first = -1;
    char err[300] = "";
    CHECK(latest >= 1);
    CHECK(pg_schema_plan(0, &first, err, sizeof err) == 0);
    CHECK_EQ_INT(first, 1);
    CHECK(pg_schema_plan(latest, &first, err, sizeof err) == 0);
    CHECK_EQ_INT(first, latest + 1); /* nothing to do */
    CHECK(pg_schema_plan(latest + 1, &first, err, sizeof err) == -1);
    CHECK(strstr(err, "newer texoptd") != NULL);
    CHECK(pg_schema_plan(-1, &first, err, sizeof err) == -1);
    CHECK(pg_schema_migration(0) == NULL);
    CHECK(pg_schema_migration(latest + 1) == NULL);
    for (int v = 1; v <= latest; v++)
        CHECK(pg_schema_migration(v) != NULL);
    /* What the store's statements rely on. */
    const char *first_step = pg_schema_migration(1);
    CHECK(strstr(first_step, "CREATE TABLE texopt_jobs") != NULL);
    CHECK(strstr(first_step, "idempotency_key text UNIQUE") != NULL);
    CHECK(strstr(first_step, "lease_until_ms bigint") != NULL);
}

TEST(store_flags_and_environment_are_read)
{
    service_config c;
    char err[256] = "";
    config_defaults(&c);
    CHECK(c.store[0] == '\0');
    CHECK_EQ_INT(c.lease_seconds, 30);
    CHECK_EQ_INT(c.max_attempts, 3);
    setenv("TEXOPT_STORE", "postgresql://texopt:pw@db/jobs", 1);
    setenv("TEXOPT_BLOB_DIR", "/mnt/blobs", 1);
    CHECK(config_apply_env(&c, err, sizeof err) == 0);
    unsetenv("TEXOPT_STORE");
    unsetenv("TEXOPT_BLOB_DIR");
    CHECK(strcmp(c.store, "postgresql://texopt:pw@db/jobs") == 0);
    CHECK(strcmp(c.blob_dir, "/mnt/blobs") == 0);
    char *argv[] = {"texoptd", "--lease-seconds", "5", "--max-attempts=2", "--blob-dir", "/srv/b", NULL};
    CHECK(config_apply_args(&c, 6, argv, err, sizeof err) == 0);
    CHECK_EQ_INT(c.lease_seconds, 5);
    CHECK_EQ_INT(c.max_attempts, 2);
    CHECK(strcmp(c.blob_dir, "/srv/b") == 0);
    char *short_lease[] = {"texoptd", "--lease-seconds", "1", NULL};
    CHECK(config_apply_args(&c, 3, short_lease, err, sizeof err) == -1);
    CHECK(strstr(err, "--lease-seconds") != NULL);
    char *no_attempts[] = {"texoptd", "--max-attempts", "0", NULL};
    CHECK(config_apply_args(&c, 3, no_attempts, err, sizeof err) == -1);
    CHECK(strstr(err, "--max-attempts") != NULL);
}

TEST(the_configuration_chooses_the_store)
{
    service_config c;
    char err[512] = "", root[64];
    config_defaults(&c);
    strcpy(root, "/tmp/texopt-store-shared.XXXXXX");
    CHECK(mkdtemp(root) != NULL);
    snprintf(c.data_dir, sizeof c.data_dir, "%s", root);
    job_store *disk = store_open_config(&c, err, sizeof err);
    CHECK(disk != NULL);
    if (disk) {
        CHECK(strcmp(store_kind(disk), "disk") == 0);
        CHECK(store_shared(disk) == 0);
        CHECK(store_unreachable(disk) == 0);
        job_record r;
        const atomic_int *cancel = NULL;
        CHECK(store_lease_next(disk, 10, &r, &cancel) == NULL);
        store_close(disk);
    }
    snprintf(c.store, sizeof c.store, "mysql://db/jobs");
    CHECK(store_open_config(&c, err, sizeof err) == NULL);
    CHECK(strstr(err, "--store") != NULL);
    /* No server listens on this socket: start-up fails with the reason, password hidden. */
    snprintf(c.store, sizeof c.store, "postgresql://texopt:pw@/jobs?host=%s&port=1", root);
    err[0] = '\0';
    CHECK(store_open_config(&c, err, sizeof err) == NULL);
#ifdef TEXOPT_HAVE_POSTGRES
    CHECK(strstr(err, "cannot connect") != NULL);
    CHECK(strstr(err, "pw") == NULL);
#else
    CHECK(strstr(err, "without PostgreSQL") != NULL);
#endif
    fs_remove_tree(root);
}
