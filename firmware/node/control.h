/* Hub-to-node datagrams: decodes and checks a Control or HubAnnounce datagram and turns it into
 * one typed command for the node loop. Mask images arrive in chunks and are assembled here into
 * a buffer allocated once. Anything malformed, out of range or of the wrong kind is rejected
 * with a reason (and counted by the caller); nothing here touches the camera or the network. */
#ifndef MN_NODE_CONTROL_H
#define MN_NODE_CONTROL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define MN_CONTROL_MAX_RECTS 16
/* Mask images up to this many cells (a 1280x800 frame at 4 px cells is 64000). */
#define MN_CONTROL_MAX_MASK_CELLS (512u * 512u)

enum mn_command_kind {
    MN_CMD_NONE,       /* accepted but nothing to do yet (a mask chunk that is not the last) */
    MN_CMD_START,
    MN_CMD_STOP,
    MN_CMD_THRESHOLD,
    MN_CMD_EXPOSURE,
    MN_CMD_PICTURE,
    MN_CMD_MASK_CLEAR,
    MN_CMD_MASK_RECTS,
    MN_CMD_MASK_BITS,
    MN_CMD_PREVIEW,
    MN_CMD_IDENTIFY,
    MN_CMD_ANNOUNCE,   /* HubAnnounce: where the hub listens, session epoch and rate */
};

struct mn_mask_rect {
    uint32_t x, y, w, h;
};

struct mn_command {
    enum mn_command_kind kind;
    /* The datagram was a v1 Control for this node (or every node), whatever its fate: the node
     * answers `sequence` with a ControlAck. False for anything it could not read as one. */
    bool acknowledge;
    uint32_t sequence;
    union {
        struct { int64_t epoch_ns; uint32_t rate_millihz; } start;       /* also ANNOUNCE */
        struct { bool automatic; uint8_t value; } threshold;
        struct { uint32_t exposure_us, gain_milli; } exposure;          /* 0 = unchanged */
        struct { int32_t brightness_pct, contrast_pct; } picture;      /* -1 = unchanged */
        struct { struct mn_mask_rect rects[MN_CONTROL_MAX_RECTS]; size_t n; } rects;
        struct { uint32_t cell_px, cells_x, cells_y; const uint8_t *bits; } bits; /* bits owned
                                                              by the handler until the next call */
        struct { bool thresholded; uint32_t downscale; } preview;
        struct { uint32_t duration_ms; } identify;
        struct { uint16_t port; int64_t epoch_ns; uint32_t rate_millihz; } announce;
    } u;
};

enum mn_control_result {
    MN_CONTROL_ACCEPTED = 0,
    MN_CONTROL_IGNORED = 1,  /* well-formed but addressed to another node, or nothing to do (a
                                mask chunk already stored) */
    MN_CONTROL_REJECTED = -1,
};

struct mn_control;

/* node_id: this node (commands for 0 or node_id are accepted). NULL with errno set; free with
 * mn_control_free. */
struct mn_control *mn_control_new(uint32_t node_id);
void mn_control_free(struct mn_control *ctl);

/* Decodes one datagram. announce_socket: it arrived on the broadcast socket, where only
 * HubAnnounce is valid (and Control is not). On MN_CONTROL_REJECTED, and on MN_CONTROL_IGNORED
 * with out->acknowledge, *reason says why.
 * Mask image chunks: one image's chunks carry consecutive sequences (proto/mocap.proto), so the
 * assembly is keyed on the sequence of chunk 0; a chunk stored already is ignored (the hub sent
 * it again because an ack was lost), a chunk with another first sequence starts a new image. */
enum mn_control_result mn_control_handle(struct mn_control *ctl, const uint8_t *data, size_t len,
                                         bool announce_socket, struct mn_command *out,
                                         const char **reason);

#endif
