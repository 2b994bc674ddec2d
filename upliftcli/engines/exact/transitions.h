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

/* out = M x from the transposed matrix M^T (n, n) (product.h) */
static inline void matvec(const double *restrict matrix_t, const double *restrict x, double *restrict out, int64_t n)
{
    transposed_product(matrix_t, x, n, n, out);
}

/* the contact states and elements of one run (see stepping_kernels.States, Elements, Grid) */
typedef struct {
    const double *ops, *events, *rates, *matrices;
    const int64_t *patterns;
    int64_t count, n_events, n, levels;
    const int64_t *z_index;
    const double *lift_rows;
    const unsigned char *damped;
    int64_t all_lifted;
    int allow_flight;
} Model;

static inline const double *op_of(const Model *m, int64_t state, int64_t level)
{
    return m->ops + (state * (m->levels + 1) + level) * m->n * m->n;
}

/* Bracket the first crossing inside the chunk x -> trial by bisection with the finer exact
 * operators down to h / 2^L (left, right: its ends), then place it by linear interpolation of
 * each event function inside that last sliver. Returns start; *fraction: the crossing is at
 * start + fraction * chunk[L] from x. */
static double crossing(const Model *m, int64_t state, const double *x, int64_t level, const double *chunk,
                       double *left, double *trial, double *right, double *fraction)
{
    const int64_t n = m->n, n_levels = m->levels;
    const double *events = m->events + state * m->n_events * n;
    memcpy(left, x, n * sizeof(double));
    double start = 0.0;
    for (int64_t j = level + 1; j <= n_levels; j++) {
        matvec(op_of(m, state, j), left, trial, n);
        if (max_event(events, m->n_events, trial, n) <= EVENT_TOLERANCE) {
            memcpy(left, trial, n * sizeof(double));
            start += chunk[j];
        }
    }
    matvec(op_of(m, state, n_levels), left, right, n);
    /* earliest crossing inside the last sliver, linear interpolation of each g_i */
    double best = 1.0;
    for (int64_t i = 0; i < m->n_events; i++) {
        double gl = dot(events + i * n, left, n);
        double gr = dot(events + i * n, right, n);
        if (gr > EVENT_TOLERANCE) {
            double f = 0.0;
            if (gr > gl) {
                f = (EVENT_TOLERANCE - gl) / (gr - gl);
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
 * where the edge is (k z + c z' = 0 from there). Updates x. */
static int64_t switch_pattern(const Model *m, int64_t state, int64_t pattern, double *x, const double *right)
{
    const int64_t n = m->n;
    const double *events = m->events + state * m->n_events * n;
    for (int64_t i = 0; i < m->n_events; i++) {
        if (dot(events + i * n, x, n) >= -1e-9 && dot(events + i * n, right, n) > EVENT_TOLERANCE) {
            pattern ^= (int64_t)1 << i;
            if ((pattern >> i) & 1) {
                double value = 0.0;
                if (m->damped[i]) {
                    value = dot(m->lift_rows + i * n, x, n);
                }
                x[m->z_index[i]] = value;
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
static void classify(const Model *m, int64_t s, int64_t index_acceleration, int64_t index_slope,
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

#endif
