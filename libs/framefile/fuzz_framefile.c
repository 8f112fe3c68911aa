/* libFuzzer target: arbitrary bytes as a frames.mcf file must never crash the reader, which
 * either refuses the header or yields frames until the data ends or is damaged. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "framefile/framefile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* Frame size sits at bytes 12..19; large frames are valid but only slow the fuzzer
     * down with big buffers, so they are skipped before the reader allocates for them. */
    if (size >= 20) {
        uint32_t w = data[12] | data[13] << 8 | (uint32_t)data[14] << 16 | (uint32_t)data[15] << 24;
        uint32_t h = data[16] | data[17] << 8 | (uint32_t)data[18] << 16 | (uint32_t)data[19] << 24;
        if ((uint64_t)w * h > 256u * 256u)
            return 0;
    }
    const char *why = NULL;
    struct mn_ff_reader *rd = mn_ff_reader_open_mem(data, size, &why);
    if (!rd)
        return 0;
    const struct mn_ff_info *info = mn_ff_reader_info(rd);
    uint8_t *px = malloc((size_t)info->width * info->height);
    struct mn_ff_frame fr;
    if (px) {
        for (int i = 0; i < 64 && mn_ff_reader_next(rd, px, info->width, &fr) == 1; i++)
            ;
        free(px);
    }
    mn_ff_reader_close(rd);
    return 0;
}
