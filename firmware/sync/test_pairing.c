/* Global frame numbering and frame-to-edge pairing: the grid arithmetic, then edges with
 * jitter, missed and spurious edges against known truth, and the simulated trigger source
 * checked against its own truth counters. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "sync/grid.h"
#include "sync/pairing.h"
#include "sync/sync.h"

#define EPOCH INT64_C(1700000000000000000)
#define OFFSET INT64_C(1690000000000000000) /* realtime - monotonic of a booted board */

static struct mn_grid grid_at(uint32_t rate_millihz)
{
    struct mn_grid g = {.epoch_real_ns = EPOCH, .rate_millihz = rate_millihz,
                        .real_minus_mono_ns = OFFSET};
    return g;
}

static void grid_numbers(void **state)
{
    (void)state;
    struct mn_grid g = grid_at(60000); /* 60 Hz: period 16 666 666.67 ns, not an integer */
    int64_t mono_epoch = EPOCH - OFFSET;
    assert_int_equal(mn_grid_slot(&g, mono_epoch), 0);
    /* Slot n's time, computed exactly, maps back to n for a day's worth of frames. */
    for (int64_t n = 0; n < 60 * 86400; n += 9973) {
        int64_t t = mn_grid_slot_mono(&g, n);
        assert_int_equal(mn_grid_slot(&g, t), n);
        assert_int_equal(mn_grid_slot(&g, t + 8000000), n);  /* +8 ms: still slot n */
        assert_int_equal(mn_grid_slot(&g, t + 8700000), n + 1);
    }
    /* One hour in at 60 Hz is frame 216000 exactly. */
    assert_int_equal(mn_grid_slot_mono(&g, 216000), mono_epoch + INT64_C(3600000000000));
    assert_int_equal(mn_grid_slot(&g, mono_epoch - 20000000), -1);
    assert_int_equal(mn_grid_period_ns(&g), 16666667);
    assert_int_equal(mn_grid_rate_millihz(59.94), 59940);
}

/* Deterministic noise for the edge generator. */
static uint64_t rng = 12345;
static double uniform(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static double gauss(void)
{
    double u = uniform();
    if (u < 1e-12)
        u = 1e-12;
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * uniform());
}

static void pairing_with_faults(void **state)
{
    (void)state;
    struct mn_grid g = grid_at(100000); /* 100 Hz */
    const int64_t delay = 3000000;      /* frames stamped 3 ms after their edge */
    const int64_t jitter = 20000;       /* 20 us sd edge jitter */
    struct mn_pairing *p = mn_pairing_new(&g, delay, 25);
    assert_non_null(p);

    const int64_t first = 500, frames = 2000;
    int missed_truth = 0, spurious_truth = 0, unmatched_truth = 0;
    bool edge_present[2600] = {false};
    for (int64_t n = first; n < first + frames; n++) {
        int64_t nominal = mn_grid_slot_mono(&g, n);
        if (uniform() < 0.05) {
            if (n > first) /* before the first edge nothing can be counted as missed */
                missed_truth++;
        } else {
            mn_pairing_add_edge(p, nominal + (int64_t)(gauss() * jitter));
            edge_present[n] = true;
        }
        if (uniform() < 0.03) {
            /* Glitch halfway between two triggers. */
            mn_pairing_add_edge(p, nominal + 5000000 + (int64_t)(uniform() * 1000000));
            spurious_truth++;
        }
        if (edge_present[n] && uniform() < 0.02) {
            /* Doubled edge within the same slot (contact bounce). */
            mn_pairing_add_edge(p, nominal + 150000);
            spurious_truth++;
        }
        /* The frame of slot n, stamped with its own small latency noise. */
        struct mn_pair_result r;
        mn_pairing_match(p, nominal + delay + (int64_t)(gauss() * 50000), &r);
        assert_int_equal(r.frame_number, n);
        assert_int_equal(r.matched, edge_present[n]);
        if (!edge_present[n])
            unmatched_truth++;
        if (r.matched)
            assert_true(llabs(r.trigger_mono_ns - nominal) < 200000);
        else
            assert_int_equal(r.trigger_mono_ns, nominal);
    }
    struct mn_sync_health h;
    mn_pairing_health(p, &h);
    /* A missed edge at the very end is not yet visible as a gap. */
    assert_true(h.missed_edges == (uint32_t)missed_truth ||
                h.missed_edges + 1 == (uint32_t)missed_truth);
    assert_int_equal(h.spurious_edges, spurious_truth);
    assert_int_equal(h.unmatched_frames, unmatched_truth);
    /* Interval jitter of independent edges is sqrt(2) x the edge jitter (EWMA: loose bounds);
     * doubled edges nearer the grid may replace real ones, so allow some excess. */
    assert_true(h.edge_jitter_ns > 15000 && h.edge_jitter_ns < 60000);
    mn_pairing_free(p);
}

static void second_frame_in_slot_is_unmatched(void **state)
{
    (void)state;
    struct mn_grid g = grid_at(100000);
    struct mn_pairing *p = mn_pairing_new(&g, 0, 25);
    int64_t t = mn_grid_slot_mono(&g, 10);
    mn_pairing_add_edge(p, t);
    struct mn_pair_result r;
    mn_pairing_match(p, t + 100000, &r);
    assert_true(r.matched);
    assert_int_equal(r.frame_number, 10);
    mn_pairing_match(p, t + 200000, &r); /* a camera running faster than the trigger */
    assert_false(r.matched);
    struct mn_sync_health h;
    mn_pairing_health(p, &h);
    assert_int_equal(h.unmatched_frames, 1);
    /* A frame far from its edge (outside the 25 % window) is not paired with it. */
    mn_pairing_add_edge(p, mn_grid_slot_mono(&g, 11));
    mn_pairing_match(p, mn_grid_slot_mono(&g, 11) + 3000000, &r);
    assert_false(r.matched);
    assert_int_equal(r.frame_number, 11);
    mn_pairing_free(p);
}

static void new_epoch_and_free_run(void **state)
{
    (void)state;
    struct mn_grid g = grid_at(50000);
    struct mn_pairing *p = mn_pairing_new(&g, 1000000, 20);
    struct mn_pair_result r;
    mn_pairing_free_run(p, mn_grid_slot_mono(&g, 77) + 1000000 + 3000000, &r);
    assert_int_equal(r.frame_number, 77);
    assert_false(r.matched);
    /* Before the epoch: negative numbers, which the node drops. */
    mn_pairing_free_run(p, mn_grid_slot_mono(&g, -3) + 1000000, &r);
    assert_int_equal(r.frame_number, -3);
    /* A new epoch renumbers: the old slot 100 is slot 0 of the new session. */
    int64_t t100 = mn_grid_slot_mono(&g, 100);
    mn_pairing_add_edge(p, t100);
    struct mn_grid g2 = g;
    g2.epoch_real_ns = g.epoch_real_ns + 2 * INT64_C(1000000000); /* 100 periods at 50 Hz */
    mn_pairing_set_grid(p, &g2);
    mn_pairing_match(p, t100 + 1000000, &r);
    assert_false(r.matched); /* the edge belonged to the old session */
    assert_int_equal(r.frame_number, 0);
    mn_pairing_add_edge(p, mn_grid_slot_mono(&g2, 1));
    mn_pairing_match(p, mn_grid_slot_mono(&g2, 1) + 1000000, &r);
    assert_true(r.matched);
    assert_int_equal(r.frame_number, 1);
    assert_null(mn_pairing_new(&g, 0, 50)); /* a window of half a period is ambiguous */
    mn_pairing_free(p);
}

/* The sim source's own truth must equal what the pairing measures from its edges. */
static void sim_source_truth(void **state)
{
    (void)state;
    struct mn_sim_sync_params sp = {
        .grid = grid_at(200000), .jitter_ns = 30000, .missed = 0.1, .spurious = 0.05, .seed = 7};
    void *sim = mn_sync_sim_new(&sp);
    assert_non_null(sim);
    struct mn_pairing *p = mn_pairing_new(&sp.grid, 0, 25);
    int64_t edges[16];
    int unmatched = 0;
    int64_t start_slot = 1000;
    for (int64_t n = start_slot; n < start_slot + 5000; n++) {
        int64_t frame_t = mn_grid_slot_mono(&sp.grid, n);
        int64_t until = frame_t + mn_grid_period_ns(&sp.grid) / 4;
        for (;;) {
            size_t got = 0;
            assert_int_equal(mn_sync_sim_ops.read(sim, until, edges, 16, &got), 0);
            for (size_t i = 0; i < got; i++)
                mn_pairing_add_edge(p, edges[i]);
            if (got < 16)
                break;
        }
        struct mn_pair_result r;
        mn_pairing_match(p, frame_t, &r);
        assert_int_equal(r.frame_number, n);
        if (!r.matched)
            unmatched++;
    }
    uint64_t emitted, missed, spurious;
    mn_sync_sim_truth(sim, &emitted, &missed, &spurious);
    struct mn_sync_health h;
    mn_pairing_health(p, &h);
    assert_true(missed > 300 && missed < 700);     /* ~10 % of 5000 */
    assert_true(spurious > 120 && spurious < 380); /* ~5 % */
    assert_int_equal(h.spurious_edges, spurious);
    assert_int_equal(h.edges, emitted);
    /* Every missed slot is one unmatched frame; the pairing counts gaps between its edges. */
    assert_true((uint64_t)unmatched <= missed && missed - (uint64_t)unmatched <= 3);
    assert_true(h.missed_edges <= missed && missed - h.missed_edges <= 3);
    assert_true(h.edge_jitter_ns > 25000 && h.edge_jitter_ns < 70000);
    mn_pairing_free(p);
    mn_sync_sim_ops.close(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(grid_numbers),
        cmocka_unit_test(pairing_with_faults),
        cmocka_unit_test(second_frame_in_slot_is_unmatched),
        cmocka_unit_test(new_epoch_and_free_run),
        cmocka_unit_test(sim_source_truth),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
