/* libFuzzer target: arbitrary datagrams through the C client's decoder. It must never write
 * past the caller's arrays, and its counts must add up. */
#include <stdint.h>
#include <stdlib.h>

#include "mocap_stream_client.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    mocap_stream_point points[4];
    mocap_stream_body bodies[2];
    mocap_stream_frame frame = {.points = points, .point_capacity = 4, .bodies = bodies, .body_capacity = 2};
    if (mocap_stream_decode(data, size, &frame) == 0) {
        if (frame.point_count > 4 || frame.body_count > 2)
            abort();
        if (frame.point_count > frame.points_total || frame.body_count > frame.bodies_total)
            abort();
        for (size_t i = 0; i < frame.point_count; ++i)
            if (points[i].label[sizeof points[i].label - 1] != '\0')
                abort();
    }
    return 0;
}
