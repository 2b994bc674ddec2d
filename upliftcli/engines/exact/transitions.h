/* The contact states of one run as the stepping loop reads them (Model), and the location of a
 * contact transition inside a step: the bisection with the finer exact operators, the new contact
 * pattern at the crossing, and which event functions a state has (docs/exact-engine.md,
 * "Integration"). Included by _stepping.c alone (stepping_kernels.py: the method and arguments;
 * stepping_numpy.py: the numpy twin). */

#ifndef UPLIFT_TRANSITIONS_H
#define UPLIFT_TRANSITIONS_H

#include "buffers.h" /* restrict on every compiler */
#include "events.h"
#include "product.h"
#include <math.h>
#include <stdint.h>

enum { VALUES = 1, RATES = 2 }; /* what integrate knows of the event functions at x */

#if defined(__GNUC__)
/* the widest product register_product keeps in registers: 12 vectors of four outputs, and three more (the
 * README example's event tables: 40 outputs rigid, 44 bonded and uplift) */
#define REGISTER_VECTORS 12

/* strided_product (product.h) for width = 4 vectors + extra outputs, the outputs held in registers for the
 * whole product (vectors a compile-time constant where inlined): a row of the table costs a broadcast, a
 * multiplication and an addition per four outputs, where strided_product loads and stores its outputs for
 * every four rows, tests the inputs of four rows and loops over each row's outputs (the 33 x 33 steps and
 * 33 x 40 event tables of the README example's rigid yielding run: 23.4 M instructions to 15.1 M, and
 * their memset of the outputs). The sums are strided_product's: each output summed over q = 0, 1, ... in
 * that order from +0 (the vector lanes are independent; no fused multiply-add: setup.py), so the same
 * bits: a pair of zero inputs is skipped, and a zero input beside a nonzero one adds a zero product of
 * its (finite) row, which changes no such sum, as those strided_product skips. */
static ALWAYS_INLINE void registers_of(const double *restrict table, int64_t stride, const double *restrict x,
                                       int64_t n, double *restrict out, const int vectors, const int extra)
{
    const product_vector zero = {0.0, 0.0, 0.0, 0.0};
    product_vector sums[REGISTER_VECTORS];
    double tail[3] = {0.0, 0.0, 0.0};
    for (int v = 0; v < vectors; v++) {
        sums[v] = zero;
    }
    int64_t q = 0;
    for (; q + 2 <= n; q += 2) { /* two rows at a time (a pair of zero inputs skipped) */
        const double x0 = x[q], x1 = x[q + 1];
        if (x0 == 0.0 && x1 == 0.0) {
            continue;
        }
        const double *row0 = table + q * stride, *row1 = row0 + stride;
        for (int v = 0; v < vectors; v++) {
            sums[v] = (sums[v] + VECTOR_AT(row0 + 4 * v) * x0) + VECTOR_AT(row1 + 4 * v) * x1;
        }
        for (int e = 0; e < extra; e++) {
            tail[e] = (tail[e] + row0[4 * vectors + e] * x0) + row1[4 * vectors + e] * x1;
        }
    }
    if (q < n && x[q] != 0.0) {
        const double *row = table + q * stride;
        for (int v = 0; v < vectors; v++) {
            sums[v] += VECTOR_AT(row + 4 * v) * x[q];
        }
        for (int e = 0; e < extra; e++) {
            tail[e] += row[4 * vectors + e] * x[q];
        }
    }
    for (int v = 0; v < vectors; v++) {
        VECTOR_AT(out + 4 * v) = sums[v];
    }
    for (int e = 0; e < extra; e++) {
        out[4 * vectors + e] = tail[e];
    }
}

/* out[r] = sum_q table[q * stride + r] x[q], r < width: strided_product, in registers (registers_of, one
 * copy for each width) up to 51 outputs */
HOT_LOOP static void register_product(const double *restrict table, int64_t stride, const double *restrict x,
                                      int64_t n, int64_t width, double *restrict out)
{
    switch (width) {
#define WIDTH(k, e)                                                                                                    \
    case 4 * (k) + (e):                                                                                                \
        registers_of(table, stride, x, n, out, k, e);                                                                  \
        return;
#define WIDTHS(k) WIDTH(k, 0) WIDTH(k, 1) WIDTH(k, 2) WIDTH(k, 3)
        WIDTH(0, 1) WIDTH(0, 2) WIDTH(0, 3) WIDTHS(1) WIDTHS(2) WIDTHS(3) WIDTHS(4) WIDTHS(5) WIDTHS(6) WIDTHS(7)
        WIDTHS(8) WIDTHS(9) WIDTHS(10) WIDTHS(11) WIDTHS(12)
#undef WIDTHS
#undef WIDTH
    default:
        strided_product(table, stride, x, n, width, out);
    }
}
#else
#define register_product strided_product
#endif

/* out = M x from the transposed matrix M^T (n, n) (register_product) */
static inline void matvec(const double *restrict matrix_t, const double *restrict x, double *restrict out, int64_t n)
{
    register_product(matrix_t, n, x, n, n, out);
}

/* the contact states and elements of one run (see stepping_kernels.States, Elements, Grid) */
typedef struct {
    const double *ops, *events, *rates, *matrices;
    const int64_t *slots, *patterns; /* slots: per state, its operators' slot of ops (states of one A share one) */
    int64_t count, n_events, n, levels;
    int64_t room; /* the states the loop's work space covers: count, or the most it may build (builds.h) */
    const int64_t *z_index;
    const double *lift_rows;
    const unsigned char *damped;
    int64_t all_lifted;
    int allow_flight;
} Model;

static inline const double *op_of(const Model *m, int64_t state, int64_t level)
{
    return m->ops + (m->slots[state] * (m->levels + 1) + level) * m->n * m->n;
}

/* The event rows of the states a call of integrate enters, transposed for strided_product (product.h):
 * slot k holds table[q * 2 n_e + r] = G_s[r, q] and table[q * 2 n_e + n_e + r] = (G A)_s[r, q], so that
 * the values and rates of every event function come from one product. A state's table is made when
 * integrate enters it (n * 2 n_e copies, about one evaluation of its events) in the next of `slots`
 * slots, round robin (a state entered again while its slot is still its own is not copied again). */
#define TABLE_SLOTS 8

typedef struct {
    double *tables;   /* slots * n * 2 n_e */
    int64_t *slot_of; /* per state: its slot, -1 without one */
    int64_t *owner;   /* per slot: its state, -1 without one */
    int64_t slots, next;
} EventTables;

/* the table of state s (made in a slot if it has none) */
static ALWAYS_INLINE const double *event_table(const Model *m, EventTables *t, int64_t s)
{
    const int64_t n = m->n, n_e = m->n_events, width = 2 * n_e;
    if (t->slot_of[s] >= 0) {
        return t->tables + t->slot_of[s] * n * width;
    }
    const int64_t k = t->next;
    t->next = (k + 1) % t->slots;
    if (t->owner[k] >= 0) {
        t->slot_of[t->owner[k]] = -1;
    }
    t->owner[k] = s;
    t->slot_of[s] = k;
    double *table = t->tables + k * n * width;
    const double *events = m->events + s * n_e * n, *rates = m->rates + s * n_e * n;
    for (int64_t i = 0; i < n_e; i++) {
        for (int64_t q = 0; q < n; q++) {
            table[q * width + i] = events[i * n + q];
            table[q * width + n_e + i] = rates[i * n + q];
        }
    }
    return table;
}

/* values[i] = G_i x of the n_e event functions from their table */
static inline void table_values(const double *table, int64_t n_e, const double *x, int64_t n, double *values)
{
    register_product(table, 2 * n_e, x, n, n_e, values);
}

/* the rows of `values` above the tolerance into rows; their count */
static inline int64_t rows_above(const double *values, int64_t n_e, int64_t *rows)
{
    int64_t count = 0;
    for (int64_t i = 0; i < n_e; i++) {
        if (values[i] > EVENT_TOLERANCE) {
            rows[count++] = i;
        }
    }
    return count;
}

/* whether one of the `count` rows is above the tolerance at x, each value summed as table_values sums it
 * (over q = 0, 1, ... from +0: the same bits; the terms of zero components, which it skips, add a zero that
 * changes no such sum) */
static inline int some_above(const double *table, int64_t n_e, const double *x, int64_t n, const int64_t *rows,
                             int64_t count)
{
    for (int64_t k = 0; k < count; k++) {
        const double *column = table + rows[k];
        double value = 0.0;
        for (int64_t q = 0; q < n; q++) {
            value += column[q * 2 * n_e] * x[q];
        }
        if (value > EVENT_TOLERANCE) {
            return 1;
        }
    }
    return 0;
}

/* Bracket the first crossing inside the chunk x -> trial by bisection with the finer exact
 * operators down to h / 2^L (left, right: its ends), then place it by linear interpolation of
 * each event function inside that last sliver. Returns start; *fraction: the crossing is at
 * start + fraction * chunk[L] from x. table: the state's (EventTables); g_x, g_end: the event values at x
 * and at the chunk's end; work: 3 n_e doubles, the values at right in work + n_e on return (switch_pattern).
 * A bisection point is tried on the rows last seen above the tolerance first (some_above): where one of
 * them is above it, so is the largest of all (about half the points, whose other rows are not evaluated);
 * elsewhere on all rows, as before. What is known already is not computed again (the same products of the
 * same vectors: the same bits): the values at left (x's, or those of the point it moved to) and, where the
 * finest point did not move it, right (that point) and its values where they were evaluated. */
static ALWAYS_INLINE double crossing(const Model *m, int64_t state, const double *table, const double *x,
                                     int64_t level, const double *chunk, const double *g_x, const double *g_end,
                                     double *left, double *trial, double *right, double *fraction, double *work)
{
    const int64_t n = m->n, n_levels = m->levels, n_e = m->n_events;
    double *gl = work, *gr = work + n_e;
    int64_t *above = (int64_t *)(work + 2 * n_e), n_above = rows_above(g_end, n_e, above);
    memcpy(left, x, n * sizeof(double));
    memcpy(gl, g_x, n_e * sizeof(double));
    double start = 0.0;
    int finest = 0; /* 1: trial is the finest point from left (right), 2: and gr its values */
    for (int64_t j = level + 1; j <= n_levels; j++) {
        matvec(op_of(m, state, j), left, trial, n);
        finest = j == n_levels;
        if (some_above(table, n_e, trial, n, above, n_above)) {
            continue;
        }
        table_values(table, n_e, trial, n, gr);
        if (!any_above(gr, n_e)) {
            memcpy(left, trial, n * sizeof(double));
            memcpy(gl, gr, n_e * sizeof(double));
            start += chunk[j];
            finest = 0;
        } else {
            n_above = rows_above(gr, n_e, above);
            finest *= 2;
        }
    }
    if (finest) {
        memcpy(right, trial, n * sizeof(double));
    } else {
        matvec(op_of(m, state, n_levels), left, right, n);
    }
    /* earliest crossing inside the last sliver, linear interpolation of each g_i */
    if (finest != 2) {
        table_values(table, n_e, right, n, gr);
    }
    double best = 1.0;
    for (int64_t i = 0; i < n_e; i++) {
        if (gr[i] > EVENT_TOLERANCE) {
            double f = 0.0;
            if (gr[i] > gl[i]) {
                f = (EVENT_TOLERANCE - gl[i]) / (gr[i] - gl[i]);
            }
            if (f < 0.0) {
                f = 0.0;
            }
            if (f < best) {
                best = f;
            }
        }
    }
    *fraction = best;
    return start;
}

/* The new contact pattern at the crossing x: every element whose event function has reached
 * zero there (and is positive at the sliver's end) switches; a lifting element's top starts
 * where the edge is (k z + c z' = 0 from there). Updates x (the rows after a switch are evaluated
 * at the updated x, one at a time). table: the state's (EventTables); work: 2 n_e doubles, the
 * values at the sliver's end in work + n_e (crossing's). */
static ALWAYS_INLINE int64_t switch_pattern(const Model *m, int64_t state, const double *table, int64_t pattern,
                                            double *x, double *work)
{
    const int64_t n = m->n, n_e = m->n_events;
    const double *events = m->events + state * n_e * n;
    double *gx = work;
    const double *gr = work + n_e;
    table_values(table, n_e, x, n, gx);
    int updated = 0;
    for (int64_t i = 0; i < n_e; i++) {
        const double at_x = updated ? dot(events + i * n, x, n) : gx[i];
        if (at_x >= -1e-9 && gr[i] > EVENT_TOLERANCE) {
            pattern ^= (int64_t)1 << i;
            if ((pattern >> i) & 1) {
                double value = 0.0;
                if (m->damped[i]) {
                    value = dot(m->lift_rows + i * n, x, n);
                }
                x[m->z_index[i]] = value;
                updated = 1;
            }
        }
    }
    return pattern;
}

/* active[s] before classify has looked at state s */
#define UNCLASSIFIED 2

/* Whether state s has event functions (active[s]: a bonded run's are all zero) and which of their
 * values and rates do not depend on the ground acceleration and its slope (ground_free[s]: VALUES,
 * RATES), unless already known (active[s] != UNCLASSIFIED). */
static ALWAYS_INLINE void classify(const Model *m, int64_t s, int64_t index_acceleration, int64_t index_slope,
                                   unsigned char *active, unsigned char *ground_free)
{
    if (active[s] != UNCLASSIFIED) {
        return;
    }
    const int64_t n = m->n;
    const double *events = m->events + s * m->n_events * n, *rates = m->rates + s * m->n_events * n;
    active[s] = 0;
    int values_free = 1, rates_free = 1;
    for (int64_t i = 0; i < m->n_events * n && !active[s]; i++) { /* stops at the first nonzero entry */
        active[s] = events[i] != 0.0;
    }
    for (int64_t i = 0; i < m->n_events; i++) {
        const int64_t a = i * n + index_acceleration, b = i * n + index_slope;
        values_free &= events[a] == 0.0 && events[b] == 0.0;
        rates_free &= rates[a] == 0.0 && rates[b] == 0.0;
    }
    ground_free[s] = (unsigned char)((values_free ? VALUES : 0) | (values_free && rates_free ? RATES : 0));
}

/* the slots of EventTables: none without event rows */
static inline int64_t table_slots(const Model *m)
{
    return m->n_events ? (m->room < TABLE_SLOTS ? m->room : TABLE_SLOTS) : 0;
}

/* Classify state s as integrate enters it (classify) and return its event table (event_table), NULL
 * for a state without event functions. */
static ALWAYS_INLINE const double *entered(const Model *m, int64_t s, int64_t index_acceleration,
                                          int64_t index_slope, unsigned char *active, unsigned char *ground_free,
                                          EventTables *t)
{
    classify(m, s, index_acceleration, index_slope, active, ground_free);
    return active[s] ? event_table(m, t, s) : NULL;
}

#endif
