/* The background model of frames.mcf: a table of bg + Gaussian-like noise values built from
 * the seed with integer arithmetic only, and per-row offsets hashed from (seed, frame, row),
 * so writer and reader (x86 hub, arm64 node) rebuild the same pixels with a memcpy per row. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "framefile/framefile.h"

#define NOISE_TABLE 65536u

struct mn_ff_noise {
    uint32_t max_w;
    uint64_t seed;
    uint8_t *table; /* NOISE_TABLE + max_w values, so every row slice is contiguous */
};

/* MurmurHash3's 64-bit finaliser: a cheap, well-mixing bijection. */
static uint64_t fmix64(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    k ^= k >> 33;
    return k;
}

struct mn_ff_noise *mn_ff_noise_new(uint32_t max_w, uint8_t background, uint32_t sigma_q8,
                                    uint64_t seed)
{
    if (max_w < 1 || max_w > MN_FF_MAX_SIDE || sigma_q8 > 64u * 256u) {
        errno = EINVAL;
        return NULL;
    }
    struct mn_ff_noise *n = malloc(sizeof *n);
    if (!n)
        return NULL;
    n->max_w = max_w;
    n->seed = seed;
    n->table = malloc(NOISE_TABLE + max_w);
    if (!n->table) {
        free(n);
        return NULL;
    }
    /* Sum of four 16-bit uniforms: nearly Gaussian, mean 2 * 65535, sigma 65536 / sqrt(3). */
    const int64_t unit_sigma = 37837;
    for (uint32_t i = 0; i < NOISE_TABLE + max_w; i++) {
        uint64_t h = fmix64(seed ^ fmix64(0x6e6f697365ull + (i % NOISE_TABLE)));
        int64_t s = (int64_t)(h & 0xffff) + (int64_t)((h >> 16) & 0xffff) +
                    (int64_t)((h >> 32) & 0xffff) + (int64_t)(h >> 48) - 2 * 65535;
        int64_t q8 = (int64_t)background * 256 + s * (int64_t)sigma_q8 / unit_sigma + 128;
        int64_t v = q8 < 0 ? 0 : q8 / 256;
        n->table[i] = (uint8_t)(v > 255 ? 255 : v);
    }
    return n;
}

void mn_ff_noise_free(struct mn_ff_noise *noise)
{
    if (!noise)
        return;
    free(noise->table);
    free(noise);
}

void mn_ff_noise_fill(const struct mn_ff_noise *noise, uint64_t frame_number, uint32_t x0,
                      uint32_t y0, uint32_t w, uint32_t rows, uint8_t *dst, size_t stride)
{
    uint64_t fkey = fmix64(noise->seed + 0x9e3779b97f4a7c15ull * (frame_number + 1));
    for (uint32_t r = 0; r < rows; r++) {
        uint64_t off = fmix64(fkey ^ (0xc2b2ae3d27d4eb4full * (uint64_t)(y0 + r + 1)));
        memcpy(dst + (size_t)r * stride, noise->table + (off % NOISE_TABLE) + x0, w);
    }
}
