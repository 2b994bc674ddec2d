/* The loops of hermite_peaks (_peaks.c) over the responses of a sample, four responses at a time where the
 * GCC and Clang vector type of product.h exists (one at a time elsewhere): the same comparisons, in the same
 * order, as one at a time. */
#ifndef UPLIFT_RESPONSE_LANES_H
#define UPLIFT_RESPONSE_LANES_H

#include "product.h"
#include <math.h>
#include <stdint.h>

#if defined(__GNUC__)
/* four 64-bit lanes of comparison results (all ones or zeros) beside product_vector */
typedef long long peak_mask __attribute__((vector_size(4 * sizeof(long long)), aligned(sizeof(double)), may_alias));
/* |v| of four doubles: the sign bits cleared, as fabs does (a macro: a function returning a vector
 * would change the ABI of the default clone) */
#define SIGN_CLEARED ((peak_mask){0x7fffffffffffffffLL, 0x7fffffffffffffffLL, 0x7fffffffffffffffLL, \
                                  0x7fffffffffffffffLL})
#define VECTOR_FABS(v) ((product_vector)((peak_mask)(v) & SIGN_CLEARED))
#endif

/* best[j] = |row[j]| and where[j] = position where |row[j]| is larger, for j in [from, to) */
static ALWAYS_INLINE void keep_larger(const double *restrict row, int64_t from, int64_t to, double position,
                                      double *restrict best, double *restrict where)
{
    for (int64_t j = from; j < to; j++) {
        const double v = fabs(row[j]);
        const int better = v > best[j];
        best[j] = better ? v : best[j];
        where[j] = better ? position : where[j];
    }
}

/* keep_larger for the `count` samples of a block (rows `width` apart, the first at index i0), in order. Where
 * the vector type exists, four responses at a time: when no sample of the block exceeds their best so far (most
 * blocks: a peak rises rarely) nothing changes, and the check alone is done; else the samples one at a time. */
static ALWAYS_INLINE void keep_larger_block(const double *restrict rows, int64_t width, int64_t count, int64_t i0,
                                            int64_t m, double *restrict best, double *restrict where)
{
    int64_t j = 0;
#if defined(__GNUC__)
    for (; count == PRODUCT_SAMPLES && j + 4 <= m; j += 4) {
        const product_vector b = VECTOR_AT(best + j);
        const peak_mask up = (VECTOR_FABS(VECTOR_AT(rows + j)) > b) | (VECTOR_FABS(VECTOR_AT(rows + width + j)) > b)
                             | (VECTOR_FABS(VECTOR_AT(rows + 2 * width + j)) > b)
                             | (VECTOR_FABS(VECTOR_AT(rows + 3 * width + j)) > b);
        if ((up[0] | up[1] | up[2] | up[3]) != 0) {
            for (int64_t s = 0; s < PRODUCT_SAMPLES; s++) {
                keep_larger(rows + s * width, j, j + 4, (double)(i0 + s), best, where);
            }
        }
    }
#endif
    for (int64_t s = 0; s < count; s++) {
        keep_larger(rows + s * width, j, m, (double)(i0 + s), best, where);
    }
}

/* 1 if |row[j]| >= threshold[j] for some j < m, else 0 (four at a time where the vector type exists) */
static ALWAYS_INLINE int any_at_least(const double *restrict row, const double *restrict threshold, int64_t m)
{
    int64_t j = 0;
    int flag = 0;
#if defined(__GNUC__)
    peak_mask found = {0, 0, 0, 0};
    for (; j + 4 <= m; j += 4) {
        found |= VECTOR_FABS(VECTOR_AT(row + j)) >= VECTOR_AT(threshold + j);
    }
    flag = (found[0] | found[1] | found[2] | found[3]) != 0;
#endif
    for (; j < m; j++) {
        flag |= fabs(row[j]) >= threshold[j];
    }
    return flag;
}

/* 1 if |r0[j]| < threshold[j] and |r1[j]| < threshold[j] for the four j from here (the pass over the
 * intervals skips them: the test it makes one at a time, NaN not below), else 0; 0 without the vector type */
static ALWAYS_INLINE int all_below(const double *restrict r0, const double *restrict r1,
                                   const double *restrict threshold)
{
#if defined(__GNUC__)
    const product_vector t = VECTOR_AT(threshold);
    const peak_mask below = (VECTOR_FABS(VECTOR_AT(r0)) < t) & (VECTOR_FABS(VECTOR_AT(r1)) < t);
    return (below[0] & below[1] & below[2] & below[3]) != 0;
#else
    (void)r0;
    (void)r1;
    (void)threshold;
    return 0;
#endif
}

#endif
