/* The memory-bound floor for detection: one vectorisable read of every pixel (a byte sum),
 * compiled as C with the detector's flags so the comparison is like for like. */
#ifndef MN_BENCH_READ_PASS_H
#define MN_BENCH_READ_PASS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Sum of all pixels of a w x h Y8 frame with the given stride. */
uint64_t mn_bench_read_pass(const uint8_t *pixels, uint32_t w, uint32_t h, size_t stride);

#ifdef __cplusplus
}
#endif

#endif
