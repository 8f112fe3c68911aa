/* UDP transport of the node: one socket that sends marker frames, status and previews to the hub
 * and receives the hub's control datagrams, plus one socket listening for the hub's HubAnnounce
 * broadcast. Sending never blocks: when the hub is unknown, unreachable or the socket buffer is
 * full the datagram is dropped and counted, so capture never waits on the network. */
#ifndef MN_NODE_NET_H
#define MN_NODE_NET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

struct mn_net;

struct mn_net_stats {
    uint64_t sent;           /* datagrams handed to the kernel */
    uint64_t dropped;        /* datagrams not sent (no hub, buffer full, unreachable) */
};

/* hub_host NULL or "": the hub is learned from HubAnnounce (mn_net_set_hub_from_announce).
 * announce_port 0: no announce socket. NULL with errno set and the reason in err; free with
 * mn_net_free. */
struct mn_net *mn_net_new(const char *hub_host, uint16_t hub_port, uint16_t control_port,
                          uint16_t announce_port, uint32_t send_buffer_kb, char *err,
                          size_t errlen);
void mn_net_free(struct mn_net *net);

int mn_net_fd(const struct mn_net *net);
/* -1 when there is no announce socket. */
int mn_net_announce_fd(const struct mn_net *net);
bool mn_net_hub_known(const struct mn_net *net);
/* Local port of the data socket (useful with control_port 0). */
uint16_t mn_net_local_port(const struct mn_net *net);

/* Sends one datagram to the hub; 0, or -1 with errno (EAGAIN, ENOBUFS, ECONNREFUSED,
 * EDESTADDRREQ when the hub is unknown ...) after counting the drop. */
int mn_net_send(struct mn_net *net, const uint8_t *data, size_t len);

/* Receives one datagram from fd (data or announce socket). Returns its length, 0 when nothing is
 * queued, -1 on error. *from_hub tells whether the sender is the known hub (control datagrams
 * from anyone else are refused by the caller); *from_ipv4 gets the sender's IPv4 address in
 * network order when it is one (0 otherwise), for learning the hub from an announce. */
ssize_t mn_net_recv(struct mn_net *net, int fd, uint8_t *buf, size_t cap, bool *from_hub,
                    uint32_t *from_ipv4);

/* Adopts sender_ipv4:port as the hub unless a hub was configured. Returns true when the hub
 * address changed. */
bool mn_net_set_hub_from_announce(struct mn_net *net, uint32_t sender_ipv4, uint16_t port);

void mn_net_get_stats(const struct mn_net *net, struct mn_net_stats *out);

#endif
