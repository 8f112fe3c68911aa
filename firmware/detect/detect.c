/* Marker blob detector: a vectorisable scan for bright 64-pixel chunks, scanline seed fill of
 * each bright region into a span list, optional per-blob morphology on a small bit patch, then
 * blob statistics from the spans. Every buffer comes from mn_detector_new; running never
 * allocates, and the fill consumes the bright bitmap, so nothing needs clearing per frame. */
#include "detect/detect.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "detect/detect_internal.h"

void mn_detect_config_default(struct mn_detect_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->threshold_mode = MN_THRESHOLD_FIXED;
    cfg->threshold = 128;
    cfg->auto_sigma_k = 8.0f;
    cfg->auto_min_contrast = 24;
    cfg->morph_radius = 1;
    cfg->centroid_mode = MN_CENTROID_WEIGHTED;
    cfg->min_area = 3;
    cfg->max_area = 10000;
    cfg->min_bbox = 1;
    cfg->max_bbox = 128;
    cfg->min_roundness = 0.0f;
    cfg->merged_roundness = 0.7f;
    cfg->saturation_level = 255;
    cfg->max_blobs = 1024;
}

const char *mn_detect_config_check(const struct mn_detect_config *cfg)
{
    if (!cfg)
        return "config is NULL";
    if (cfg->threshold_mode != MN_THRESHOLD_FIXED && cfg->threshold_mode != MN_THRESHOLD_AUTO)
        return "threshold_mode must be fixed or auto";
    if (!(cfg->auto_sigma_k > 0.0f && cfg->auto_sigma_k <= 100.0f))
        return "auto_sigma_k must be in (0, 100]";
    if (cfg->morph_radius > MN_DETECT_MAX_MORPH_RADIUS)
        return "morph_radius must be at most 8";
    if (cfg->centroid_mode != MN_CENTROID_WEIGHTED && cfg->centroid_mode != MN_CENTROID_BINARY)
        return "centroid_mode must be weighted or binary";
    if (cfg->min_area < 1 || cfg->max_area < cfg->min_area)
        return "area limits must satisfy 1 <= min_area <= max_area";
    if (cfg->min_bbox < 1 || cfg->max_bbox < cfg->min_bbox)
        return "bbox limits must satisfy 1 <= min_bbox <= max_bbox";
    if (cfg->max_bbox > MN_DETECT_MAX_BBOX)
        return "max_bbox must be at most 1024";
    if (!(cfg->min_roundness >= 0.0f && cfg->min_roundness <= 1.0f))
        return "min_roundness must be in [0, 1]";
    if (!(cfg->merged_roundness >= 0.0f && cfg->merged_roundness <= 1.0f))
        return "merged_roundness must be in [0, 1]";
    if (cfg->saturation_level < 1)
        return "saturation_level must be at least 1";
    if (cfg->max_blobs < 1)
        return "max_blobs must be at least 1";
    return NULL;
}

struct mn_detector *mn_detector_new(const struct mn_detect_config *cfg, uint32_t max_w,
                                    uint32_t max_h)
{
    if (mn_detect_config_check(cfg) || max_w < 1 || max_h < 1 || max_w > MN_DETECT_MAX_SIDE ||
        max_h > MN_DETECT_MAX_SIDE) {
        errno = EINVAL;
        return NULL;
    }
    struct mn_detector *det = calloc(1, sizeof *det);
    if (!det)
        goto fail;
    det->cfg = *cfg;
    det->max_w = max_w;
    det->max_h = max_h;
    det->cap_bbox = cfg->max_bbox;
    det->cap_radius = cfg->morph_radius;
    det->row_words = (max_w + 63) / 64;
    size_t bitmap_words = det->row_words * max_h;
    det->bright = calloc(bitmap_words, sizeof(uint64_t));
    det->mask = calloc(bitmap_words, sizeof(uint64_t));
    det->seeds = malloc(bitmap_words * sizeof *det->seeds);
    if (!det->bright || !det->mask || !det->seeds)
        goto fail_free;

    /* The patch holds the largest accepted bbox plus the morphology margin on each side. */
    size_t patch_side = (size_t)det->cap_bbox + 2u * det->cap_radius;
    det->patch_words = (patch_side + 63) / 64;
    det->patch_rows = patch_side;
    for (int i = 0; i < MN_PATCH_PLANES; i++) {
        det->patch[i] = calloc(det->patch_words * det->patch_rows, sizeof(uint64_t));
        if (!det->patch[i])
            goto fail_free;
    }

    /* One span queue serves the region fill and the patch relabelling (a component and its
     * final pixel set, at most half the patch's pixels as runs each). A region with more spans
     * than this is rejected (its threshold is hopeless anyway), so it bounds memory. */
    size_t cap = (size_t)max_w * max_h / 8;
    size_t patch_spans = 2 * patch_side * (patch_side / 2 + 1);
    if (cap < patch_spans)
        cap = patch_spans;
    if (cap < 16384)
        cap = 16384;
    det->spans_cap = cap;
    det->spans = malloc(cap * sizeof *det->spans);
    if (!det->spans)
        goto fail_free;
    return det;

fail_free:
    mn_detector_free(det);
fail:
    errno = ENOMEM;
    return NULL;
}

void mn_detector_free(struct mn_detector *det)
{
    if (!det)
        return;
    free(det->seeds);
    free(det->spans);
    for (int i = 0; i < MN_PATCH_PLANES; i++)
        free(det->patch[i]);
    free(det->mask);
    free(det->bright);
    free(det);
}

int mn_detector_set_config(struct mn_detector *det, const struct mn_detect_config *cfg)
{
    if (!det || mn_detect_config_check(cfg) || cfg->max_bbox > det->cap_bbox ||
        cfg->morph_radius > det->cap_radius) {
        errno = EINVAL;
        return -1;
    }
    det->cfg = *cfg;
    return 0;
}

const struct mn_detect_config *mn_detector_config(const struct mn_detector *det)
{
    return &det->cfg;
}

int mn_detector_set_threshold(struct mn_detector *det, enum mn_threshold_mode mode,
                              uint8_t value)
{
    if (!det || (mode != MN_THRESHOLD_FIXED && mode != MN_THRESHOLD_AUTO)) {
        errno = EINVAL;
        return -1;
    }
    det->cfg.threshold_mode = mode;
    if (mode == MN_THRESHOLD_FIXED)
        det->cfg.threshold = value;
    return 0;
}

const struct mn_detect_stats *mn_detector_stats(const struct mn_detector *det)
{
    return &det->stats;
}
