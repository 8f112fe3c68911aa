/* The V4L2 calls that both ends of a video device make: mocap-node's capture backend
 * (capture_v4l2.c) on a capture device and the vivid test's feeder (tests/vivid/vivid_tool.c) on
 * an output device. ioctls retried on EINTR, and mmap streaming buffers requested, queried and
 * mapped. V4L2 uAPI types stay in the files that include this. */
#ifndef MN_V4L2_BUFFERS_H
#define MN_V4L2_BUFFERS_H

#include <linux/videodev2.h>
#include <stddef.h>
#include <stdint.h>

/* ioctl, again while a signal interrupts it. */
int mn_v4l2_ioctl(int fd, unsigned long req, void *arg);

/* A zeroed mmap buffer of `type` with index set, as QUERYBUF, QBUF and DQBUF take it. */
struct v4l2_buffer mn_v4l2_mmap_buffer(enum v4l2_buf_type type, uint32_t index);

struct mn_v4l2_map {
    void *start;
    size_t length;
};

/* Asks the driver for `count` mmap buffers of `type` and maps each into maps[i], keeping
 * *n_maps the number mapped so far (so the caller can unmap after a failure). The driver must
 * grant from 2 to max. 0, or -1 with errno set and the reason, naming `device`, in err. */
int mn_v4l2_map_buffers(int fd, const char *device, enum v4l2_buf_type type, uint32_t count,
                        struct mn_v4l2_map *maps, uint32_t max, uint32_t *n_maps, char *err,
                        size_t errlen);

/* Unmaps maps[0..*n_maps) and sets *n_maps to 0; the driver's buffers stay allocated (freed by
 * REQBUFS with count 0 or by closing the device). */
void mn_v4l2_unmap_buffers(struct mn_v4l2_map *maps, uint32_t *n_maps);

#endif
