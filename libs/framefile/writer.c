/* frames.mcf writer: compares each 16x16 tile with the background model (or with a dark
 * level), stores only the tiles that differ, optionally zlib-compressed as one block per
 * frame, and flushes every record so that a crash loses at most the frame being written. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "framefile/format.h"
#include "framefile/framefile.h"

struct mn_ff_writer {
    FILE *f;
    struct mn_ff_info info;
    struct mn_ff_write_options opts;
    struct mn_ff_noise *noise; /* exact mode only */
    uint8_t *model;            /* one frame of the model (exact mode) */
    uint8_t *tiles;            /* stored tiles' pixels, concatenated */
    uint32_t *index;
    uint8_t *payload;
    size_t payload_cap;
    uint64_t bytes;
};

/* mkdir -p: creates each missing component of dir. */
static int make_dirs(const char *dir)
{
    char path[4096];
    size_t len = strlen(dir);
    if (len == 0 || len >= sizeof path) {
        errno = ENAMETOOLONG;
        return -1;
    }
    memcpy(path, dir, len + 1);
    for (size_t i = 1; i <= len; i++) {
        if (path[i] != '/' && path[i] != '\0')
            continue;
        char saved = path[i];
        path[i] = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST)
            return -1;
        path[i] = saved;
    }
    struct stat st;
    if (stat(dir, &st) != 0)
        return -1;
    if (!S_ISDIR(st.st_mode)) {
        errno = ENOTDIR;
        return -1;
    }
    return 0;
}

static void writer_free(struct mn_ff_writer *wr)
{
    free(wr->payload);
    free(wr->index);
    free(wr->tiles);
    free(wr->model);
    mn_ff_noise_free(wr->noise);
    free(wr);
}

struct mn_ff_writer *mn_ff_writer_open(const char *dir, const struct mn_ff_info *info,
                                       const struct mn_ff_write_options *opts)
{
    if (!dir || !info || !opts || info->width < 1 || info->height < 1 ||
        info->width > MN_FF_MAX_SIDE || info->height > MN_FF_MAX_SIDE ||
        info->noise_sigma_q8 > 64u * 256u || opts->zlib_level < 0 || opts->zlib_level > 9 ||
        opts->dark_level < -1 || opts->dark_level > 255) {
        errno = EINVAL;
        return NULL;
    }
    if (make_dirs(dir) != 0)
        return NULL;
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, MN_FF_FILE_NAME) >= (int)sizeof path) {
        errno = ENAMETOOLONG;
        return NULL;
    }

    struct mn_ff_writer *wr = calloc(1, sizeof *wr);
    if (!wr)
        return NULL;
    wr->info = *info;
    wr->info.frame_count = 0;
    wr->opts = *opts;
    size_t pixels = (size_t)info->width * info->height;
    size_t tiles = (size_t)mn_ff_tiles_x(info->width) * mn_ff_tiles_y(info->height);
    wr->payload_cap = mn_ff_max_payload(info->width, info->height);
    wr->tiles = malloc(pixels);
    wr->index = malloc(tiles * sizeof *wr->index);
    wr->payload = malloc(wr->payload_cap);
    if (!wr->tiles || !wr->index || !wr->payload)
        goto fail;
    if (opts->dark_level < 0) {
        wr->noise = mn_ff_noise_new(info->width, info->background, info->noise_sigma_q8,
                                    info->noise_seed);
        wr->model = malloc(pixels);
        if (!wr->noise || !wr->model)
            goto fail;
    }
    wr->f = fopen(path, "wb");
    if (!wr->f)
        goto fail;
    uint8_t head[MN_FF_HEADER_SIZE];
    mn_ff_encode_header(&wr->info, head);
    if (fwrite(head, 1, sizeof head, wr->f) != sizeof head || fflush(wr->f) != 0) {
        int e = errno;
        fclose(wr->f);
        errno = e;
        goto fail;
    }
    wr->bytes = sizeof head;
    return wr;

fail:
    if (errno == 0)
        errno = ENOMEM;
    writer_free(wr);
    return NULL;
}

/* True when the tile must be stored. */
static int tile_has_content(const struct mn_ff_writer *wr, const uint8_t *px, size_t stride,
                            uint32_t x0, uint32_t y0, uint32_t tw, uint32_t th)
{
    const uint32_t w = wr->info.width;
    for (uint32_t r = 0; r < th; r++) {
        const uint8_t *row = px + (size_t)(y0 + r) * stride + x0;
        if (wr->opts.dark_level < 0) {
            if (memcmp(row, wr->model + (size_t)(y0 + r) * w + x0, tw) != 0)
                return 1;
        } else {
            for (uint32_t i = 0; i < tw; i++)
                if (row[i] > wr->opts.dark_level)
                    return 1;
        }
    }
    return 0;
}

int mn_ff_writer_add(struct mn_ff_writer *wr, uint64_t frame_number, uint64_t timestamp_ns,
                     const uint8_t *pixels, size_t stride)
{
    if (!wr || !pixels || stride < wr->info.width) {
        errno = EINVAL;
        return -1;
    }
    const uint32_t w = wr->info.width, h = wr->info.height;
    if (wr->noise)
        mn_ff_noise_fill(wr->noise, frame_number, 0, 0, w, h, wr->model, w);

    uint32_t n = 0;
    size_t raw = 0;
    for (uint32_t ty = 0; ty < mn_ff_tiles_y(h); ty++) {
        uint32_t y0 = ty * MN_FF_TILE, th = h - y0 < MN_FF_TILE ? h - y0 : MN_FF_TILE;
        for (uint32_t tx = 0; tx < mn_ff_tiles_x(w); tx++) {
            uint32_t x0 = tx * MN_FF_TILE, tw = w - x0 < MN_FF_TILE ? w - x0 : MN_FF_TILE;
            if (!tile_has_content(wr, pixels, stride, x0, y0, tw, th))
                continue;
            wr->index[n++] = ty * mn_ff_tiles_x(w) + tx;
            for (uint32_t r = 0; r < th; r++) {
                memcpy(wr->tiles + raw, pixels + (size_t)(y0 + r) * stride + x0, tw);
                raw += tw;
            }
        }
    }

    uint8_t *p = wr->payload;
    uint8_t *data = p + MN_FF_PAYLOAD_FIXED + 4u * n;
    size_t data_len = raw;
    uint8_t enc = MN_FF_ENC_RAW;
    if (wr->opts.zlib_level > 0 && raw > 0) {
        uLongf out_len = (uLongf)(wr->payload_cap - (size_t)(data - p));
        if (compress2(data, &out_len, wr->tiles, (uLong)raw, wr->opts.zlib_level) == Z_OK &&
            out_len < raw) {
            enc = MN_FF_ENC_ZLIB;
            data_len = out_len;
        }
    }
    if (enc == MN_FF_ENC_RAW)
        memcpy(data, wr->tiles, raw);

    mn_ff_put64(p, frame_number);
    mn_ff_put64(p + 8, timestamp_ns);
    mn_ff_put32(p + 16, n);
    p[20] = enc;
    p[21] = p[22] = p[23] = 0;
    mn_ff_put32(p + 24, (uint32_t)data_len);
    for (uint32_t i = 0; i < n; i++)
        mn_ff_put32(p + MN_FF_PAYLOAD_FIXED + 4u * i, wr->index[i]);
    size_t len = MN_FF_PAYLOAD_FIXED + 4u * n + data_len;

    uint8_t head[MN_FF_RECORD_HEAD];
    mn_ff_put32(head, MN_FF_RECORD_MAGIC);
    mn_ff_put32(head + 4, (uint32_t)len);
    mn_ff_put32(head + 8, (uint32_t)crc32(0L, p, (uInt)len));
    if (fwrite(head, 1, sizeof head, wr->f) != sizeof head || fwrite(p, 1, len, wr->f) != len ||
        fflush(wr->f) != 0)
        return -1;
    wr->bytes += sizeof head + len;
    wr->info.frame_count++;
    return 0;
}

uint64_t mn_ff_writer_bytes(const struct mn_ff_writer *wr)
{
    return wr->bytes;
}

int mn_ff_writer_close(struct mn_ff_writer *wr)
{
    if (!wr) {
        errno = EINVAL;
        return -1;
    }
    uint8_t head[MN_FF_HEADER_SIZE];
    mn_ff_encode_header(&wr->info, head);
    int rc = 0;
    if (fseek(wr->f, 0, SEEK_SET) != 0 || fwrite(head, 1, sizeof head, wr->f) != sizeof head)
        rc = -1;
    int e = errno;
    if (fclose(wr->f) != 0 && rc == 0) {
        rc = -1;
        e = errno;
    }
    writer_free(wr);
    errno = e;
    return rc;
}
