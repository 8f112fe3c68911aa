/* Control and HubAnnounce decoding, range checks beyond the wire's own rules (the wire allows
 * 16-bit brightness, a Y8 node does not), and mask-image assembly across chunks. */
#include "node/control.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "wire/wire.h"

/* Chunks of one mask image; 64 x 896 bytes covers MN_CONTROL_MAX_MASK_CELLS. */
#define MAX_MASK_CHUNKS 64

struct mn_control {
    uint32_t node_id;
    mocap_v1_Packet packet; /* decode scratch: large, so kept here rather than on the stack */
    uint8_t mask_bits[MN_CONTROL_MAX_MASK_CELLS / 8];
    uint32_t mask_cell_px, mask_cells_x, mask_cells_y, mask_chunk_count;
    uint32_t mask_first_sequence; /* sequence of chunk 0 of the image being assembled */
    uint64_t mask_chunks_seen;    /* bit i: chunk i arrived; all set once the image is applied */
};

struct mn_control *mn_control_new(uint32_t node_id)
{
    struct mn_control *ctl = calloc(1, sizeof(*ctl));
    if (ctl == NULL)
        return NULL;
    ctl->node_id = node_id;
    return ctl;
}

void mn_control_free(struct mn_control *ctl)
{
    free(ctl);
}

static enum mn_control_result reject(const char **reason, const char *why)
{
    *reason = why;
    return MN_CONTROL_REJECTED;
}

static enum mn_control_result mask_chunk(struct mn_control *ctl, const mocap_v1_SetMask *m,
                                         uint32_t sequence, struct mn_command *out,
                                         const char **reason)
{
    uint64_t cells = (uint64_t)m->cells_x * m->cells_y;
    if (cells > MN_CONTROL_MAX_MASK_CELLS)
        return reject(reason, "control: mask image larger than the node accepts");
    if (m->chunk_count > MAX_MASK_CHUNKS)
        return reject(reason, "control: mask image in too many chunks");
    /* Chunks of one image may arrive in any order and more than once; a chunk of another image
     * (another first sequence or shape) starts a new assembly. Unsigned wrap-around keeps the
     * first sequence right across 2^32. */
    uint32_t first_sequence = sequence - m->chunk_index;
    uint64_t bit = UINT64_C(1) << m->chunk_index;
    if (m->cell_px != ctl->mask_cell_px || m->cells_x != ctl->mask_cells_x ||
        m->cells_y != ctl->mask_cells_y || m->chunk_count != ctl->mask_chunk_count ||
        first_sequence != ctl->mask_first_sequence) {
        memset(ctl->mask_bits, 0, sizeof(ctl->mask_bits));
        ctl->mask_chunks_seen = 0;
        ctl->mask_cell_px = m->cell_px;
        ctl->mask_cells_x = m->cells_x;
        ctl->mask_cells_y = m->cells_y;
        ctl->mask_chunk_count = m->chunk_count;
        ctl->mask_first_sequence = first_sequence;
    } else if ((ctl->mask_chunks_seen & bit) != 0) {
        *reason = "control: mask chunk already stored";
        return MN_CONTROL_IGNORED;
    }
    /* The wire checked bit_offset + bits against the image size (rounded up to a byte). */
    memcpy(ctl->mask_bits + m->bit_offset / 8, m->bits.bytes, m->bits.size);
    ctl->mask_chunks_seen |= bit;
    uint64_t all = m->chunk_count == 64 ? UINT64_MAX : (UINT64_C(1) << m->chunk_count) - 1;
    if (ctl->mask_chunks_seen != all) {
        out->kind = MN_CMD_NONE;
        return MN_CONTROL_ACCEPTED;
    }
    out->kind = MN_CMD_MASK_BITS;
    out->u.bits.cell_px = m->cell_px;
    out->u.bits.cells_x = m->cells_x;
    out->u.bits.cells_y = m->cells_y;
    out->u.bits.bits = ctl->mask_bits;
    return MN_CONTROL_ACCEPTED;
}

static enum mn_control_result set_mask(struct mn_control *ctl, const mocap_v1_SetMask *m,
                                       uint32_t sequence, struct mn_command *out,
                                       const char **reason)
{
    if (m->bits.size > 0) {
        if (m->rects_count > 0 || m->clear)
            return reject(reason, "control: mask mixes an image with rectangles or clear");
        return mask_chunk(ctl, m, sequence, out, reason);
    }
    if (m->rects_count > 0) {
        if (m->clear)
            return reject(reason, "control: mask mixes rectangles with clear");
        out->kind = MN_CMD_MASK_RECTS;
        out->u.rects.n = m->rects_count;
        for (pb_size_t i = 0; i < m->rects_count; i++) {
            out->u.rects.rects[i].x = m->rects[i].x;
            out->u.rects.rects[i].y = m->rects[i].y;
            out->u.rects.rects[i].w = m->rects[i].width;
            out->u.rects.rects[i].h = m->rects[i].height;
        }
        return MN_CONTROL_ACCEPTED;
    }
    if (m->clear) {
        out->kind = MN_CMD_MASK_CLEAR;
        return MN_CONTROL_ACCEPTED;
    }
    return reject(reason, "control: empty mask command");
}

static enum mn_control_result control(struct mn_control *ctl, const mocap_v1_Control *c,
                                      struct mn_command *out, const char **reason)
{
    switch (c->which_command) {
    case mocap_v1_Control_start_tag:
        if (c->command.start.rate_millihz < 100 || c->command.start.rate_millihz > 1000000)
            return reject(reason, "control: start rate outside 0.1..1000 Hz");
        if (c->command.start.epoch_ns > INT64_MAX)
            return reject(reason, "control: start epoch out of range");
        out->kind = MN_CMD_START;
        out->u.start.epoch_ns = (int64_t)c->command.start.epoch_ns;
        out->u.start.rate_millihz = c->command.start.rate_millihz;
        return MN_CONTROL_ACCEPTED;
    case mocap_v1_Control_stop_tag:
        out->kind = MN_CMD_STOP;
        return MN_CONTROL_ACCEPTED;
    case mocap_v1_Control_set_threshold_tag:
        if (!c->command.set_threshold.automatic &&
            (c->command.set_threshold.value < 1 || c->command.set_threshold.value > 255))
            return reject(reason, "control: threshold outside 1..255");
        out->kind = MN_CMD_THRESHOLD;
        out->u.threshold.automatic = c->command.set_threshold.automatic;
        out->u.threshold.value = (uint8_t)c->command.set_threshold.value;
        return MN_CONTROL_ACCEPTED;
    case mocap_v1_Control_set_exposure_tag:
        if (c->command.set_exposure.exposure_us > 1000000 ||
            c->command.set_exposure.gain_milli > 64000)
            return reject(reason, "control: exposure above 1 s or gain above 64x");
        if (c->command.set_exposure.exposure_us == 0 && c->command.set_exposure.gain_milli == 0)
            return reject(reason, "control: exposure command changes nothing");
        out->kind = MN_CMD_EXPOSURE;
        out->u.exposure.exposure_us = c->command.set_exposure.exposure_us;
        out->u.exposure.gain_milli = c->command.set_exposure.gain_milli;
        return MN_CONTROL_ACCEPTED;
    case mocap_v1_Control_set_picture_tag: {
        /* Ranges and "changes nothing" are checked by the wire's validation. */
        const mocap_v1_SetPicture *p = &c->command.set_picture;
        out->kind = MN_CMD_PICTURE;
        out->u.picture.brightness_pct = p->set_brightness ? (int32_t)p->brightness_pct : -1;
        out->u.picture.contrast_pct = p->set_contrast ? (int32_t)p->contrast_pct : -1;
        return MN_CONTROL_ACCEPTED;
    }
    case mocap_v1_Control_set_mask_tag:
        return set_mask(ctl, &c->command.set_mask, c->sequence, out, reason);
    case mocap_v1_Control_preview_request_tag:
        out->kind = MN_CMD_PREVIEW;
        out->u.preview.thresholded =
            c->command.preview_request.mode == mocap_v1_PreviewMode_PREVIEW_MODE_THRESHOLDED;
        out->u.preview.downscale = c->command.preview_request.downscale;
        return MN_CONTROL_ACCEPTED;
    case mocap_v1_Control_identify_tag:
        if (c->command.identify.duration_ms > 600000)
            return reject(reason, "control: identify longer than 10 minutes");
        out->kind = MN_CMD_IDENTIFY;
        out->u.identify.duration_ms = c->command.identify.duration_ms;
        return MN_CONTROL_ACCEPTED;
    default:
        return reject(reason, "control: no command");
    }
}

enum mn_control_result mn_control_handle(struct mn_control *ctl, const uint8_t *data, size_t len,
                                         bool announce_socket, struct mn_command *out,
                                         const char **reason)
{
    memset(out, 0, sizeof(*out));
    const char *why = NULL;
    if (mn_wire_parse(data, len, &ctl->packet, &why) < 0)
        return reject(reason, why);
    const mocap_v1_Packet *p = &ctl->packet;
    /* A v1 Control for this node is answered even when refused below, so the hub learns why;
     * one that breaks the wire rules is refused before the address check, as it always was. */
    bool control_packet = !announce_socket && p->version == MN_WIRE_VERSION &&
                          p->which_body == mocap_v1_Packet_control_tag;
    bool for_us = control_packet && (p->body.control.node_id == 0 ||
                                     p->body.control.node_id == ctl->node_id);
    if (for_us) {
        out->acknowledge = true;
        out->sequence = p->body.control.sequence;
    }
    why = mn_wire_validate(p);
    if (why != NULL)
        return reject(reason, why);
    if (control_packet && !for_us)
        return MN_CONTROL_IGNORED;
    if (announce_socket) {
        if (p->which_body != mocap_v1_Packet_hub_announce_tag)
            return reject(reason, "announce port: not a HubAnnounce");
        const mocap_v1_HubAnnounce *a = &p->body.hub_announce;
        if (a->epoch_ns > INT64_MAX)
            return reject(reason, "hub announce: epoch out of range");
        if (a->rate_millihz != 0 && (a->rate_millihz < 100 || a->rate_millihz > 1000000))
            return reject(reason, "hub announce: rate outside 0.1..1000 Hz");
        out->kind = MN_CMD_ANNOUNCE;
        out->u.announce.port = (uint16_t)a->port;
        out->u.announce.epoch_ns = (int64_t)a->epoch_ns;
        out->u.announce.rate_millihz = a->rate_millihz;
        return MN_CONTROL_ACCEPTED;
    }
    if (p->which_body != mocap_v1_Packet_control_tag)
        return reject(reason, "control port: not a Control packet");
    return control(ctl, &p->body.control, out, reason);
}
