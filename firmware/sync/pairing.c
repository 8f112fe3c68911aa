/* Frame-to-edge pairing and sync health (see pairing.h for the assumptions). Accepted edges sit
 * in a ring indexed by slot, so pairing a frame is one lookup. */
#include "sync/pairing.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

struct edge {
    int64_t slot;
    int64_t mono_ns;
    bool valid;
    bool used; /* already paired with a frame: a second frame in the slot is unmatched */
};

struct mn_pairing {
    struct mn_grid grid;
    int64_t delay_ns;
    uint32_t window_pct;
    int64_t window_ns;
    struct edge ring[MN_PAIRING_EDGES];
    bool have_last;
    int64_t last_slot;
    int64_t last_residual_ns;
    double jitter_sq_ns2; /* EWMA of squared interval deviations */
    struct mn_sync_health health;
};

static void apply_grid(struct mn_pairing *p, const struct mn_grid *grid)
{
    p->grid = *grid;
    p->window_ns = mn_grid_period_ns(grid) * p->window_pct / 100;
    for (size_t i = 0; i < MN_PAIRING_EDGES; i++)
        p->ring[i].valid = false;
    p->have_last = false;
}

struct mn_pairing *mn_pairing_new(const struct mn_grid *grid, int64_t trigger_delay_ns,
                                  uint32_t window_pct)
{
    if (grid->rate_millihz == 0 || window_pct < 1 || window_pct > 49) {
        errno = EINVAL;
        return NULL;
    }
    struct mn_pairing *p = calloc(1, sizeof(*p));
    if (p == NULL)
        return NULL;
    p->delay_ns = trigger_delay_ns;
    p->window_pct = window_pct;
    apply_grid(p, grid);
    return p;
}

void mn_pairing_free(struct mn_pairing *p)
{
    free(p);
}

void mn_pairing_set_grid(struct mn_pairing *p, const struct mn_grid *grid)
{
    if (grid->epoch_real_ns == p->grid.epoch_real_ns &&
        grid->rate_millihz == p->grid.rate_millihz) {
        /* Only the clock offset moved (a refresh): stored slots stay valid. */
        p->grid = *grid;
        return;
    }
    apply_grid(p, grid);
}

static struct edge *ring_at(struct mn_pairing *p, int64_t slot)
{
    /* slot may be negative before the epoch; keep the index in range. */
    int64_t i = slot % MN_PAIRING_EDGES;
    if (i < 0)
        i += MN_PAIRING_EDGES;
    return &p->ring[i];
}

static void count_add(uint32_t *counter, int64_t n)
{
    int64_t sum = (int64_t)*counter + n;
    *counter = sum > UINT32_MAX ? UINT32_MAX : (uint32_t)sum;
}

void mn_pairing_add_edge(struct mn_pairing *p, int64_t edge_mono_ns)
{
    int64_t slot = mn_grid_slot(&p->grid, edge_mono_ns);
    int64_t residual = edge_mono_ns - mn_grid_slot_mono(&p->grid, slot);
    if (llabs(residual) > p->window_ns) {
        count_add(&p->health.spurious_edges, 1); /* between slots: glitch or crosstalk */
        return;
    }
    if (p->have_last) {
        if (slot < p->last_slot) {
            count_add(&p->health.spurious_edges, 1);
            return;
        }
        if (slot == p->last_slot) {
            /* Two edges in one slot: one of them is spurious; keep the one nearer the grid. */
            count_add(&p->health.spurious_edges, 1);
            struct edge *e = ring_at(p, slot);
            if (llabs(residual) < llabs(p->last_residual_ns) && !e->used) {
                e->mono_ns = edge_mono_ns;
                p->last_residual_ns = residual;
            }
            return;
        }
        count_add(&p->health.missed_edges, slot - p->last_slot - 1);
        /* Interval deviation from whole periods = difference of the two residuals. */
        double dev = (double)(residual - p->last_residual_ns);
        p->jitter_sq_ns2 += (dev * dev - p->jitter_sq_ns2) / 16.0;
    }
    struct edge *e = ring_at(p, slot);
    e->slot = slot;
    e->mono_ns = edge_mono_ns;
    e->valid = true;
    e->used = false;
    p->have_last = true;
    p->last_slot = slot;
    p->last_residual_ns = residual;
    p->health.edges++;
}

void mn_pairing_match(struct mn_pairing *p, int64_t capture_mono_ns, struct mn_pair_result *out)
{
    int64_t expected = capture_mono_ns - p->delay_ns;
    int64_t slot = mn_grid_slot(&p->grid, expected);
    struct edge *e = ring_at(p, slot);
    if (e->valid && e->slot == slot && !e->used && llabs(e->mono_ns - expected) <= p->window_ns) {
        e->used = true;
        out->frame_number = slot;
        out->trigger_mono_ns = e->mono_ns;
        out->matched = true;
        return;
    }
    count_add(&p->health.unmatched_frames, 1);
    out->frame_number = slot;
    out->trigger_mono_ns = mn_grid_slot_mono(&p->grid, slot);
    out->matched = false;
}

void mn_pairing_free_run(const struct mn_pairing *p, int64_t capture_mono_ns,
                         struct mn_pair_result *out)
{
    int64_t slot = mn_grid_slot(&p->grid, capture_mono_ns - p->delay_ns);
    out->frame_number = slot;
    out->trigger_mono_ns = mn_grid_slot_mono(&p->grid, slot);
    out->matched = false;
}

void mn_pairing_health(const struct mn_pairing *p, struct mn_sync_health *out)
{
    *out = p->health;
    double rms = sqrt(p->jitter_sq_ns2);
    out->edge_jitter_ns = rms > UINT32_MAX ? UINT32_MAX : (uint32_t)lround(rms);
}
