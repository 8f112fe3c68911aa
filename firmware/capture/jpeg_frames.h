/* Recorded JPEG frames: the *.jpg / *.jpeg files of one directory in name order (what
 * `ffmpeg -i cam.mjpeg DIR/%06d.jpg` or a webcam's saved MJPEG frames give), frame k being the
 * k-th name. Each is read whole (refused above the largest JPEG the frame size allows) and
 * decoded to its luma by the node's MJPEG decoder (mjpeg.h), so the replay source exercises the
 * webcam path without a webcam. The size is the first readable frame's; a frame of another
 * size, cut short or corrupt does not decode and is dropped by the caller. */
#ifndef MN_JPEG_FRAMES_H
#define MN_JPEG_FRAMES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Most files one directory may list (a bound on the name table). */
#define MN_JPEG_FRAMES_MAX 1000000u

struct mn_jpeg_frames;

/* True when dir holds at least one *.jpg or *.jpeg file. */
bool mn_jpeg_frames_present(const char *dir);

/* Lists dir's JPEG files and reads the frame size from the first whose header reads. NULL with
 * errno set and the reason in err (no JPEG file, none readable, too many files, no memory). */
struct mn_jpeg_frames *mn_jpeg_frames_open(const char *dir, uint32_t *width, uint32_t *height,
                                           char *err, size_t errlen);
void mn_jpeg_frames_close(struct mn_jpeg_frames *f);

size_t mn_jpeg_frames_count(const struct mn_jpeg_frames *f);

/* Frame index's luma into dst (width bytes per row). 0; -1 with the reason in err when the file
 * cannot be read or does not decode as a JPEG of the frame size (the frame is to be dropped). */
int mn_jpeg_frames_read(struct mn_jpeg_frames *f, size_t index, uint8_t *dst, char *err,
                        size_t errlen);

#endif
