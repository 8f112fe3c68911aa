// libcamera capture behind the C capture interface. libcamera completes requests on its own
// thread; this shim queues them under a mutex and signals an eventfd, so the node's single poll
// loop sees libcamera like any other descriptor and all processing stays on the loop's thread.
// Formats whose first plane is 8-bit luma are handed out in place; packed RGB (vimc, ISPs
// without a YUV output) is converted to luma into one buffer allocated at open.
// An unplugged camera: libcamera (0.0.3) signals Camera::disconnected only for pipelines that
// ask for hot-unplug events (UVC); for the others (vimc, the boards' CSI pipelines) requests
// just stop completing, and stopping the camera then trips an assertion in libcamera's
// PipelineHandler::stop() (abort). So while running, a timer checks twice a second whether the
// V4L2 device nodes libcamera opened for this camera still exist. When one was removed, the
// camera cannot be torn down either (without stop(), destroying it ends the process through a
// still-running IPA thread): dequeue reports ENOTRECOVERABLE, close leaves libcamera's objects
// alone, and the node exits with "hardware missing" for systemd to start it afresh.
// The C headers of the node (capture_libcamera.h declares only its own functions extern "C").
extern "C" {
#include "capture/pixfmt.h"
#include "common/log.h"
}
#include "capture/capture_libcamera.h"

#include <dirent.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <new>
#include <vector>

#include <libcamera/libcamera.h>

namespace {

using namespace libcamera;

struct Mapped {
    void *start = MAP_FAILED;
    size_t length = 0;
    size_t offset = 0; // of plane 0 inside the mapping
};

struct LibcameraCapture {
    std::unique_ptr<CameraManager> manager;
    std::shared_ptr<Camera> camera;
    std::unique_ptr<CameraConfiguration> config;
    std::unique_ptr<FrameBufferAllocator> allocator;
    Stream *stream = nullptr;
    std::vector<std::unique_ptr<Request>> requests;
    std::vector<Mapped> maps; // by request index
    uint32_t width = 0, height = 0, stride = 0;
    bool convert = false;       // packed RGB: luma into y8
    enum mn_pixfmt pixfmt = MN_PIXFMT_RGB24;
    uint32_t bytes_per_pixel = 1;
    std::vector<uint8_t> y8;
    int event_fd = -1;
    int check_fd = -1;            // timerfd: the unplug check while running
    int poll_fd = -1;             // epoll over event_fd and check_fd, what the loop polls
    std::vector<int> device_fds;  // libcamera's descriptors of this camera's /dev/video* nodes
    bool gone = false;            // a device node was removed: no stop() (see above)
    bool acquired = false;
    bool running = false;
    std::mutex lock;
    std::deque<Request *> completed; // guarded by lock
    bool disconnected = false;       // guarded by lock: the camera was unplugged
    // Control values waiting for the next requeued request (set from the loop thread only).
    bool exposure_pending = false, gain_pending = false;
    bool brightness_pending = false, contrast_pending = false;
    int32_t exposure_us = 0;
    float gain = 1.0f, brightness = 0.0f, contrast = 1.0f;

    void onComplete(Request *request)
    {
        {
            std::lock_guard<std::mutex> guard(lock);
            completed.push_back(request);
        }
        signal();
    }

    // The pipeline handler's devices went away (hot-unplug seen by libcamera's udev monitor).
    void onDisconnect()
    {
        {
            std::lock_guard<std::mutex> guard(lock);
            disconnected = true;
        }
        signal();
    }

    void signal()
    {
        uint64_t one = 1;
        // A full eventfd counter still wakes the loop, so a failed write loses nothing.
        ssize_t rc = write(event_fd, &one, sizeof(one));
        (void)rc;
    }

    ~LibcameraCapture()
    {
        if (running && camera)
            camera->stop();
        if (camera) {
            camera->requestCompleted.disconnect(this, &LibcameraCapture::onComplete);
            camera->disconnected.disconnect(this, &LibcameraCapture::onDisconnect);
        }
        for (Mapped &m : maps)
            if (m.start != MAP_FAILED)
                munmap(m.start, m.length);
        requests.clear();
        allocator.reset();
        if (acquired)
            camera->release();
        camera.reset();
        if (manager)
            manager->stop();
        if (event_fd >= 0)
            close(event_fd);
        if (check_fd >= 0)
            close(check_fd);
        if (poll_fd >= 0)
            close(poll_fd);
    }
};

void fail(char *err, size_t errlen, const char *what, int e)
{
    std::snprintf(err, errlen, "libcamera: %s", what);
    errno = e;
}

// What the node reads from a libcamera format: its first plane in place (8-bit luma), or packed
// RGB converted. libcamera names packed RGB by the 32-bit word, so RGB888 is B, G, R in memory.
struct FormatUse {
    PixelFormat format;
    bool convert;
    enum mn_pixfmt pixfmt;
    uint32_t bytes_per_pixel;
};

const FormatUse kFormats[] = {
    {formats::R8, false, MN_PIXFMT_RGB24, 1},
    {formats::YUV420, false, MN_PIXFMT_RGB24, 1},
    {formats::YVU420, false, MN_PIXFMT_RGB24, 1},
    {formats::NV12, false, MN_PIXFMT_RGB24, 1},
    {formats::NV21, false, MN_PIXFMT_RGB24, 1},
    {formats::RGB888, true, MN_PIXFMT_BGR24, 3},
    {formats::BGR888, true, MN_PIXFMT_RGB24, 3},
    {formats::XRGB8888, true, MN_PIXFMT_XBGR32, 4},
};

// The first format of kFormats the camera accepts unchanged at the requested size.
bool configure(LibcameraCapture *c, uint32_t width, uint32_t height, uint32_t buffers)
{
    for (const FormatUse &use : kFormats) {
        c->config = c->camera->generateConfiguration({StreamRole::Raw});
        if (!c->config || c->config->size() != 1)
            c->config = c->camera->generateConfiguration({StreamRole::VideoRecording});
        if (!c->config || c->config->size() != 1)
            return false;
        StreamConfiguration &sc = c->config->at(0);
        sc.pixelFormat = use.format;
        sc.bufferCount = buffers;
        if (width != 0)
            sc.size = Size(width, height);
        if (c->config->validate() == CameraConfiguration::Invalid)
            continue;
        if (sc.pixelFormat != use.format)
            continue;
        if (c->camera->configure(c->config.get()) < 0)
            return false;
        c->stream = sc.stream();
        c->width = sc.size.width;
        c->height = sc.size.height;
        c->stride = sc.stride;
        c->convert = use.convert;
        c->pixfmt = use.pixfmt;
        c->bytes_per_pixel = use.bytes_per_pixel;
        if (c->stride < c->width * c->bytes_per_pixel)
            return false;
        if (c->convert)
            c->y8.resize(static_cast<size_t>(c->width) * c->height);
        return true;
    }
    return false;
}

bool map_and_request(LibcameraCapture *c, char *err, size_t errlen)
{
    c->allocator = std::make_unique<FrameBufferAllocator>(c->camera);
    if (c->allocator->allocate(c->stream) < 0) {
        fail(err, errlen, "cannot allocate frame buffers", ENOMEM);
        return false;
    }
    for (const std::unique_ptr<FrameBuffer> &buffer : c->allocator->buffers(c->stream)) {
        const FrameBuffer::Plane &plane = buffer->planes()[0];
        Mapped m;
        // mmap needs a page-aligned offset; keep the remainder to find the plane.
        size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
        size_t aligned = plane.offset / page * page;
        m.offset = plane.offset - aligned;
        m.length = plane.length + m.offset;
        m.start = mmap(nullptr, m.length, PROT_READ, MAP_SHARED, plane.fd.get(),
                       static_cast<off_t>(aligned));
        if (m.start == MAP_FAILED) {
            fail(err, errlen, "cannot mmap a frame buffer", errno);
            return false;
        }
        if (static_cast<size_t>(c->stride) * (c->height - 1) + c->width * c->bytes_per_pixel >
            plane.length) {
            munmap(m.start, m.length);
            fail(err, errlen, "frame buffer smaller than the configured frame", EPROTO);
            return false;
        }
        c->maps.push_back(m);
        std::unique_ptr<Request> request = c->camera->createRequest(c->requests.size());
        if (!request || request->addBuffer(c->stream, buffer.get()) < 0) {
            fail(err, errlen, "cannot create a capture request", ENOMEM);
            return false;
        }
        c->requests.push_back(std::move(request));
    }
    return true;
}

// The descriptors libcamera holds open on /dev/video* nodes once the camera is configured and
// its buffers allocated: the nodes of this camera (the node's process opens no other camera).
void record_device_fds(LibcameraCapture *c)
{
    DIR *dir = opendir("/proc/self/fd");
    if (dir == nullptr)
        return;
    while (struct dirent *e = readdir(dir)) {
        char path[300], target[256];
        std::snprintf(path, sizeof(path), "/proc/self/fd/%s", e->d_name);
        ssize_t n = readlink(path, target, sizeof(target) - 1);
        if (n <= 0)
            continue;
        target[n] = '\0';
        if (std::strncmp(target, "/dev/video", 10) == 0)
            c->device_fds.push_back(std::atoi(e->d_name));
    }
    closedir(dir);
}

// True when one of the camera's device nodes was removed (its link reads "... (deleted)").
bool device_removed(const LibcameraCapture *c)
{
    for (int fd : c->device_fds) {
        char path[64], target[256];
        std::snprintf(path, sizeof(path), "/proc/self/fd/%d", fd);
        ssize_t n = readlink(path, target, sizeof(target) - 1);
        if (n <= 0)
            return true;
        target[n] = '\0';
        if (std::strstr(target, " (deleted)") != nullptr)
            return true;
    }
    return false;
}

void arm_check(LibcameraCapture *c, bool on)
{
    struct itimerspec its = {};
    if (on) {
        its.it_value.tv_nsec = 500000000;
        its.it_interval.tv_nsec = 500000000;
    }
    timerfd_settime(c->check_fd, 0, &its, nullptr);
}

LibcameraCapture *impl_of(void *impl)
{
    return static_cast<LibcameraCapture *>(impl);
}

void apply_pending_controls(LibcameraCapture *c, Request *request)
{
    if (c->exposure_pending) {
        request->controls().set(controls::ExposureTime, c->exposure_us);
        c->exposure_pending = false;
    }
    if (c->gain_pending) {
        request->controls().set(controls::AnalogueGain, c->gain);
        c->gain_pending = false;
    }
    if (c->brightness_pending) {
        request->controls().set(controls::Brightness, c->brightness);
        c->brightness_pending = false;
    }
    if (c->contrast_pending) {
        request->controls().set(controls::Contrast, c->contrast);
        c->contrast_pending = false;
    }
}

int lc_start(void *impl)
{
    LibcameraCapture *c = impl_of(impl);
    if (c->camera->start() < 0) {
        errno = EIO;
        return -1;
    }
    c->running = true;
    arm_check(c, true);
    for (std::unique_ptr<Request> &r : c->requests) {
        r->reuse(Request::ReuseBuffers); // requests cancelled by a previous stop
        apply_pending_controls(c, r.get());
        if (c->camera->queueRequest(r.get()) < 0) {
            errno = EIO;
            return -1;
        }
    }
    return 0;
}

int lc_stop(void *impl)
{
    LibcameraCapture *c = impl_of(impl);
    if (!c->running)
        return 0;
    c->running = false;
    arm_check(c, false);
    if (c->gone)
        return 0; // see the top of this file: stop() would abort
    int rc = c->camera->stop(); // completes (cancels) every queued request
    std::lock_guard<std::mutex> guard(c->lock);
    c->completed.clear();
    if (rc < 0) {
        errno = EIO;
        return -1;
    }
    return 0;
}

int lc_fd(void *impl)
{
    return impl_of(impl)->poll_fd;
}

// The next completed request, or nullptr. The eventfd is read only once the queue is seen
// empty, and the queue checked again after it: a completion always pushes before it signals, so
// no frame is left queued without a wake-up, however few frames the loop takes per wake-up.
Request *next_completed(LibcameraCapture *c, bool *disconnected)
{
    for (int pass = 0; pass < 2; pass++) {
        {
            std::lock_guard<std::mutex> guard(c->lock);
            *disconnected = c->disconnected;
            if (!c->completed.empty()) {
                Request *request = c->completed.front();
                c->completed.pop_front();
                return request;
            }
        }
        if (pass == 0) {
            uint64_t counter;
            ssize_t rc = read(c->event_fd, &counter, sizeof(counter)); // EAGAIN: not signalled
            (void)rc;
        }
    }
    return nullptr;
}

int lc_dequeue(void *impl, struct mn_frame *frame)
{
    LibcameraCapture *c = impl_of(impl);
    uint64_t expirations;
    if (read(c->check_fd, &expirations, sizeof(expirations)) > 0 && device_removed(c)) {
        c->gone = true;
        errno = ENOTRECOVERABLE;
        return -1;
    }
    for (;;) {
        bool disconnected = false;
        Request *request = next_completed(c, &disconnected);
        if (request == nullptr) {
            if (disconnected) {
                errno = ENODEV;
                return -1;
            }
            return 0;
        }
        if (request->status() != Request::RequestComplete) {
            if (!c->running)
                continue;
            // Cancelled while running: the camera went away or failed.
            errno = EIO;
            return -1;
        }
        FrameBuffer *buffer = request->buffers().begin()->second;
        const FrameMetadata &meta = buffer->metadata();
        if (meta.status != FrameMetadata::FrameSuccess) {
            request->reuse(Request::ReuseBuffers);
            if (c->camera->queueRequest(request) < 0) {
                errno = EIO;
                return -1;
            }
            continue;
        }
        const Mapped &m = c->maps[request->cookie()];
        const uint8_t *plane = static_cast<const uint8_t *>(m.start) + m.offset;
        if (c->convert) {
            mn_pixfmt_to_y8(c->pixfmt, plane, c->stride, c->width, c->height, c->y8.data(),
                            c->width);
            frame->pixels = c->y8.data();
            frame->stride = c->width;
        } else {
            frame->pixels = plane;
            frame->stride = c->stride;
        }
        frame->width = c->width;
        frame->height = c->height;
        frame->capture_mono_ns = static_cast<int64_t>(meta.timestamp); // CLOCK_MONOTONIC
        frame->sequence = meta.sequence;
        frame->slot = static_cast<int>(request->cookie());
        return 1;
    }
}

int lc_release(void *impl, const struct mn_frame *frame)
{
    LibcameraCapture *c = impl_of(impl);
    if (frame->slot < 0 || static_cast<size_t>(frame->slot) >= c->requests.size()) {
        errno = EINVAL;
        return -1;
    }
    Request *request = c->requests[static_cast<size_t>(frame->slot)].get();
    request->reuse(Request::ReuseBuffers);
    apply_pending_controls(c, request);
    if (c->running && c->camera->queueRequest(request) < 0) {
        errno = EIO;
        return -1;
    }
    return 0;
}

// A control the camera does not list would be dropped by libcamera with only a log line (vimc
// has neither exposure nor gain): refuse it here so that the hub's ack says so.
const ControlInfo *control_info(LibcameraCapture *c, const ControlId &id)
{
    const ControlInfoMap &info = c->camera->controls();
    auto it = info.find(&id);
    return it == info.end() ? nullptr : &it->second;
}

int lc_set_exposure(void *impl, uint32_t exposure_us)
{
    LibcameraCapture *c = impl_of(impl);
    const ControlInfo *info = control_info(c, controls::ExposureTime);
    if (info == nullptr) {
        errno = ENOTSUP;
        return -1;
    }
    int32_t value = static_cast<int32_t>(exposure_us);
    value = std::max(value, info->min().get<int32_t>());
    value = std::min(value, info->max().get<int32_t>());
    c->exposure_us = value;
    c->exposure_pending = true;
    return 0;
}

int lc_set_gain(void *impl, uint32_t gain_milli)
{
    LibcameraCapture *c = impl_of(impl);
    const ControlInfo *info = control_info(c, controls::AnalogueGain);
    if (info == nullptr) {
        errno = ENOTSUP;
        return -1;
    }
    float value = static_cast<float>(gain_milli) / 1000.0f;
    value = std::max(value, info->min().get<float>());
    value = std::min(value, info->max().get<float>());
    c->gain = value;
    c->gain_pending = true;
    return 0;
}

// Brightness (-1..1) and Contrast (1 = unchanged) in the camera's own range; like exposure and
// gain they go with the next queued request.
int lc_set_picture(void *impl, enum mn_picture_control which, uint32_t pct, double *value_out)
{
    LibcameraCapture *c = impl_of(impl);
    const ControlId &id = which == MN_PICTURE_BRIGHTNESS ? static_cast<const ControlId &>(controls::Brightness)
                                                         : static_cast<const ControlId &>(controls::Contrast);
    const ControlInfo *info = control_info(c, id);
    if (info == nullptr) {
        errno = ENOTSUP;
        return -1;
    }
    float lo = info->min().get<float>(), hi = info->max().get<float>();
    float value = lo + (hi - lo) * static_cast<float>(pct) / 100.0f;
    *value_out = value;
    if (which == MN_PICTURE_BRIGHTNESS) {
        c->brightness = value;
        c->brightness_pending = true;
    } else {
        c->contrast = value;
        c->contrast_pending = true;
    }
    return 0;
}

void lc_close(void *impl)
{
    LibcameraCapture *c = impl_of(impl);
    if (c->gone) {
        // See the top of this file: only our own descriptors go; the process is exiting.
        close(c->event_fd);
        close(c->check_fd);
        close(c->poll_fd);
        return;
    }
    delete c;
}

} // namespace

extern "C" const struct mn_capture_ops mn_capture_libcamera_ops = {
    "libcamera", lc_start, lc_stop, lc_fd, lc_dequeue, lc_release, lc_set_exposure, lc_set_gain,
    lc_set_picture, lc_close,
};

extern "C" void *mn_capture_libcamera_new(unsigned index, uint32_t width, uint32_t height,
                                          uint32_t buffers, uint32_t *out_width,
                                          uint32_t *out_height, char *err, size_t errlen)
{
    LibcameraCapture *c = new (std::nothrow) LibcameraCapture;
    if (c == nullptr) {
        fail(err, errlen, "out of memory", ENOMEM);
        return nullptr;
    }
    try {
        c->event_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
        c->check_fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
        c->poll_fd = epoll_create1(EPOLL_CLOEXEC);
        if (c->event_fd < 0 || c->check_fd < 0 || c->poll_fd < 0) {
            fail(err, errlen, "eventfd, timerfd or epoll failed", errno);
            goto fail;
        }
        for (int fd : {c->event_fd, c->check_fd}) {
            struct epoll_event ev = {};
            ev.events = EPOLLIN;
            ev.data.fd = fd;
            if (epoll_ctl(c->poll_fd, EPOLL_CTL_ADD, fd, &ev) < 0) {
                fail(err, errlen, "epoll_ctl failed", errno);
                goto fail;
            }
        }
        c->manager = std::make_unique<CameraManager>();
        if (c->manager->start() < 0) {
            c->manager.reset();
            fail(err, errlen, "camera manager did not start", EIO);
            goto fail;
        }
        {
            std::vector<std::shared_ptr<Camera>> cameras = c->manager->cameras();
            if (index >= cameras.size()) {
                std::snprintf(err, errlen, "libcamera: no camera %u (%zu found)", index,
                              cameras.size());
                errno = ENODEV;
                goto fail;
            }
            c->camera = cameras[index];
        }
        if (c->camera->acquire() < 0) {
            fail(err, errlen, "camera is in use by another process", EBUSY);
            goto fail;
        }
        c->acquired = true;
        if (!configure(c, width, height, buffers)) {
            fail(err, errlen,
                 "camera offers none of R8, YUV420, YVU420, NV12, NV21, RGB888, BGR888, XRGB8888 "
                 "at the requested size",
                 ENOTSUP);
            goto fail;
        }
        if (!map_and_request(c, err, errlen))
            goto fail;
        record_device_fds(c);
        c->camera->requestCompleted.connect(c, &LibcameraCapture::onComplete);
        c->camera->disconnected.connect(c, &LibcameraCapture::onDisconnect);
        mn_log_info("libcamera %u (%s): %ux%u %s, stride %u, %zu buffers, %zu video nodes",
                    index, c->camera->id().c_str(), c->width, c->height,
                    c->config->at(0).pixelFormat.toString().c_str(), c->stride,
                    c->requests.size(), c->device_fds.size());
    } catch (const std::bad_alloc &) {
        fail(err, errlen, "out of memory", ENOMEM);
        goto fail;
    }
    *out_width = c->width;
    *out_height = c->height;
    return c;

fail:
    int e = errno;
    delete c;
    errno = e;
    return nullptr;
}
