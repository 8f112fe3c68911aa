/* UDP sockets of the node (see net.h). Plain BSD sockets, non-blocking, no connect(): a
 * connected UDP socket would turn ICMP port-unreachable into errors on later sends and
 * receives, which we would rather count than react to. */
#include "node/net.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "common/log.h"

struct mn_net {
    int fd;
    int announce_fd;
    struct sockaddr_storage hub;
    socklen_t hub_len;
    bool hub_known;
    bool hub_configured;
    struct mn_net_stats stats;
};

static int resolve(const char *host, uint16_t port, struct sockaddr_storage *out, socklen_t *len,
                   char *err, size_t errlen)
{
    struct addrinfo hints;
    memset(&hints, 0, sizeof(hints));
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_DGRAM;
    char service[8];
    snprintf(service, sizeof(service), "%u", port);
    struct addrinfo *res = NULL;
    int rc = getaddrinfo(host, service, &hints, &res);
    if (rc != 0) {
        snprintf(err, errlen, "hub '%s': %s", host, gai_strerror(rc));
        errno = EHOSTUNREACH;
        return -1;
    }
    memcpy(out, res->ai_addr, res->ai_addrlen);
    *len = res->ai_addrlen;
    freeaddrinfo(res);
    return 0;
}

static int open_socket(int family, uint16_t port, bool reuse, char *err, size_t errlen)
{
    int fd = socket(family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        snprintf(err, errlen, "socket: %s", strerror(errno));
        return -1;
    }
    int one = 1;
    /* Several nodes on one machine (simulated sessions) all hear the same announce port. */
    if (reuse && setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one)) < 0)
        goto fail;
    struct sockaddr_storage addr;
    socklen_t len;
    memset(&addr, 0, sizeof(addr));
    if (family == AF_INET6) {
        struct sockaddr_in6 *a = (struct sockaddr_in6 *)&addr;
        a->sin6_family = AF_INET6;
        a->sin6_addr = in6addr_any;
        a->sin6_port = htons(port);
        len = sizeof(*a);
    } else {
        struct sockaddr_in *a = (struct sockaddr_in *)&addr;
        a->sin_family = AF_INET;
        a->sin_addr.s_addr = htonl(INADDR_ANY);
        a->sin_port = htons(port);
        len = sizeof(*a);
    }
    if (bind(fd, (struct sockaddr *)&addr, len) < 0)
        goto fail;
    return fd;

fail:;
    int e = errno;
    snprintf(err, errlen, "UDP port %u: %s", port, strerror(e));
    close(fd);
    errno = e;
    return -1;
}

struct mn_net *mn_net_new(const char *hub_host, uint16_t hub_port, uint16_t control_port,
                          uint16_t announce_port, uint32_t send_buffer_kb, char *err,
                          size_t errlen)
{
    struct mn_net *net = calloc(1, sizeof(*net));
    if (net == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    int e;
    net->announce_fd = -1;
    int family = AF_INET;
    if (hub_host != NULL && hub_host[0] != '\0') {
        if (resolve(hub_host, hub_port, &net->hub, &net->hub_len, err, errlen) < 0) {
            e = errno;
            goto fail_free;
        }
        family = net->hub.ss_family;
        net->hub_known = true;
        net->hub_configured = true;
    }
    net->fd = open_socket(family, control_port, false, err, errlen);
    if (net->fd < 0) {
        e = errno;
        goto fail_free;
    }
    /* A deep send buffer absorbs a preview burst; frames still go out first in the loop. */
    int sndbuf = (int)send_buffer_kb * 1024;
    setsockopt(net->fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof(sndbuf));
    if (announce_port != 0) {
        char why[256];
        net->announce_fd = open_socket(AF_INET, announce_port, true, why, sizeof(why));
        if (net->announce_fd < 0) {
            e = errno;
            if (!net->hub_configured) {
                snprintf(err, errlen, "no hub configured and cannot listen for its announce: %s",
                         why);
                goto fail_sock;
            }
            mn_log_warn("not listening for hub announces (%s); using the configured hub", why);
        }
    }
    return net;

fail_sock:
    close(net->fd);
fail_free:
    free(net);
    errno = e;
    return NULL;
}

void mn_net_free(struct mn_net *net)
{
    if (net == NULL)
        return;
    if (net->announce_fd >= 0)
        close(net->announce_fd);
    close(net->fd);
    free(net);
}

int mn_net_fd(const struct mn_net *net)
{
    return net->fd;
}

int mn_net_announce_fd(const struct mn_net *net)
{
    return net->announce_fd;
}

bool mn_net_hub_known(const struct mn_net *net)
{
    return net->hub_known;
}

uint16_t mn_net_local_port(const struct mn_net *net)
{
    struct sockaddr_storage addr;
    socklen_t len = sizeof(addr);
    if (getsockname(net->fd, (struct sockaddr *)&addr, &len) < 0)
        return 0;
    if (addr.ss_family == AF_INET6)
        return ntohs(((struct sockaddr_in6 *)&addr)->sin6_port);
    return ntohs(((struct sockaddr_in *)&addr)->sin_port);
}

int mn_net_send(struct mn_net *net, const uint8_t *data, size_t len)
{
    if (!net->hub_known) {
        net->stats.dropped++;
        errno = EDESTADDRREQ;
        return -1;
    }
    ssize_t rc;
    do {
        rc = sendto(net->fd, data, len, MSG_DONTWAIT | MSG_NOSIGNAL,
                    (const struct sockaddr *)&net->hub, net->hub_len);
    } while (rc < 0 && errno == EINTR);
    if (rc < 0 || (size_t)rc != len) {
        net->stats.dropped++;
        if (rc >= 0)
            errno = EMSGSIZE;
        return -1;
    }
    net->stats.sent++;
    return 0;
}

static bool same_host(const struct sockaddr_storage *a, const struct sockaddr_storage *b)
{
    if (a->ss_family != b->ss_family)
        return false;
    if (a->ss_family == AF_INET)
        return ((const struct sockaddr_in *)a)->sin_addr.s_addr ==
               ((const struct sockaddr_in *)b)->sin_addr.s_addr;
    if (a->ss_family == AF_INET6)
        return memcmp(&((const struct sockaddr_in6 *)a)->sin6_addr,
                      &((const struct sockaddr_in6 *)b)->sin6_addr, sizeof(struct in6_addr)) == 0;
    return false;
}

ssize_t mn_net_recv(struct mn_net *net, int fd, uint8_t *buf, size_t cap, bool *from_hub,
                    uint32_t *from_ipv4)
{
    struct sockaddr_storage from;
    socklen_t len = sizeof(from);
    ssize_t n;
    do {
        n = recvfrom(fd, buf, cap, MSG_DONTWAIT | MSG_TRUNC, (struct sockaddr *)&from, &len);
    } while (n < 0 && errno == EINTR);
    if (n < 0)
        return (errno == EAGAIN || errno == EWOULDBLOCK || errno == ECONNREFUSED) ? 0 : -1;
    /* MSG_TRUNC reports the real size: an oversized datagram is passed on as such (the caller
     * rejects it) instead of being silently cut. */
    *from_hub = net->hub_known && same_host(&from, &net->hub);
    *from_ipv4 = from.ss_family == AF_INET ? ((struct sockaddr_in *)&from)->sin_addr.s_addr : 0;
    return n;
}

bool mn_net_set_hub_from_announce(struct mn_net *net, uint32_t sender_ipv4, uint16_t port)
{
    if (net->hub_configured || sender_ipv4 == 0)
        return false;
    struct sockaddr_in a;
    memset(&a, 0, sizeof(a));
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = sender_ipv4;
    a.sin_port = htons(port);
    if (net->hub_known && net->hub_len == sizeof(a) && memcmp(&net->hub, &a, sizeof(a)) == 0)
        return false;
    memset(&net->hub, 0, sizeof(net->hub));
    memcpy(&net->hub, &a, sizeof(a));
    net->hub_len = sizeof(a);
    net->hub_known = true;
    return true;
}

void mn_net_get_stats(const struct mn_net *net, struct mn_net_stats *out)
{
    *out = net->stats;
}
