/* Read floor: sums every byte. Blocks of 256 bytes summed in 16 bits cannot overflow
 * (256 * 255 < 65536), which lets the compiler add in 16-bit vector lanes and reduce once per
 * block; of the plain-C sums tried (32-bit accumulators, 64- and 256-byte blocks, per-lane
 * accumulators) this was the fastest with GCC 12 -O3 on x86-64. */
#include "detect-bench/read_pass.h"

static inline uint32_t sum256(const uint8_t *p)
{
    uint16_t s = 0;
    for (int i = 0; i < 256; i++)
        s = (uint16_t)(s + p[i]);
    return s;
}

uint64_t mn_bench_read_pass(const uint8_t *pixels, uint32_t w, uint32_t h, size_t stride)
{
    uint64_t total = 0;
    uint32_t full = w & ~255u;
    for (uint32_t y = 0; y < h; y++) {
        const uint8_t *row = pixels + (size_t)y * stride;
        uint32_t s = 0;
        for (uint32_t x = 0; x < full; x += 256)
            s += sum256(row + x);
        for (uint32_t x = full; x < w; x++)
            s += row[x];
        total += s;
    }
    return total;
}
