/* The event functions of the exact engine's stepping loop (_stepping.c): their values G x and
 * rates G A x at a state, and the test for an excursion above zero inside a chunk that its ends
 * miss (docs/exact-engine.md, "Integration"). Included by _stepping.c and transitions.h. */

#ifndef UPLIFT_EVENTS_H
#define UPLIFT_EVENTS_H

#include "buffers.h" /* restrict on every compiler */
#include "product.h" /* ALWAYS_INLINE */
#include <math.h>
#include <stdint.h>

/* an event function counts as crossed above this (they are dimensionless: a force over the weight,
 * a length over the settlement) */
#define EVENT_TOLERANCE 1e-12

static inline double dot(const double *restrict row, const double *restrict x, int64_t n)
{
    double acc = 0.0;
    for (int64_t j = 0; j < n; j++) {
        acc += row[j] * x[j];
    }
    return acc;
}

/* whether some value is above the tolerance (the largest of them is: a NaN is neither), in one pass that
 * vectorises */
static inline int any_above(const double *values, int64_t count)
{
    int above = 0;
    for (int64_t i = 0; i < count; i++) {
        above |= values[i] > EVENT_TOLERANCE;
    }
    return above;
}

/* values[i] = G_i x and rates[i] = (G A)_i x of every event function at the state x, each summed
 * as dot sums (all of them in one pass over x) */
static inline void event_values(const double *events, const double *event_rates, int64_t n_events,
                                const double *restrict x, int64_t n, double *restrict values,
                                double *restrict rates)
{
    int64_t i = 0;
    for (; i + 1 < n_events; i += 2) { /* two events at a time: four sums in flight */
        const double *g0 = events + i * n, *g1 = g0 + n, *r0 = event_rates + i * n, *r1 = r0 + n;
        double v0 = 0.0, v1 = 0.0, s0 = 0.0, s1 = 0.0;
        for (int64_t j = 0; j < n; j++) {
            v0 += g0[j] * x[j];
            s0 += r0[j] * x[j];
            v1 += g1[j] * x[j];
            s1 += r1[j] * x[j];
        }
        values[i] = v0;
        rates[i] = s0;
        values[i + 1] = v1;
        rates[i + 1] = s1;
    }
    for (; i < n_events; i++) {
        const double *g = events + i * n, *r = event_rates + i * n;
        double v = 0.0, d = 0.0;
        for (int64_t j = 0; j < n; j++) {
            v += g[j] * x[j];
            d += r[j] * x[j];
        }
        values[i] = v;
        rates[i] = d;
    }
}

/* Whether some event function passes both tests of excursion_between that clear it (it is falling at the
 * start and rising at the end; the largest Bernstein coefficient of its interpolant, with room for
 * round-off, is at most the tolerance): the same expressions for every row at once, without a branch, so
 * that the loop vectorises (the tests clear almost every row of every chunk). */
static ALWAYS_INLINE int bound_reached(const double *g0s, const double *d0s, const double *g1s, const double *d1s,
                                       int64_t n_events, double length)
{
    int reached = 0;
    for (int64_t i = 0; i < n_events; i++) {
        const double g0 = g0s[i], g1 = g1s[i], d0 = d0s[i] * length, d1 = d1s[i] * length;
        const double third = 1.0 / 3.0, early = g0 + d0 * third, late = g1 - d1 * third;
        const double ends = g0 > g1 ? g0 : g1, inner = early > late ? early : late;
        const double top = (ends > inner ? ends : inner) + 1e-12 * (fabs(g0) + fabs(g1) + fabs(d0) + fabs(d1));
        reached |= !((d0s[i] <= 0.0) & (d1s[i] >= 0.0)) & !(top <= EVENT_TOLERANCE);
    }
    return reached;
}

/* True if some event function, not positive at either end of a chunk of `length` [s], has a
 * positive interior maximum on its cubic Hermite interpolant through its values g0, g1 and exact
 * rates d0, d1 at the ends: a brief excursion the chunk ends would miss. */
static ALWAYS_INLINE int excursion_between(const double *g0s, const double *d0s, const double *g1s,
                                           const double *d1s, int64_t n_events, double length)
{
    if (!bound_reached(g0s, d0s, g1s, d1s, n_events, length)) {
        return 0;
    }
    for (int64_t i = 0; i < n_events; i++) {
        const double g0 = g0s[i], g1 = g1s[i];
        double d0 = d0s[i], d1 = d1s[i];
        if (d0 <= 0.0 && d1 >= 0.0) {
            continue; /* falling at the start and rising at the end: no interior maximum */
        }
        d0 *= length;
        d1 *= length;
        /* p lies below its largest Bernstein coefficient, g0, g0 + d0/3, g1 - d1/3 or g1: no maximum to look
         * for where that bound, with room for round-off (the twin's), stays at most the tolerance (most
         * events of a step; the test below costs a square root and two divisions) */
        const double third = 1.0 / 3.0, early = g0 + d0 * third, late = g1 - d1 * third;
        const double ends = g0 > g1 ? g0 : g1, inner = early > late ? early : late;
        if ((ends > inner ? ends : inner) + 1e-12 * (fabs(g0) + fabs(g1) + fabs(d0) + fabs(d1)) <= EVENT_TOLERANCE) {
            continue;
        }
        double a = 2.0 * (g0 - g1) + d0 + d1;
        double b = 3.0 * (g1 - g0) - 2.0 * d0 - d1;
        /* p'(s) = 3 a s^2 + 2 b s + d0 = 0 */
        if (fabs(a) > 1e-14 * (fabs(b) + fabs(d0))) {
            double disc = b * b - 3.0 * a * d0;
            if (disc < 0.0) {
                continue;
            }
            double root = sqrt(disc);
            double candidates[2] = {(-b + root) / (3.0 * a), (-b - root) / (3.0 * a)};
            for (int k = 0; k < 2; k++) {
                double s = candidates[k];
                if (0.0 < s && s < 1.0 && ((a * s + b) * s + d0) * s + g0 > EVENT_TOLERANCE) {
                    return 1;
                }
            }
        } else if (b != 0.0) {
            double s = -d0 / (2.0 * b);
            if (0.0 < s && s < 1.0 && ((a * s + b) * s + d0) * s + g0 > EVENT_TOLERANCE) {
                return 1;
            }
        }
    }
    return 0;
}

/* excursion_between for the states x, y at the ends of the chunk (values G x, G y and exact rates
 * G A x, G A y); work: 4 n_events doubles */
static int excursion(const double *events, const double *rates, int64_t n_events, const double *x, const double *y,
                     int64_t n, double length, double *work)
{
    double *g0 = work, *d0 = work + n_events, *g1 = work + 2 * n_events, *d1 = work + 3 * n_events;
    event_values(events, rates, n_events, x, n, g0, d0);
    event_values(events, rates, n_events, y, n, g1, d1);
    return excursion_between(g0, d0, g1, d1, n_events, length);
}

#endif
