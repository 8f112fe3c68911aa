/* Marker blob detection on one Y8 frame: threshold, local morphology, scanline seed fill and
 * sub-pixel centroids (seed 000, section 4.1). Pure code: no I/O, no clock, no global state, and
 * no allocation after mn_detector_new, so the per-frame path has a fixed memory footprint.
 *
 * Error rule: functions returning int give 0 on success or -1 with errno set (EINVAL for bad
 * arguments); functions returning a pointer give NULL on failure with errno set.
 *
 * Coordinates: the centre of pixel (i, j) is at x = i, y = j, so pixel (0, 0) covers
 * [-0.5, 0.5] x [-0.5, 0.5]. A pixel is foreground when its value is strictly greater than the
 * threshold (the same rule as OpenCV's THRESH_BINARY), so a threshold of 255 finds nothing.
 */
#ifndef MN_DETECT_DETECT_H
#define MN_DETECT_DETECT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Largest frame side the detector accepts; keeps every per-blob sum exact in 64-bit integers. */
#define MN_DETECT_MAX_SIDE 16384u

enum mn_threshold_mode {
    MN_THRESHOLD_FIXED = 0, /* use threshold as given */
    MN_THRESHOLD_AUTO = 1,  /* background + noise estimated from a sampled histogram per frame */
};

enum mn_centroid_mode {
    MN_CENTROID_WEIGHTED = 0, /* weights = value - threshold (sharper, default) */
    MN_CENTROID_BINARY = 1,   /* the seed's plain mean of the blob's pixel centres */
};

/* Blob flags; the values are the wire protocol's MarkerFlag bits. */
enum mn_blob_flag {
    MN_BLOB_SATURATED = 1, /* some pixel reached saturation_level */
    MN_BLOB_MERGED = 2,    /* shape suggests two or more touching markers */
    MN_BLOB_BORDER = 4,    /* touches the image border or a masked pixel: centroid may be biased */
};

struct mn_detect_config {
    enum mn_threshold_mode threshold_mode;
    uint8_t threshold;        /* fixed mode: foreground is value > threshold */
    float auto_sigma_k;       /* auto mode: threshold = background + k * noise sigma ... */
    uint8_t auto_min_contrast; /* ... but at least background + this */
    uint8_t morph_radius;     /* 0: none; r: opening then closing with a (2r+1)^2 square, per blob */
    enum mn_centroid_mode centroid_mode;
    uint32_t min_area, max_area; /* pixels, after morphology */
    uint16_t min_bbox, max_bbox; /* bounding box side limits in pixels (both sides checked) */
    float min_roundness;      /* 0..1, blobs less round than this are rejected */
    float merged_roundness;   /* 0..1, blobs less round than this get MN_BLOB_MERGED */
    uint8_t saturation_level; /* peak >= this sets MN_BLOB_SATURATED */
    uint32_t max_blobs;       /* blobs kept per frame; more are counted in stats and dropped */
};

struct mn_blob {
    double x, y;          /* sub-pixel centroid, pixel-centre coordinates (see above) */
    uint32_t area;        /* pixels in the blob */
    uint16_t peak, mean;  /* brightest pixel; mean pixel value over the blob */
    uint16_t bbox_w, bbox_h;
    float roundness;      /* sqrt(minor / major second moment): 1 for a disc, ~0.45 for two */
    uint8_t flags;        /* enum mn_blob_flag bits */
};

/* Counters from the last mn_detector_run, for node status and tuning. */
struct mn_detect_stats {
    uint8_t threshold;         /* threshold actually used (auto mode: the estimate) */
    uint32_t candidates;       /* connected foreground regions found before filtering */
    uint32_t rejected_area;    /* outside min_area..max_area */
    uint32_t rejected_bbox;    /* outside min_bbox..max_bbox */
    uint32_t rejected_round;   /* below min_roundness */
    uint32_t rejected_complex; /* region too intricate for the fill's preallocated stack */
    uint32_t dropped;          /* accepted blobs beyond max_blobs or the caller's capacity */
};

struct mn_rect {
    uint32_t x, y, w, h;
};

struct mn_detector;

/* Fills cfg with working defaults: fixed threshold 128, morphology radius 1, weighted
 * centroids, area 3..10000, bbox 1..128, no roundness rejection, merged below 0.7,
 * saturation 255, 1024 blobs. */
void mn_detect_config_default(struct mn_detect_config *cfg);

/* Returns NULL when cfg is valid, otherwise a static string naming the first bad field. */
const char *mn_detect_config_check(const struct mn_detect_config *cfg);

/* Allocates everything the detector will need for frames up to max_w x max_h. Returns NULL with
 * errno EINVAL if cfg is invalid or a size is 0 or above MN_DETECT_MAX_SIDE, ENOMEM if memory
 * runs out. The caller frees the detector with mn_detector_free. */
struct mn_detector *mn_detector_new(const struct mn_detect_config *cfg, uint32_t max_w,
                                    uint32_t max_h);
void mn_detector_free(struct mn_detector *det);

/* Replaces the configuration (max_bbox and morph_radius may not grow beyond the values given
 * to mn_detector_new, since they size the per-blob buffers). */
int mn_detector_set_config(struct mn_detector *det, const struct mn_detect_config *cfg);
const struct mn_detect_config *mn_detector_config(const struct mn_detector *det);

/* Live threshold change from the hub: switches to the given mode (value ignored for auto). */
int mn_detector_set_threshold(struct mn_detector *det, enum mn_threshold_mode mode,
                              uint8_t value);

/* Masks hide static reflections: masked pixels count as background. Each set call replaces
 * the previous mask. Rectangles are clipped to the detector's maximum frame. */
int mn_detector_set_mask_rects(struct mn_detector *det, const struct mn_rect *rects, size_t n);
/* One bit per cell of cell_px x cell_px pixels, cells row-major, least significant bit first
 * (bit k of bits[i] is cell i * 8 + k); bits holds ceil(cells_x * cells_y / 8) bytes. */
int mn_detector_set_mask_bits(struct mn_detector *det, uint32_t cell_px, uint32_t cells_x,
                              uint32_t cells_y, const uint8_t *bits);
void mn_detector_clear_mask(struct mn_detector *det);

/* Detects blobs in a w x h Y8 frame whose rows start stride bytes apart (stride >= w). Writes
 * at most cap blobs to out in scan order (by topmost row, then leftmost pixel of that row) and
 * their number to *n_out. Returns -1/EINVAL if the frame exceeds the detector's maximum size. */
int mn_detector_run(struct mn_detector *det, const uint8_t *pixels, uint32_t w, uint32_t h,
                    size_t stride, struct mn_blob *out, size_t cap, size_t *n_out);

/* Counters of the most recent mn_detector_run. */
const struct mn_detect_stats *mn_detector_stats(const struct mn_detector *det);

#ifdef __cplusplus
}
#endif

#endif
