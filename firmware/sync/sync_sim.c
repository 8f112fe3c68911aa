/* Simulated trigger: edges on the global grid with Gaussian jitter, lost edges and extra edges,
 * from a seeded generator so a failing test replays exactly. Edges are produced on demand up to
 * the time the node asks for, which keeps them in step with a replay source in both paced and
 * as-fast-as-possible modes. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "sync/sync.h"

struct sim {
    struct mn_sim_sync_params p;
    uint64_t rng;
    bool started;
    int64_t next_slot;
    /* An extra edge decided for the current period but not yet due. */
    bool pending_extra;
    int64_t extra_mono_ns;
    uint64_t emitted, missed, spurious;
};

/* splitmix64: tiny, seedable, good enough for test noise. */
static uint64_t rng_next(struct sim *s)
{
    uint64_t z = (s->rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double rng_uniform(struct sim *s)
{
    return (double)(rng_next(s) >> 11) * (1.0 / 9007199254740992.0);
}

static double rng_gauss(struct sim *s)
{
    double u1 = rng_uniform(s);
    double u2 = rng_uniform(s);
    if (u1 < 1e-300)
        u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

void *mn_sync_sim_new(const struct mn_sim_sync_params *params)
{
    struct sim *s = calloc(1, sizeof(*s));
    if (s == NULL)
        return NULL;
    s->p = *params;
    s->rng = params->seed;
    return s;
}

static int sim_fd(void *impl)
{
    (void)impl;
    return -1;
}

static int sim_read(void *impl, int64_t until, int64_t *edges, size_t cap, size_t *n)
{
    struct sim *s = impl;
    const struct mn_grid *g = &s->p.grid;
    int64_t period = mn_grid_period_ns(g);
    *n = 0;
    if (!s->started) {
        /* Start a little before the first request so its own slot has an edge, never before
         * frame 0: a trigger generator starts at the epoch. */
        int64_t first = mn_grid_slot(g, until) - 2;
        s->next_slot = first < 0 ? 0 : first;
        s->started = true;
    }
    while (*n < cap) {
        if (s->pending_extra) {
            if (s->extra_mono_ns > until)
                break;
            edges[(*n)++] = s->extra_mono_ns;
            s->pending_extra = false;
            s->spurious++;
            continue;
        }
        int64_t nominal = mn_grid_slot_mono(g, s->next_slot);
        /* Never emit an edge before a jittered neighbour could still follow it. */
        if (nominal - 4 * s->p.jitter_ns > until)
            break;
        int64_t t = nominal + (int64_t)llround(rng_gauss(s) * (double)s->p.jitter_ns);
        bool lost = rng_uniform(s) < s->p.missed;
        if (rng_uniform(s) < s->p.spurious) {
            /* Somewhere in the middle of the following period, away from both neighbours. */
            s->pending_extra = true;
            s->extra_mono_ns = nominal + (int64_t)((0.3 + 0.4 * rng_uniform(s)) * (double)period);
        }
        s->next_slot++;
        if (lost) {
            s->missed++;
            continue;
        }
        edges[(*n)++] = t;
        s->emitted++;
    }
    return 0;
}

static void sim_set_grid(void *impl, const struct mn_grid *grid)
{
    struct sim *s = impl;
    s->p.grid = *grid;
    s->started = false;
    s->pending_extra = false;
}

static void sim_close(void *impl)
{
    free(impl);
}

void mn_sync_sim_truth(const void *impl, uint64_t *emitted, uint64_t *missed, uint64_t *spurious)
{
    const struct sim *s = impl;
    *emitted = s->emitted;
    *missed = s->missed;
    *spurious = s->spurious;
}

const struct mn_sync_ops mn_sync_sim_ops = {
    .name = "sim",
    .free_run = false,
    .fd = sim_fd,
    .read = sim_read,
    .set_grid = sim_set_grid,
    .close = sim_close,
};
