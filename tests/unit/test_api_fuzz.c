/* test_api_fuzz.c - the parsers of outside input under random and mutated input (seeded, so
 * a failure reproduces): params JSON, upload file names, route matching. Run under the
 * sanitizer build this is the memory-safety check; the assertions are the contracts: an
 * accepted params object validates, a refusal names a key, a "safe" name has no way out of
 * its directory, a matched job route has a well-formed id. */
#include <stdint.h>
#include <string.h>

#include "params_json.h"
#include "routes.h"
#include "test.h"
#include "upload.h"

static uint64_t next_random(uint64_t *state)
{
    /* splitmix64 */
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static const char *const seeds[] = {
    "{\"method\":\"input\",\"relative_cost\":0.5,\"iterations\":20}",
    "{\"texture_width\":512,\"texture_height\":256,\"evaluate\":true,\"seed\":42}",
    "{\"budget\":\"target_loss\",\"target_loss\":0.05,\"epsilon\":0.02,\"lambda_min\":0.2}",
    "{}",
};
static const char alphabet[] = "{}[]\":,0123456789.-+eE truefalsnmethodinputbudget\\u";

static void mutate(char *buf, size_t *len, size_t cap, uint64_t *rng)
{
    int edits = 1 + (int)(next_random(rng) % 4);
    for (int e = 0; e < edits; e++) {
        size_t at = *len ? next_random(rng) % *len : 0;
        char c = alphabet[next_random(rng) % (sizeof alphabet - 1)];
        switch (next_random(rng) % 3) {
        case 0: /* replace */
            if (*len)
                buf[at] = c;
            break;
        case 1: /* insert */
            if (*len + 1 < cap) {
                memmove(buf + at + 1, buf + at, *len - at);
                buf[at] = c;
                (*len)++;
            }
            break;
        default: /* delete */
            if (*len) {
                memmove(buf + at, buf + at + 1, *len - at - 1);
                (*len)--;
            }
        }
    }
    buf[*len] = '\0';
}

/* A refusal points at what to fix: the params object or one of its keys. */
static int names_a_key(const char *err)
{
    static const char *const keys[] = {"params",       "method",      "budget",          "relative_cost",
                                       "texture_size", "target_loss", "epsilon",         "iterations",
                                       "lambda_min",   "threads",     "eval_resolution", "parameters must be finite"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (strstr(err, keys[i]))
            return 1;
    return 0;
}

TEST(mutated_params_are_accepted_valid_or_refused_by_name)
{
    uint64_t rng = 20261121;
    int accepted = 0, refused = 0;
    for (int i = 0; i < 20000; i++) {
        char buf[256];
        const char *seed = seeds[next_random(&rng) % (sizeof seeds / sizeof seeds[0])];
        size_t len = strlen(seed);
        memcpy(buf, seed, len + 1);
        mutate(buf, &len, sizeof buf, &rng);
        texopt_params p;
        char err[256] = "";
        texopt_status s = api_params_from_text(buf, len, &p, err, sizeof err);
        if (s == TEXOPT_OK) {
            char again[256] = "";
            CHECK_MSG(texopt_params_validate(&p, again, sizeof again) == TEXOPT_OK, "accepted invalid: %s", buf);
            accepted++;
        } else {
            CHECK_MSG(s == TEXOPT_E_INVALID_ARGUMENT, "status %d for %s", (int)s, buf);
            CHECK_MSG(names_a_key(err), "message '%s' names no key for %s", err, buf);
            refused++;
        }
    }
    /* Both outcomes must really occur, or the mutations test nothing. */
    CHECK(accepted > 100);
    CHECK(refused > 1000);
}

static int has_way_out(const char *name)
{
    if (name[0] == '/' || strchr(name, '\\'))
        return 1;
    const char *p = name;
    for (;;) {
        const char *slash = strchr(p, '/');
        size_t n = slash ? (size_t)(slash - p) : strlen(p);
        if (n == 0 || (n == 2 && p[0] == '.' && p[1] == '.') || (n == 1 && p[0] == '.'))
            return 1;
        if (!slash)
            return 0;
        p = slash + 1;
    }
}

TEST(random_names_judged_safe_cannot_leave_the_directory)
{
    uint64_t rng = 7;
    static const char parts[] = "./\\a.b";
    int safe = 0;
    for (int i = 0; i < 50000; i++) {
        char name[16];
        int len = (int)(next_random(&rng) % 12);
        for (int k = 0; k < len; k++)
            name[k] = parts[next_random(&rng) % (sizeof parts - 1)];
        name[len] = '\0';
        if (api_upload_safe_name(name)) {
            CHECK_MSG(!has_way_out(name), "'%s' judged safe", name);
            safe++;
        }
    }
    CHECK(safe > 1000);
}

TEST(random_paths_match_only_well_formed_routes)
{
    uint64_t rng = 99;
    static const char parts[] = "/v1jobs0123456789abcdefABC.%?";
    for (int i = 0; i < 50000; i++) {
        char path[80] = "/v1/jobs/";
        size_t len = strlen(path);
        size_t extra = next_random(&rng) % 60;
        for (size_t k = 0; k < extra; k++)
            path[len++] = parts[next_random(&rng) % (sizeof parts - 1)];
        path[len] = '\0';
        api_match m = api_route_match(path);
        if (m.route >= ROUTE_JOB && m.route <= ROUTE_JOB_REPORT) {
            CHECK_EQ_INT(strlen(m.id), JOB_ID_LEN);
            CHECK_MSG(strspn(m.id, "0123456789abcdef") == JOB_ID_LEN, "bad id from %s", path);
        }
    }
}
