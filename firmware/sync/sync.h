/* Trigger-edge sources behind one table of function pointers: gpio (libgpiod edge events with
 * kernel time stamps), sim (seeded simulated edges with jitter, missed and spurious edges) and
 * none (free run). Edges are CLOCK_MONOTONIC ns; numbering and pairing happen in pairing.h. */
#ifndef MN_SYNC_H
#define MN_SYNC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sync/grid.h"

enum mn_sync_kind {
    MN_SYNC_NONE, /* free run: frame numbers from capture time */
    MN_SYNC_GPIO, /* gpio:CHIP:LINE edge events */
    MN_SYNC_SIM,  /* sim:RATE simulated edges (tests, simulated sessions) */
};

struct mn_sync_ops {
    const char *name;
    bool free_run; /* no edges: frames are numbered from their capture time */
    int (*fd)(void *impl);
    /* Appends edges up to until_mono_ns (a simulated source generates them on demand; a real
     * one returns whatever the kernel has queued) to edges[0..cap), count in *n. */
    int (*read)(void *impl, int64_t until_mono_ns, int64_t *edges, size_t cap, size_t *n);
    void (*set_grid)(void *impl, const struct mn_grid *grid);
    void (*close)(void *impl);
};

struct mn_sim_sync_params {
    struct mn_grid grid;
    int64_t jitter_ns;  /* standard deviation of the edge time */
    double missed;      /* probability that a slot's edge is lost */
    double spurious;    /* probability of an extra edge somewhere within a period */
    uint32_t seed;
};

struct mn_gpio_sync_params {
    const char *chip; /* gpiochip name or path */
    uint32_t line;
    bool falling;     /* trigger on the falling edge instead of the rising one */
};

/* What mn_sync_open needs: the kind, and the parameters of that kind (the others are ignored). */
struct mn_sync_params {
    enum mn_sync_kind kind;
    struct mn_gpio_sync_params gpio;
    struct mn_sim_sync_params sim;
};

struct mn_sync;

/* Opens the source params->kind names. NULL with errno set on failure (and the reason in err);
 * close with mn_sync_close. */
struct mn_sync *mn_sync_open(const struct mn_sync_params *params, char *err, size_t errlen);
void mn_sync_close(struct mn_sync *s);

const char *mn_sync_name(const struct mn_sync *s);
bool mn_sync_free_run(const struct mn_sync *s);
/* Pollable descriptor, or -1 when the source has none (sim, none). */
int mn_sync_fd(const struct mn_sync *s);
int mn_sync_read(struct mn_sync *s, int64_t until_mono_ns, int64_t *edges, size_t cap, size_t *n);
void mn_sync_set_grid(struct mn_sync *s, const struct mn_grid *grid);

/* Backend constructors (used by mn_sync_open and directly by tests). */
extern const struct mn_sync_ops mn_sync_gpio_ops;
extern const struct mn_sync_ops mn_sync_sim_ops;
extern const struct mn_sync_ops mn_sync_none_ops;
void *mn_sync_gpio_new(const char *chip, uint32_t line, bool falling, char *err, size_t errlen);
void *mn_sync_sim_new(const struct mn_sim_sync_params *params);

/* Truth counters of a sim source, for tests: edges emitted, slots dropped, extras emitted. */
void mn_sync_sim_truth(const void *impl, uint64_t *emitted, uint64_t *missed, uint64_t *spurious);

#endif
