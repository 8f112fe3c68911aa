/* Recorded JPEG frames (see jpeg_frames.h). The names are listed once at open; one buffer of
 * the largest JPEG the frame size allows is allocated then, so a run allocates nothing more. */
#include "capture/jpeg_frames.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "capture/mjpeg.h"

struct mn_jpeg_frames {
    char dir[4096];
    struct dirent **names;
    size_t count;
    uint32_t width, height;
    struct mn_mjpeg *decoder;
    uint8_t *data;     /* one file's bytes */
    size_t data_size;  /* its capacity: the largest JPEG of width x height */
};

static int is_jpeg_name(const struct dirent *e)
{
    const char *dot = strrchr(e->d_name, '.');
    if (dot == NULL || dot == e->d_name)
        return 0;
    return strcasecmp(dot, ".jpg") == 0 || strcasecmp(dot, ".jpeg") == 0;
}

static void free_names(struct dirent **names, size_t count)
{
    for (size_t i = 0; i < count; i++)
        free(names[i]);
    free(names);
}

bool mn_jpeg_frames_present(const char *dir)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return false;
    bool found = false;
    const struct dirent *e;
    while (!found && (e = readdir(d)) != NULL)
        found = is_jpeg_name(e);
    closedir(d);
    return found;
}

/* Reads file index into f->data: the whole file, refused when larger than limit, or with
 * head_only its first limit bytes. The bytes read, or -1 with the reason. */
static ssize_t read_file(struct mn_jpeg_frames *f, size_t index, size_t limit, bool head_only,
                         char *err, size_t errlen)
{
    char path[4096 + 256 + 2];
    snprintf(path, sizeof(path), "%s/%s", f->dir, f->names[index]->d_name);
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st) < 0 || !S_ISREG(st.st_mode)) {
        snprintf(err, errlen, "%s: not a regular file", path);
        close(fd);
        return -1;
    }
    if (!head_only && (uint64_t)st.st_size > limit) {
        snprintf(err, errlen, "%s: %lld bytes, more than a JPEG frame can take (%zu)", path,
                 (long long)st.st_size, limit);
        close(fd);
        return -1;
    }
    size_t got = 0;
    while (got < limit) {
        ssize_t n = read(fd, f->data + got, limit - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            snprintf(err, errlen, "%s: %s", path, strerror(errno));
            close(fd);
            return -1;
        }
        if (n == 0)
            break;
        got += (size_t)n;
    }
    close(fd);
    return (ssize_t)got;
}

struct mn_jpeg_frames *mn_jpeg_frames_open(const char *dir, uint32_t *width, uint32_t *height,
                                           char *err, size_t errlen)
{
    struct mn_jpeg_frames *f = calloc(1, sizeof(*f));
    if (f == NULL) {
        snprintf(err, errlen, "out of memory");
        errno = ENOMEM;
        return NULL;
    }
    snprintf(f->dir, sizeof(f->dir), "%s", dir);
    int e = 0;
    int n = scandir(dir, &f->names, is_jpeg_name, alphasort);
    if (n < 0) {
        e = errno;
        snprintf(err, errlen, "%s: %s", dir, strerror(e));
        goto fail;
    }
    f->count = (size_t)n;
    if (f->count == 0) {
        e = ENOENT;
        snprintf(err, errlen, "%s: no *.jpg or *.jpeg file", dir);
        goto fail;
    }
    if (f->count > MN_JPEG_FRAMES_MAX) {
        e = EFBIG;
        snprintf(err, errlen, "%s: %zu JPEG files, more than %u", dir, f->count,
                 MN_JPEG_FRAMES_MAX);
        goto fail;
    }
    if ((f->decoder = mn_mjpeg_new()) == NULL) {
        e = ENOMEM;
        snprintf(err, errlen, "cannot make a JPEG decoder");
        goto fail;
    }
    /* The size: the first file whose header reads (a header fits in 64 KiB). */
    f->data_size = 64 * 1024;
    if ((f->data = malloc(f->data_size)) == NULL) {
        e = ENOMEM;
        snprintf(err, errlen, "out of memory");
        goto fail;
    }
    const char *why = "no file could be read";
    for (size_t i = 0; i < f->count && f->width == 0; i++) {
        char file_err[256];
        ssize_t got = read_file(f, i, f->data_size, true, file_err, sizeof(file_err));
        if (got <= 0)
            continue;
        uint32_t w, h;
        if (mn_mjpeg_size(f->decoder, f->data, (size_t)got, &w, &h, &why) == 0) {
            f->width = w;
            f->height = h;
        }
    }
    if (f->width == 0) {
        e = EINVAL;
        snprintf(err, errlen, "%s: no JPEG file whose header reads (last: %s)", dir, why);
        goto fail;
    }
    size_t bound = mn_mjpeg_max_bytes(f->width, f->height);
    uint8_t *bigger = bound == 0 ? NULL : realloc(f->data, bound);
    if (bigger == NULL) {
        e = ENOMEM;
        snprintf(err, errlen, "%s: no memory for a %ux%u JPEG frame", dir, f->width, f->height);
        goto fail;
    }
    f->data = bigger;
    f->data_size = bound;
    *width = f->width;
    *height = f->height;
    return f;

fail:
    mn_jpeg_frames_close(f);
    errno = e;
    return NULL;
}

void mn_jpeg_frames_close(struct mn_jpeg_frames *f)
{
    if (f == NULL)
        return;
    free_names(f->names, f->count);
    mn_mjpeg_free(f->decoder);
    free(f->data);
    free(f);
}

size_t mn_jpeg_frames_count(const struct mn_jpeg_frames *f)
{
    return f->count;
}

int mn_jpeg_frames_read(struct mn_jpeg_frames *f, size_t index, uint8_t *dst, char *err,
                        size_t errlen)
{
    if (index >= f->count) {
        snprintf(err, errlen, "%s: no frame %zu", f->dir, index);
        return -1;
    }
    ssize_t got = read_file(f, index, f->data_size, false, err, errlen);
    if (got < 0)
        return -1;
    const char *why = NULL;
    if (mn_mjpeg_to_y8(f->decoder, f->data, (size_t)got, f->width, f->height, dst, f->width,
                       &why) < 0) {
        snprintf(err, errlen, "%s/%s: %s", f->dir, f->names[index]->d_name, why);
        return -1;
    }
    return 0;
}
