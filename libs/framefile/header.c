/* frames.mcf header: fixed 64 bytes, little-endian, CRC-protected; every field is range
 * checked on read because the file is outside input. */
#include <string.h>
#include <zlib.h>

#include "framefile/format.h"
#include "framefile/framefile.h"

void mn_ff_encode_header(const struct mn_ff_info *info, uint8_t *out)
{
    memset(out, 0, MN_FF_HEADER_SIZE);
    memcpy(out, MN_FF_MAGIC, 8);
    mn_ff_put16(out + 8, MN_FF_VERSION);
    mn_ff_put16(out + 10, MN_FF_HEADER_SIZE);
    mn_ff_put32(out + 12, info->width);
    mn_ff_put32(out + 16, info->height);
    mn_ff_put32(out + 20, info->rate_mhz);
    mn_ff_put32(out + MN_FF_COUNT_OFFSET, info->frame_count);
    out[28] = info->background;
    out[29] = MN_FF_TILE;
    mn_ff_put32(out + 32, info->noise_sigma_q8);
    mn_ff_put64(out + 40, info->noise_seed);
    mn_ff_put32(out + 60, (uint32_t)crc32(0L, out, 60));
}

const char *mn_ff_decode_header(const uint8_t *in, struct mn_ff_info *info)
{
    if (memcmp(in, MN_FF_MAGIC, 8) != 0)
        return "not a frames.mcf file (bad magic)";
    if (mn_ff_get16(in + 8) != MN_FF_VERSION)
        return "unsupported frames.mcf version";
    if (mn_ff_get16(in + 10) != MN_FF_HEADER_SIZE)
        return "unexpected frames.mcf header size";
    if (mn_ff_get32(in + 60) != (uint32_t)crc32(0L, in, 60))
        return "frames.mcf header CRC mismatch";
    if (in[29] != MN_FF_TILE)
        return "unsupported tile size";
    memset(info, 0, sizeof *info);
    info->width = mn_ff_get32(in + 12);
    info->height = mn_ff_get32(in + 16);
    info->rate_mhz = mn_ff_get32(in + 20);
    info->frame_count = mn_ff_get32(in + MN_FF_COUNT_OFFSET);
    info->background = in[28];
    info->noise_sigma_q8 = mn_ff_get32(in + 32);
    info->noise_seed = mn_ff_get64(in + 40);
    if (info->width < 1 || info->height < 1 || info->width > MN_FF_MAX_SIDE ||
        info->height > MN_FF_MAX_SIDE)
        return "frame size out of range (1..16384)";
    if (info->noise_sigma_q8 > 64u * 256u)
        return "noise sigma out of range (0..64 grey levels)";
    return NULL;
}

size_t mn_ff_max_payload(uint32_t w, uint32_t h)
{
    size_t pixels = (size_t)w * h;
    size_t tiles = (size_t)mn_ff_tiles_x(w) * mn_ff_tiles_y(h);
    size_t bound = compressBound((uLong)pixels);
    return MN_FF_PAYLOAD_FIXED + 4 * tiles + (bound > pixels ? bound : pixels);
}
