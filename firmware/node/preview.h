/* Preview images for remote threshold tuning (the seed's tuning window, done by the hub): a
 * frame downscaled by 1, 2, 4 or 8 (box average), raw or thresholded, cut into PreviewChunk
 * datagrams. Pure functions over caller-owned buffers. */
#ifndef MN_NODE_PREVIEW_H
#define MN_NODE_PREVIEW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wire/wire.h"

/* Bytes of image data per PreviewChunk (the wire allows 1200; this leaves room for headers). */
#define MN_PREVIEW_CHUNK_BYTES 1152u

/* Renders w x h (stride) into out (capacity cap), downscaled; thresholded: 255 where the block
 * mean is above threshold, 0 elsewhere. Sets *out_w, *out_h. 0, or -1/EINVAL when out is too
 * small or downscale is not 1, 2, 4 or 8. */
int mn_preview_render(const uint8_t *pixels, uint32_t w, uint32_t h, size_t stride,
                      uint32_t downscale, bool thresholded, uint8_t threshold, uint8_t *out,
                      size_t cap, uint32_t *out_w, uint32_t *out_h);

uint32_t mn_preview_chunk_count(uint32_t w, uint32_t h);

/* Fills packet with chunk `index` of the image. */
void mn_preview_chunk(const uint8_t *image, uint32_t w, uint32_t h, bool thresholded,
                      uint32_t node_id, uint64_t frame_number, uint32_t index,
                      mocap_v1_Packet *packet);

#endif
