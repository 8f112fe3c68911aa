/* Preview rendering and chunking (see preview.h). */
#include "node/preview.h"

#include <errno.h>
#include <string.h>

int mn_preview_render(const uint8_t *pixels, uint32_t w, uint32_t h, size_t stride,
                      uint32_t downscale, bool thresholded, uint8_t threshold, uint8_t *out,
                      size_t cap, uint32_t *out_w, uint32_t *out_h)
{
    if (downscale != 1 && downscale != 2 && downscale != 4 && downscale != 8) {
        errno = EINVAL;
        return -1;
    }
    uint32_t ow = w / downscale, oh = h / downscale;
    if (ow == 0 || oh == 0 || (size_t)ow * oh > cap) {
        errno = EINVAL;
        return -1;
    }
    uint32_t area = downscale * downscale;
    for (uint32_t oy = 0; oy < oh; oy++) {
        for (uint32_t ox = 0; ox < ow; ox++) {
            uint32_t sum = 0;
            for (uint32_t dy = 0; dy < downscale; dy++) {
                const uint8_t *row = pixels + (size_t)(oy * downscale + dy) * stride + ox * downscale;
                for (uint32_t dx = 0; dx < downscale; dx++)
                    sum += row[dx];
            }
            uint8_t v = (uint8_t)((sum + area / 2) / area);
            /* Same rule as the detector: foreground is strictly above the threshold. */
            out[(size_t)oy * ow + ox] = thresholded ? (v > threshold ? 255 : 0) : v;
        }
    }
    *out_w = ow;
    *out_h = oh;
    return 0;
}

uint32_t mn_preview_chunk_count(uint32_t w, uint32_t h)
{
    size_t total = (size_t)w * h;
    return (uint32_t)((total + MN_PREVIEW_CHUNK_BYTES - 1) / MN_PREVIEW_CHUNK_BYTES);
}

void mn_preview_chunk(const uint8_t *image, uint32_t w, uint32_t h, bool thresholded,
                      uint32_t node_id, uint64_t frame_number, uint32_t index,
                      mocap_v1_Packet *packet)
{
    *packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
    packet->version = MN_WIRE_VERSION;
    packet->which_body = mocap_v1_Packet_preview_chunk_tag;
    mocap_v1_PreviewChunk *c = &packet->body.preview_chunk;
    size_t total = (size_t)w * h;
    size_t offset = (size_t)index * MN_PREVIEW_CHUNK_BYTES;
    size_t n = total - offset < MN_PREVIEW_CHUNK_BYTES ? total - offset : MN_PREVIEW_CHUNK_BYTES;
    c->node_id = node_id;
    c->frame_number = frame_number;
    c->mode = thresholded ? mocap_v1_PreviewMode_PREVIEW_MODE_THRESHOLDED
                          : mocap_v1_PreviewMode_PREVIEW_MODE_RAW;
    c->width = w;
    c->height = h;
    c->chunk_index = index;
    c->chunk_count = mn_preview_chunk_count(w, h);
    c->offset = (uint32_t)offset;
    c->data.size = (pb_size_t)n;
    memcpy(c->data.bytes, image + offset, n);
}
