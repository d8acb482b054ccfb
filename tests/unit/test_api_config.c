/* test_api_config.c - texoptd's configuration: defaults, environment, flags over
 * environment, and bad values refused by name. */
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "test.h"

TEST(defaults_bind_loopback)
{
    service_config c;
    config_defaults(&c);
    CHECK(strcmp(c.bind, "127.0.0.1") == 0);
    CHECK_EQ_INT(c.port, 8080);
    CHECK_EQ_INT(c.workers, 1);
    CHECK_EQ_INT(c.queue_limit, 16);
    CHECK(c.max_upload_bytes == 256ull << 20);
    CHECK(c.api_token[0] == '\0');
    CHECK(c.cors_origin[0] == '\0');
    CHECK_EQ_INT(c.max_connections_per_ip, 64);
    CHECK_EQ_INT(c.header_timeout_seconds, 10);
    CHECK_EQ_INT(c.idle_timeout_seconds, 30);
    CHECK(c.memory_budget > 0);
}

TEST(slow_client_and_memory_settings_are_read)
{
    service_config c;
    char err[256] = "";
    config_defaults(&c);
    char *argv[] = {"texoptd",
                    "--max-connections-per-ip",
                    "8",
                    "--header-timeout=3",
                    "--idle-timeout",
                    "7",
                    "--memory-budget",
                    "1000000",
                    NULL};
    CHECK(config_apply_args(&c, 8, argv, err, sizeof err) == 0);
    CHECK_EQ_INT(c.max_connections_per_ip, 8);
    CHECK_EQ_INT(c.header_timeout_seconds, 3);
    CHECK_EQ_INT(c.idle_timeout_seconds, 7);
    CHECK(c.memory_budget == 1000000);
    char *zero[] = {"texoptd", "--header-timeout", "0", NULL};
    CHECK(config_apply_args(&c, 3, zero, err, sizeof err) == -1);
    CHECK(strstr(err, "--header-timeout") != NULL);
}

TEST(flags_override_the_environment)
{
    service_config c;
    char err[256] = "";
    config_defaults(&c);
    setenv("TEXOPT_PORT", "9000", 1);
    setenv("TEXOPT_WORKERS", "3", 1);
    setenv("TEXOPT_API_TOKEN", "s3cret", 1);
    CHECK(config_apply_env(&c, err, sizeof err) == 0);
    unsetenv("TEXOPT_PORT");
    unsetenv("TEXOPT_WORKERS");
    unsetenv("TEXOPT_API_TOKEN");
    CHECK_EQ_INT(c.port, 9000);
    CHECK_EQ_INT(c.workers, 3);
    CHECK(strcmp(c.api_token, "s3cret") == 0);
    char *argv[] = {"texoptd", "--port",        "0", "--workers=2", "--max-upload-bytes", "1000", "--data-dir",
                    "/tmp/x",  "--cors-origin", "*", NULL};
    CHECK(config_apply_args(&c, 10, argv, err, sizeof err) == 0);
    CHECK_EQ_INT(c.port, 0);
    CHECK_EQ_INT(c.workers, 2);
    CHECK(c.max_upload_bytes == 1000);
    CHECK(strcmp(c.data_dir, "/tmp/x") == 0);
    CHECK(strcmp(c.cors_origin, "*") == 0);
}

TEST(bad_settings_are_refused_by_name)
{
    service_config c;
    char err[256] = "";
    config_defaults(&c);
    char *bad_port[] = {"texoptd", "--port", "70000", NULL};
    CHECK(config_apply_args(&c, 3, bad_port, err, sizeof err) == -1);
    CHECK(strstr(err, "--port") != NULL);
    char *no_value[] = {"texoptd", "--workers", NULL};
    CHECK(config_apply_args(&c, 2, no_value, err, sizeof err) == -1);
    CHECK(strstr(err, "--workers needs a value") != NULL);
    char *unknown[] = {"texoptd", "--wrokers", "2", NULL};
    CHECK(config_apply_args(&c, 3, unknown, err, sizeof err) == -1);
    CHECK(strstr(err, "unknown flag '--wrokers'") != NULL);
    char *token_flag[] = {"texoptd", "--api-token", "x", NULL}; /* environment only */
    CHECK(config_apply_args(&c, 3, token_flag, err, sizeof err) == -1);
    char *help[] = {"texoptd", "--help", NULL};
    CHECK(config_apply_args(&c, 2, help, err, sizeof err) == 1);
    setenv("TEXOPT_QUEUE_LIMIT", "many", 1);
    CHECK(config_apply_env(&c, err, sizeof err) == -1);
    unsetenv("TEXOPT_QUEUE_LIMIT");
    CHECK(strstr(err, "TEXOPT_QUEUE_LIMIT") != NULL);
}
