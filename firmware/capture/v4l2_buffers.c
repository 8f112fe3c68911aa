#include "capture/v4l2_buffers.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>

int mn_v4l2_ioctl(int fd, unsigned long req, void *arg)
{
    int rc;
    do {
        rc = ioctl(fd, req, arg);
    } while (rc < 0 && errno == EINTR);
    return rc;
}

struct v4l2_buffer mn_v4l2_mmap_buffer(enum v4l2_buf_type type, uint32_t index)
{
    struct v4l2_buffer buf;
    memset(&buf, 0, sizeof(buf));
    buf.type = type;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = index;
    return buf;
}

int mn_v4l2_map_buffers(int fd, const char *device, enum v4l2_buf_type type, uint32_t count,
                        struct mn_v4l2_map *maps, uint32_t max, uint32_t *n_maps, char *err,
                        size_t errlen)
{
    struct v4l2_requestbuffers req;
    memset(&req, 0, sizeof(req));
    req.count = count;
    req.type = type;
    req.memory = V4L2_MEMORY_MMAP;
    if (mn_v4l2_ioctl(fd, VIDIOC_REQBUFS, &req) < 0) {
        snprintf(err, errlen, "%s: VIDIOC_REQBUFS (mmap streaming): %s", device, strerror(errno));
        return -1;
    }
    if (req.count < 2 || req.count > max) {
        snprintf(err, errlen, "%s: driver granted %u buffers", device, req.count);
        errno = ENOMEM;
        return -1;
    }
    for (uint32_t i = 0; i < req.count; i++) {
        struct v4l2_buffer buf = mn_v4l2_mmap_buffer(type, i);
        if (mn_v4l2_ioctl(fd, VIDIOC_QUERYBUF, &buf) < 0) {
            snprintf(err, errlen, "%s: VIDIOC_QUERYBUF: %s", device, strerror(errno));
            return -1;
        }
        void *p = mmap(NULL, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, buf.m.offset);
        if (p == MAP_FAILED) {
            snprintf(err, errlen, "%s: mmap: %s", device, strerror(errno));
            return -1;
        }
        maps[i].start = p;
        maps[i].length = buf.length;
        *n_maps = i + 1;
    }
    return 0;
}

void mn_v4l2_unmap_buffers(struct mn_v4l2_map *maps, uint32_t *n_maps)
{
    for (uint32_t i = 0; i < *n_maps; i++)
        munmap(maps[i].start, maps[i].length);
    *n_maps = 0;
}
