/* Prints the hub's live stream, one line per frame and one per point:
 *   mocap_stream_print HOST PORT [FRAMES]            subscribe (serve --stream)
 *   mocap_stream_print --multicast GROUP PORT [FRAMES]
 * With FRAMES it stops after that many and prints two latencies of the frames, p50 p99 max in
 * ms: from the trigger edge to the frame's arrival here ("trigger_to_receive_ms") and from the
 * hub's result to its arrival here ("publish_to_receive_ms": what the stream itself adds). Both
 * compare clocks: the hub's on this host; across hosts they must be synchronised.
 * WAIT_S (default 5) is how long to wait for the first frame and between frames; exit status 1
 * when none arrives in that time. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mocap_stream_client.h"

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void print_percentiles(const char *name, double *values, long n)
{
    if (!n)
        return;
    qsort(values, (size_t)n, sizeof *values, compare);
    printf("%s %.3f %.3f %.3f\n", name, values[n / 2], values[(size_t)(0.99 * (double)(n - 1))], values[n - 1]);
}

int main(int argc, char **argv)
{
    int multicast = argc > 1 && strcmp(argv[1], "--multicast") == 0;
    if (argc < 3 + multicast) {
        fprintf(stderr, "usage: %s [--multicast] HOST PORT [FRAMES [WAIT_S]]\n", argv[0]);
        return 2;
    }
    const char *host = argv[1 + multicast];
    long port = strtol(argv[2 + multicast], NULL, 10);
    long frames = argc > 3 + multicast ? strtol(argv[3 + multicast], NULL, 10) : 0;
    long wait_s = argc > 4 + multicast ? strtol(argv[4 + multicast], NULL, 10) : 5;
    if (port <= 0 || port > 65535 || frames < 0 || wait_s <= 0 || wait_s > 3600) {
        fprintf(stderr, "bad port or frame count\n");
        return 2;
    }
    mocap_stream_client *client;
    int rc = multicast ? mocap_stream_open_multicast(&client, host, (uint16_t)port, NULL)
                       : mocap_stream_open(&client, host, (uint16_t)port, MOCAP_STREAM_POINTS | MOCAP_STREAM_BODIES);
    if (rc < 0) {
        fprintf(stderr, "cannot open the stream: %s\n", strerror(-rc));
        return 1;
    }
    static mocap_stream_point points[4096];
    static mocap_stream_body bodies[64];
    mocap_stream_frame frame = {.points = points, .point_capacity = 4096, .bodies = bodies, .body_capacity = 64};
    double *latency = frames ? calloc((size_t)frames, sizeof *latency) : NULL;
    double *stream_latency = frames ? calloc((size_t)frames, sizeof *stream_latency) : NULL;
    long got = 0, timed = 0, stream_timed = 0;
    while (!frames || got < frames) {
        rc = mocap_stream_receive(client, &frame, (int)wait_s * 1000);
        if (rc <= 0) {
            if (rc == 0)
                fprintf(stderr, "no frame for %ld s\n", wait_s);
            else
                fprintf(stderr, "receive: %s\n", strerror(-rc));
            break;
        }
        struct timespec now;
        clock_gettime(CLOCK_REALTIME, &now);
        uint64_t now_ns = (uint64_t)now.tv_sec * 1000000000ull + (uint64_t)now.tv_nsec;
        if (latency && frame.trigger_time_ns && now_ns > frame.trigger_time_ns)
            latency[timed++] = (double)(now_ns - frame.trigger_time_ns) * 1e-6;
        if (stream_latency && frame.publish_time_ns && now_ns > frame.publish_time_ns)
            stream_latency[stream_timed++] = (double)(now_ns - frame.publish_time_ns) * 1e-6;
        printf("frame %llu cameras %u points %zu bodies %zu\n", (unsigned long long)frame.frame_number,
               frame.cameras, frame.points_total, frame.bodies_total);
        for (size_t i = 0; i < frame.point_count; ++i) {
            const mocap_stream_point *p = &points[i];
            printf("  point %d %llu %.3f %.3f %.3f %.3f %u\n", p->marker, (unsigned long long)p->provisional_track,
                   p->x, p->y, p->z, p->residual_px, p->views);
        }
        for (size_t i = 0; i < frame.body_count; ++i)
            printf("  body %s %d %.3f %.3f %.3f\n", bodies[i].name, bodies[i].tracked, bodies[i].x, bodies[i].y,
                   bodies[i].z);
        ++got;
    }
    mocap_stream_close(client);
    print_percentiles("trigger_to_receive_ms", latency, timed);
    print_percentiles("publish_to_receive_ms", stream_latency, stream_timed);
    free(latency);
    free(stream_latency);
    return got > 0 && (!frames || got == frames) ? 0 : 1;
}
