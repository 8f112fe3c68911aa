/* Automatic threshold from a sparse histogram of the frame: background = median, noise sigma
 * from the median absolute deviation. Markers cover well under half of any real frame, so
 * both estimates ignore them; sampling keeps the cost a small fraction of the scan. */
#include <math.h>

#include "detect/detect.h"
#include "detect/detect_internal.h"

/* About this many samples: plenty for a median and a MAD. They are whole rows, evenly spaced,
 * because memory traffic counts cache lines, not pixels: the cost stays a few percent of the
 * frame scan. */
#define MN_AUTO_SAMPLES 4096u

static uint32_t hist_quantile(const uint32_t *hist, uint32_t rank)
{
    uint32_t acc = 0;
    for (uint32_t v = 0; v < 256; v++) {
        acc += hist[v];
        if (acc > rank)
            return v;
    }
    return 255;
}

uint8_t mn_detect_auto_threshold(const struct mn_detector *det, const struct mn_frame_view *f)
{
    uint32_t hist[256] = {0};
    uint32_t rows = MN_AUTO_SAMPLES / f->w + 1;
    if (rows > f->h)
        rows = f->h;
    uint32_t total = 0;
    for (uint32_t i = 0; i < rows; i++) {
        /* Row centres of rows equal bands. */
        uint32_t y = (uint32_t)(((uint64_t)2 * i + 1) * f->h / (2u * rows));
        const uint8_t *row = f->px + (size_t)y * f->stride;
        for (uint32_t x = 0; x < f->w; x++)
            hist[row[x]]++;
        total += f->w;
    }
    uint32_t median = hist_quantile(hist, total / 2);

    /* Median absolute deviation, via a histogram of |v - median|. */
    uint32_t dev[256] = {0};
    for (uint32_t v = 0; v < 256; v++)
        dev[v > median ? v - median : median - v] += hist[v];
    uint32_t mad = hist_quantile(dev, total / 2);
    /* Integer pixels quantise the MAD; half a level keeps a noiseless frame's sigma > 0. */
    double sigma = 1.4826 * ((double)mad + 0.5);

    double rise = det->cfg.auto_sigma_k * sigma;
    if (rise < det->cfg.auto_min_contrast)
        rise = det->cfg.auto_min_contrast;
    double t = (double)median + rise;
    return t >= 254.0 ? 254 : (uint8_t)lround(t);
}
