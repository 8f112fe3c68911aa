/* libFuzzer target for the MJPEG path of the V4L2 source (mjpeg.c): a frame of any bytes, for a
 * negotiated size taken from the input's first two bytes (1..64 x 1..64), must be decoded or
 * refused without reading or writing out of bounds, and the decoder must still work after. The
 * header read the recorded-frames reader sizes its frames by (mn_mjpeg_size) gets the same bytes
 * and must give a size within 1..MN_MJPEG_MAX_SIDE or refuse. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "capture/mjpeg.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static struct mn_mjpeg *decoder;
    static uint8_t y8[64 * 64];
    if (size < 2)
        return 0;
    if (decoder == NULL && (decoder = mn_mjpeg_new()) == NULL)
        abort();
    uint32_t w = 1u + data[0] % 64u, h = 1u + data[1] % 64u;
    const char *why = NULL;
    uint32_t jw, jh;
    if (mn_mjpeg_size(decoder, data + 2, size - 2, &jw, &jh, &why) == 0 &&
        (jw == 0 || jh == 0 || jw > MN_MJPEG_MAX_SIDE || jh > MN_MJPEG_MAX_SIDE))
        abort();
    (void)mn_mjpeg_to_y8(decoder, data + 2, size - 2, w, h, y8, w, &why);
    return 0;
}
