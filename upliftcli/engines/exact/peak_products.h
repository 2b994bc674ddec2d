/* The products of hermite_peaks (_peaks.c) at the samples: the responses R y of a sample, the samples gathered
 * PRODUCT_SAMPLES at a time, the stacked responses' products over the basis rows each tile of lanes reads, and the
 * rates of some responses at once. Each sum runs over its terms in the order of the basis from +0 (product.h). */
#ifndef UPLIFT_PEAK_PRODUCTS_H
#define UPLIFT_PEAK_PRODUCTS_H

#include "product.h"
#include <stdint.h>

/* out = R y with y = row[columns], from R^T (n_basis, m); y: n_basis doubles of work space */
static inline void combine(const double *restrict row, const int64_t *restrict columns, const double *restrict rows_t,
                           int64_t n_basis, int64_t m, double *restrict y, double *restrict out)
{
    for (int64_t q = 0; q < n_basis; q++) {
        y[q] = row[columns[q]];
    }
    transposed_product(rows_t, y, n_basis, m, out);
}

/* y[s n_b + q] = values[(i0 + s) k + columns[q]] for the PRODUCT_SAMPLES samples from i0 (zeros past the
 * last sample, n); run: how many of the columns follow the first one by one (contiguous_run) */
static ALWAYS_INLINE void gather_samples(const double *restrict values, const int64_t *restrict columns, int64_t run,
                                         int64_t i0, int64_t n, int64_t k, int64_t n_b, double *restrict y)
{
    if (i0 + PRODUCT_SAMPLES <= n && n_b > 0 && run == n_b) { /* columns[q] = columns[0] + q: a copy */
        for (int64_t s = 0; s < PRODUCT_SAMPLES; s++) {
            const double *row = values + (i0 + s) * k + columns[0];
            for (int64_t q = 0; q < n_b; q++) {
                y[s * n_b + q] = row[q];
            }
        }
        return;
    }
    if (i0 + PRODUCT_SAMPLES <= n) {
        for (int64_t s = 0; s < PRODUCT_SAMPLES; s++) {
            const double *row = values + (i0 + s) * k;
            for (int64_t q = 0; q < n_b; q++) {
                y[s * n_b + q] = row[columns[q]];
            }
        }
        return;
    }
    for (int64_t s = 0; s < PRODUCT_SAMPLES; s++) {
        for (int64_t q = 0; q < n_b; q++) {
            y[s * n_b + q] = i0 + s < n ? values[(i0 + s) * k + columns[q]] : 0.0;
        }
    }
}

/* The basis rows [ranges[2 t], ranges[2 t + 1]) of R^T padded (n_b, width) with a nonzero entry in the lanes of
 * tile t (PRODUCT_LANES lanes from t PRODUCT_LANES); [0, 0) where every entry is zero */
static void tile_ranges(const double *restrict padded, int64_t n_b, int64_t width, int64_t *restrict ranges)
{
    for (int64_t t = 0; t * PRODUCT_LANES < width; t++) {
        int64_t lo = n_b, hi = 0;
        for (int64_t q = 0; q < n_b; q++) {
            for (int64_t j = t * PRODUCT_LANES; j < (t + 1) * PRODUCT_LANES; j++) {
                if (padded[q * width + j] != 0.0) {
                    lo = q < lo ? q : lo;
                    hi = q + 1;
                }
            }
        }
        ranges[2 * t] = hi > lo ? lo : 0;
        ranges[2 * t + 1] = hi > lo ? hi : 0;
    }
}

/* product_samples of R^T padded (n_b, width) by the PRODUCT_SAMPLES samples y (PRODUCT_SAMPLES x n_b), each tile of
 * PRODUCT_LANES lanes over its basis rows alone (tile_ranges): the terms left out have a zero coefficient, so each
 * sum is product_samples' to the bit (its terms in the same order from +0); a yielding run's plastic drifts enter
 * the shears, moments and modal base shears only (a sixth of the stacked responses' products saved) */
static ALWAYS_INLINE void product_ranged(const double *restrict padded, const double *restrict y, int64_t n_b,
                                         int64_t width, const int64_t *restrict ranges, double *restrict out)
{
#if defined(__GNUC__)
    for (int64_t j = 0; j < width; j += PRODUCT_LANES) {
        const int64_t lo = ranges[2 * (j / PRODUCT_LANES)], hi = ranges[2 * (j / PRODUCT_LANES) + 1];
        product_tile(y + lo, n_b, padded + lo * width + j, width, out + j, width, hi - lo, PRODUCT_LANES);
    }
#else
    (void)ranges;
    product_samples(padded, y, n_b, width, out);
#endif
}

/* out_x[r] = sum_q m_t[q width + r] x[q] and out_z[r] = sum_q m_t[q width + r] z[q] for r in [lo, hi), each from +0
 * in the order of q: transposed_product's sums over some of its outputs, two inputs over the same rows of m_t, four
 * rows through one pass, a pass left out where all eight inputs are zero (a zero term changes no sum) */
static ALWAYS_INLINE void lanes_product_pair(const double *restrict m_t, const double *restrict x,
                                             const double *restrict z, int64_t n_in, int64_t width, int64_t lo,
                                             int64_t hi, double *restrict out_x, double *restrict out_z)
{
    for (int64_t r = lo; r < hi; r++) {
        out_x[r] = 0.0;
        out_z[r] = 0.0;
    }
    int64_t q = 0;
    for (; q + 4 <= n_in; q += 4) {
        const double x0 = x[q], x1 = x[q + 1], x2 = x[q + 2], x3 = x[q + 3];
        const double z0 = z[q], z1 = z[q + 1], z2 = z[q + 2], z3 = z[q + 3];
        if (x0 == 0.0 && x1 == 0.0 && x2 == 0.0 && x3 == 0.0 && z0 == 0.0 && z1 == 0.0 && z2 == 0.0 && z3 == 0.0) {
            continue;
        }
        const double *restrict row0 = m_t + q * width, *restrict row1 = row0 + width;
        const double *restrict row2 = row1 + width, *restrict row3 = row2 + width;
        for (int64_t r = lo; r < hi; r++) {
            out_x[r] = (((out_x[r] + row0[r] * x0) + row1[r] * x1) + row2[r] * x2) + row3[r] * x3;
            out_z[r] = (((out_z[r] + row0[r] * z0) + row1[r] * z1) + row2[r] * z2) + row3[r] * z3;
        }
    }
    for (; q < n_in; q++) {
        const double xq = x[q], zq = z[q], *restrict row = m_t + q * width;
        for (int64_t r = lo; r < hi; r++) {
            out_x[r] += row[r] * xq;
            out_z[r] += row[r] * zq;
        }
    }
}

#endif
