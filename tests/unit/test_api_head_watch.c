/* test_api_head_watch.c - request heads are cut when late, when their address has too many
 * waiting, or when too many wait in all; a cut shuts the socket down (the peer reads EOF)
 * and a complete head is never cut. Sockets are socketpair ends; addresses are made up. */
#define _DEFAULT_SOURCE
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "head_watch.h"
#include "test.h"

typedef struct conn {
    int server, client;
    head_entry *e;
} conn;

static struct sockaddr_in address(const char *ip)
{
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    inet_pton(AF_INET, ip, &a.sin_addr);
    return a;
}

static int open_conn(head_watch *hw, conn *c, const char *ip, double now)
{
    int fds[2];
    if (socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0)
        return 0;
    c->server = fds[0];
    c->client = fds[1];
    fcntl(c->client, F_SETFL, O_NONBLOCK);
    struct sockaddr_in a = address(ip);
    c->e = head_watch_open(hw, c->server, (struct sockaddr *)&a, now);
    return c->e != NULL;
}

/* The server side was shut down: the client reads end of file (not "would block"). */
static int was_cut(const conn *c)
{
    char b;
    return read(c->client, &b, 1) == 0;
}

static void close_conn(head_watch *hw, conn *c)
{
    head_watch_close(hw, c->e);
    close(c->server);
    close(c->client);
}

TEST(a_late_head_is_cut_and_a_complete_one_never)
{
    head_watch *hw = head_watch_create(10, 100, 100);
    CHECK(hw);
    conn a, b, c;
    CHECK(open_conn(hw, &a, "10.0.0.1", 100));
    CHECK(open_conn(hw, &b, "10.0.0.2", 105));
    CHECK(open_conn(hw, &c, "10.0.0.3", 100));
    head_watch_done(hw, c.e); /* its head arrived in time */
    CHECK_EQ_INT(head_watch_waiting(hw), 2);
    CHECK_EQ_INT(head_watch_sweep(hw, 109.9), 0);
    CHECK_EQ_INT(head_watch_sweep(hw, 110), 1);
    CHECK(was_cut(&a));
    CHECK(!was_cut(&b));
    CHECK(!was_cut(&c));
    /* A keep-alive connection waits for its next head from now on. */
    head_watch_again(hw, c.e, 112);
    CHECK_EQ_INT(head_watch_sweep(hw, 115), 1); /* b: 105 + 10 */
    CHECK(!was_cut(&c));
    CHECK_EQ_INT(head_watch_sweep(hw, 122), 1);
    CHECK(was_cut(&c));
    CHECK(head_watch_cut_count(hw) == 3);
    close_conn(hw, &a);
    close_conn(hw, &b);
    close_conn(hw, &c);
    CHECK_EQ_INT(head_watch_waiting(hw), 0);
    head_watch_destroy(hw);
}

TEST(one_address_holds_at_most_its_share_of_waiting_heads)
{
    head_watch *hw = head_watch_create(10, 100, 3);
    CHECK(hw);
    conn c[5];
    for (int i = 0; i < 4; i++)
        CHECK(open_conn(hw, &c[i], "10.0.0.1", 100 + i));
    CHECK(open_conn(hw, &c[4], "10.0.0.2", 104));
    /* The fourth from 10.0.0.1 cut its oldest; the other address is untouched. */
    CHECK(was_cut(&c[0]));
    for (int i = 1; i < 5; i++)
        CHECK_MSG(!was_cut(&c[i]), "connection %d cut", i);
    CHECK_EQ_INT(head_watch_waiting(hw), 4);
    for (int i = 0; i < 5; i++)
        close_conn(hw, &c[i]);
    head_watch_destroy(hw);
}

TEST(the_oldest_waiting_head_goes_when_all_slots_for_heads_are_taken)
{
    head_watch *hw = head_watch_create(10, 3, 100);
    CHECK(hw);
    conn c[4];
    static const char *const ips[] = {"10.0.0.1", "10.0.0.2", "10.0.0.3", "10.0.0.4"};
    for (int i = 0; i < 3; i++)
        CHECK(open_conn(hw, &c[i], ips[i], 100 + i));
    head_watch_done(hw, c[0].e); /* complete: not a waiting head */
    CHECK(open_conn(hw, &c[3], ips[3], 103));
    CHECK(!was_cut(&c[0]));
    CHECK_EQ_INT(head_watch_waiting(hw), 3);
    conn extra;
    CHECK(open_conn(hw, &extra, "10.0.0.9", 104));
    CHECK(was_cut(&c[1])); /* the oldest waiting */
    CHECK(!was_cut(&c[2]));
    CHECK(!was_cut(&extra));
    for (int i = 0; i < 4; i++)
        close_conn(hw, &c[i]);
    close_conn(hw, &extra);
    head_watch_destroy(hw);
}
