/* frames.mcf reader: validates every length, index and CRC before use, rebuilds unstored
 * tiles from the background model, and ends the stream cleanly (with a message) at the first
 * damaged or truncated record. All buffers are allocated at open. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "framefile/format.h"
#include "framefile/framefile.h"

struct mn_ff_reader {
    FILE *f;
    struct mn_ff_info info;
    struct mn_ff_noise *noise;
    uint8_t *payload;
    size_t payload_cap;
    uint8_t *tiles; /* inflated tile pixels */
    z_stream zs;
    int zs_ready;
    uint32_t frames_read;
    int ended;
    int damaged;
    char message[160];
};

static void reader_free(struct mn_ff_reader *rd)
{
    if (rd->zs_ready)
        inflateEnd(&rd->zs);
    if (rd->f)
        fclose(rd->f);
    free(rd->tiles);
    free(rd->payload);
    mn_ff_noise_free(rd->noise);
    free(rd);
}

static int inflate_tiles(struct mn_ff_reader *rd, const uint8_t *data, size_t len, size_t want)
{
    if (inflateReset(&rd->zs) != Z_OK)
        return -1;
    rd->zs.next_in = (Bytef *)data;
    rd->zs.avail_in = (uInt)len;
    rd->zs.next_out = rd->tiles;
    rd->zs.avail_out = (uInt)want;
    int rc = inflate(&rd->zs, Z_FINISH);
    if (rc != Z_STREAM_END || rd->zs.total_out != want || rd->zs.avail_in != 0)
        return -1;
    return 0;
}

/* Takes ownership of f (closed on failure). */
static struct mn_ff_reader *reader_from_file(FILE *f, const char **why)
{
    uint8_t head[MN_FF_HEADER_SIZE];
    struct mn_ff_info info;
    if (fread(head, 1, sizeof head, f) != sizeof head) {
        *why = "file shorter than the frames.mcf header";
        fclose(f);
        errno = EINVAL;
        return NULL;
    }
    const char *bad = mn_ff_decode_header(head, &info);
    if (bad) {
        *why = bad;
        fclose(f);
        errno = EINVAL;
        return NULL;
    }
    struct mn_ff_reader *rd = calloc(1, sizeof *rd);
    if (!rd) {
        fclose(f);
        *why = "out of memory";
        return NULL;
    }
    rd->f = f;
    rd->info = info;
    rd->payload_cap = mn_ff_max_payload(info.width, info.height);
    rd->payload = malloc(rd->payload_cap);
    rd->tiles = malloc((size_t)info.width * info.height);
    rd->noise = mn_ff_noise_new(info.width, info.background, info.noise_sigma_q8,
                                info.noise_seed);
    if (!rd->payload || !rd->tiles || !rd->noise || inflateInit(&rd->zs) != Z_OK) {
        *why = "out of memory";
        reader_free(rd);
        errno = ENOMEM;
        return NULL;
    }
    rd->zs_ready = 1;
    /* zlib allocates its window on the first inflate that produces output; do that here with
     * a one-byte stream so that reading frames never allocates. */
    static const uint8_t one_zero_byte[] = {0x78, 0x9c, 0x63, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01};
    if (inflate_tiles(rd, one_zero_byte, sizeof one_zero_byte, 1) != 0) {
        *why = "zlib self-check failed";
        reader_free(rd);
        errno = EIO;
        return NULL;
    }
    return rd;
}

struct mn_ff_reader *mn_ff_reader_open(const char *path, const char **why)
{
    const char *dummy;
    if (!why)
        why = &dummy;
    *why = "";
    if (!path) {
        *why = "no path given";
        errno = EINVAL;
        return NULL;
    }
    char file[4096];
    struct stat st;
    if (stat(path, &st) != 0) {
        *why = "no such file or directory";
        return NULL;
    }
    if (S_ISDIR(st.st_mode)) {
        if (snprintf(file, sizeof file, "%s/%s", path, MN_FF_FILE_NAME) >= (int)sizeof file) {
            *why = "path too long";
            errno = ENAMETOOLONG;
            return NULL;
        }
    } else if (snprintf(file, sizeof file, "%s", path) >= (int)sizeof file) {
        *why = "path too long";
        errno = ENAMETOOLONG;
        return NULL;
    }
    FILE *f = fopen(file, "rb");
    if (!f) {
        *why = S_ISDIR(st.st_mode) ? "directory holds no readable frames.mcf"
                                   : "cannot open file";
        return NULL;
    }
    return reader_from_file(f, why);
}

struct mn_ff_reader *mn_ff_reader_open_mem(const void *data, size_t size, const char **why)
{
    const char *dummy;
    if (!why)
        why = &dummy;
    *why = "";
    if (!data || size < MN_FF_HEADER_SIZE) {
        *why = "buffer shorter than the frames.mcf header";
        errno = EINVAL;
        return NULL;
    }
    FILE *f = fmemopen((void *)data, size, "rb");
    if (!f) {
        *why = "cannot open memory stream";
        return NULL;
    }
    return reader_from_file(f, why);
}

const struct mn_ff_info *mn_ff_reader_info(const struct mn_ff_reader *rd)
{
    return &rd->info;
}

int mn_ff_reader_damaged(const struct mn_ff_reader *rd)
{
    return rd->damaged;
}

const char *mn_ff_reader_message(const struct mn_ff_reader *rd)
{
    return rd->message;
}

static int stop_damaged(struct mn_ff_reader *rd, const char *what)
{
    rd->ended = 1;
    rd->damaged = 1;
    snprintf(rd->message, sizeof rd->message, "%s after frame %u of frames.mcf; stopping there",
             what, rd->frames_read);
    return 0;
}

/* Size of tile i of the grid, clipped to the image. */
static size_t tile_bytes(const struct mn_ff_info *info, uint32_t i)
{
    uint32_t tx = i % mn_ff_tiles_x(info->width), ty = i / mn_ff_tiles_x(info->width);
    uint32_t x0 = tx * MN_FF_TILE, y0 = ty * MN_FF_TILE;
    uint32_t tw = info->width - x0 < MN_FF_TILE ? info->width - x0 : MN_FF_TILE;
    uint32_t th = info->height - y0 < MN_FF_TILE ? info->height - y0 : MN_FF_TILE;
    return (size_t)tw * th;
}

int mn_ff_reader_next(struct mn_ff_reader *rd, uint8_t *pixels, size_t stride,
                      struct mn_ff_frame *frame)
{
    if (!rd || !pixels || stride < rd->info.width) {
        errno = EINVAL;
        return -1;
    }
    if (rd->ended)
        return 0;
    uint8_t head[MN_FF_RECORD_HEAD];
    size_t got = fread(head, 1, sizeof head, rd->f);
    if (got == 0 && feof(rd->f)) {
        rd->ended = 1;
        if (rd->info.frame_count != 0 && rd->frames_read != rd->info.frame_count)
            return stop_damaged(rd, "file ends early (header promises more frames)");
        return 0;
    }
    if (ferror(rd->f)) {
        errno = EIO;
        return -1;
    }
    if (got != sizeof head)
        return stop_damaged(rd, "truncated record header");
    if (mn_ff_get32(head) != MN_FF_RECORD_MAGIC)
        return stop_damaged(rd, "bad record magic");
    size_t len = mn_ff_get32(head + 4);
    if (len < MN_FF_PAYLOAD_FIXED || len > rd->payload_cap)
        return stop_damaged(rd, "record length out of range");
    if (fread(rd->payload, 1, len, rd->f) != len) {
        if (ferror(rd->f)) {
            errno = EIO;
            return -1;
        }
        return stop_damaged(rd, "truncated record");
    }
    const uint8_t *p = rd->payload;
    if (mn_ff_get32(head + 8) != (uint32_t)crc32(0L, p, (uInt)len))
        return stop_damaged(rd, "record CRC mismatch");

    const struct mn_ff_info *info = &rd->info;
    uint32_t total = mn_ff_tiles_x(info->width) * mn_ff_tiles_y(info->height);
    uint32_t n = mn_ff_get32(p + 16);
    uint8_t enc = p[20];
    size_t data_len = mn_ff_get32(p + 24);
    if (n > total || (enc != MN_FF_ENC_RAW && enc != MN_FF_ENC_ZLIB) ||
        MN_FF_PAYLOAD_FIXED + 4u * (size_t)n + data_len != len)
        return stop_damaged(rd, "inconsistent record fields");
    size_t want = 0;
    uint32_t prev = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t t = mn_ff_get32(p + MN_FF_PAYLOAD_FIXED + 4u * i);
        if (t >= total || (i > 0 && t <= prev))
            return stop_damaged(rd, "bad tile index");
        prev = t;
        want += tile_bytes(info, t);
    }
    const uint8_t *data = p + MN_FF_PAYLOAD_FIXED + 4u * n;
    const uint8_t *src = data;
    if (enc == MN_FF_ENC_RAW) {
        if (data_len != want)
            return stop_damaged(rd, "raw tile data of the wrong size");
    } else {
        if (want == 0 || inflate_tiles(rd, data, data_len, want) != 0)
            return stop_damaged(rd, "corrupt compressed tile data");
        src = rd->tiles;
    }

    uint64_t number = mn_ff_get64(p);
    mn_ff_noise_fill(rd->noise, number, 0, 0, info->width, info->height, pixels, stride);
    uint32_t tiles_x = mn_ff_tiles_x(info->width);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t t = mn_ff_get32(p + MN_FF_PAYLOAD_FIXED + 4u * i);
        uint32_t x0 = (t % tiles_x) * MN_FF_TILE, y0 = (t / tiles_x) * MN_FF_TILE;
        uint32_t tw = info->width - x0 < MN_FF_TILE ? info->width - x0 : MN_FF_TILE;
        uint32_t th = info->height - y0 < MN_FF_TILE ? info->height - y0 : MN_FF_TILE;
        for (uint32_t r = 0; r < th; r++) {
            memcpy(pixels + (size_t)(y0 + r) * stride + x0, src, tw);
            src += tw;
        }
    }
    if (frame) {
        frame->frame_number = number;
        frame->timestamp_ns = mn_ff_get64(p + 8);
        frame->stored_tiles = n;
    }
    rd->frames_read++;
    return 1;
}

int mn_ff_reader_rewind(struct mn_ff_reader *rd)
{
    if (!rd) {
        errno = EINVAL;
        return -1;
    }
    if (fseek(rd->f, MN_FF_HEADER_SIZE, SEEK_SET) != 0)
        return -1;
    clearerr(rd->f);
    rd->frames_read = 0;
    rd->ended = 0;
    rd->damaged = 0;
    rd->message[0] = '\0';
    return 0;
}

void mn_ff_reader_close(struct mn_ff_reader *rd)
{
    if (rd)
        reader_free(rd);
}
