/* Recorded Y8 frames of one camera in DIR/frames.mcf (format in framefile/README.md): frames
 * are mostly dark, so only 16x16 tiles with content are stored and the rest is rebuilt from a
 * seeded background-and-noise model. Written by `mocap-hub sim render`, read by the node's
 * replay source and the detection benchmark.
 *
 * Error rule: int functions return 0 (or a count) on success and -1 with errno set on failure;
 * pointer functions return NULL with errno set. Libraries never print: the reader keeps a
 * message for the caller to log (mn_ff_reader_message).
 */
#ifndef MN_FRAMEFILE_FRAMEFILE_H
#define MN_FRAMEFILE_FRAMEFILE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MN_FF_FILE_NAME "frames.mcf"
#define MN_FF_TILE 16
#define MN_FF_MAX_SIDE 16384u

/* Stream description, stored in the file header. */
struct mn_ff_info {
    uint32_t width, height;
    uint32_t rate_mhz;       /* frame rate in millihertz (120 Hz = 120000), 0 if unknown */
    uint32_t frame_count;    /* frames in the file; the writer fills it in at close */
    uint8_t background;      /* background level of tiles that are not stored */
    uint32_t noise_sigma_q8; /* their noise sigma in 1/256 grey levels (0: flat background) */
    uint64_t noise_seed;
};

/* Per-frame metadata. */
struct mn_ff_frame {
    uint64_t frame_number; /* the frame's global (trigger) number */
    uint64_t timestamp_ns; /* capture time */
    uint32_t stored_tiles; /* tiles held in the file; the others came from the model */
};

/* The background model: bg + noise for every pixel, deterministic in (seed, frame, x, y) and
 * bit-identical on every platform (integer arithmetic only). Rows are slices of one noise
 * table at hashed offsets, so filling a frame costs a copy. */
struct mn_ff_noise;

/* For frames up to max_w wide. Caller frees with mn_ff_noise_free. */
struct mn_ff_noise *mn_ff_noise_new(uint32_t max_w, uint8_t background, uint32_t sigma_q8,
                                    uint64_t seed);
void mn_ff_noise_free(struct mn_ff_noise *noise);
/* Writes the model's pixels of rows [y0, y0 + rows) and columns [x0, x0 + w) of frame
 * frame_number into dst (stride bytes per row). x0 + w must not exceed max_w. */
void mn_ff_noise_fill(const struct mn_ff_noise *noise, uint64_t frame_number, uint32_t x0,
                      uint32_t y0, uint32_t w, uint32_t rows, uint8_t *dst, size_t stride);

/* ---- writer ---- */
struct mn_ff_writer;

struct mn_ff_write_options {
    int zlib_level; /* 0: store tiles raw; 1..9: zlib level for each frame's tile block */
    int dark_level; /* -1: store tiles that differ from the model in any pixel (lossless, for
                     * simulated frames); 0..255: store tiles with a pixel above this level
                     * (real recordings: set noise_sigma_q8 to 0) */
};

/* Creates dir (and parents) if needed and starts dir/frames.mcf, replacing an older one.
 * info->frame_count is ignored. Caller closes with mn_ff_writer_close. */
struct mn_ff_writer *mn_ff_writer_open(const char *dir, const struct mn_ff_info *info,
                                       const struct mn_ff_write_options *opts);
/* Appends one frame of info's size. */
int mn_ff_writer_add(struct mn_ff_writer *wr, uint64_t frame_number, uint64_t timestamp_ns,
                     const uint8_t *pixels, size_t stride);
/* Bytes written so far (header included). */
uint64_t mn_ff_writer_bytes(const struct mn_ff_writer *wr);
/* Writes the frame count, flushes and closes; frees wr even on failure. */
int mn_ff_writer_close(struct mn_ff_writer *wr);

/* ---- reader ---- */
struct mn_ff_reader;

/* Opens a camera directory holding frames.mcf, or the file itself. Validates the header and
 * allocates every buffer needed, so reading frames never allocates. Caller closes with
 * mn_ff_reader_close. On failure, *why (if given) points at a static reason. */
struct mn_ff_reader *mn_ff_reader_open(const char *path, const char **why);
/* The same over a byte buffer (tests, fuzzing); data must outlive the reader. */
struct mn_ff_reader *mn_ff_reader_open_mem(const void *data, size_t size, const char **why);
const struct mn_ff_info *mn_ff_reader_info(const struct mn_ff_reader *rd);
/* Reads the next frame into pixels (info.width x info.height, stride bytes per row).
 * Returns 1 with a frame, 0 at the end of the good data. A damaged or truncated tail also
 * ends the stream (0) with mn_ff_reader_damaged() true and a message, so a recording cut off
 * by a crash replays up to its last whole frame. -1 (errno) only for I/O errors or bad args. */
int mn_ff_reader_next(struct mn_ff_reader *rd, uint8_t *pixels, size_t stride,
                      struct mn_ff_frame *frame);
/* Goes back to the first frame (looped replay). */
int mn_ff_reader_rewind(struct mn_ff_reader *rd);
int mn_ff_reader_damaged(const struct mn_ff_reader *rd);
/* Why the stream ended early, or "" when it did not. */
const char *mn_ff_reader_message(const struct mn_ff_reader *rd);
void mn_ff_reader_close(struct mn_ff_reader *rd);

#ifdef __cplusplus
}
#endif

#endif
