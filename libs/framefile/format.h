/* On-disk layout constants and little-endian helpers shared by the frame file writer and
 * reader (see README.md for the format). Internal to framefile. */
#ifndef MN_FRAMEFILE_FORMAT_H
#define MN_FRAMEFILE_FORMAT_H

#include <stddef.h>
#include <stdint.h>

#define MN_FF_MAGIC "MOCAPFRM"
#define MN_FF_VERSION 1u
#define MN_FF_HEADER_SIZE 64u
#define MN_FF_RECORD_MAGIC 0x43455246u /* "FREC" little-endian */
#define MN_FF_RECORD_HEAD 12u          /* magic, payload length, payload CRC */
#define MN_FF_PAYLOAD_FIXED 28u        /* frame number, timestamp, tiles, encoding, data len */
#define MN_FF_COUNT_OFFSET 24u         /* frame_count field, patched at close */
#define MN_FF_ENC_RAW 0u
#define MN_FF_ENC_ZLIB 1u

static inline void mn_ff_put16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static inline void mn_ff_put32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static inline void mn_ff_put64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static inline uint16_t mn_ff_get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static inline uint32_t mn_ff_get32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int i = 3; i >= 0; i--)
        v = (v << 8) | p[i];
    return v;
}

static inline uint64_t mn_ff_get64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; i--)
        v = (v << 8) | p[i];
    return v;
}

/* Tile grid of a frame; edge tiles are clipped to the image. */
static inline uint32_t mn_ff_tiles_x(uint32_t w)
{
    return (w + 15) / 16;
}

static inline uint32_t mn_ff_tiles_y(uint32_t h)
{
    return (h + 15) / 16;
}

/* Header bytes for info (frame_count included); out holds MN_FF_HEADER_SIZE bytes. */
struct mn_ff_info;
void mn_ff_encode_header(const struct mn_ff_info *info, uint8_t *out);
/* Parses and checks a header; returns NULL or a static reason. */
const char *mn_ff_decode_header(const uint8_t *in, struct mn_ff_info *info);
/* Largest payload a valid record of this frame size can have. */
size_t mn_ff_max_payload(uint32_t w, uint32_t h);

#endif
