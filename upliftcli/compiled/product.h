/* out = M x from the transposed matrix M^T (n_in, width): the one matrix-vector product of the
 * compiled loops (step operators, signal rows, response rows). Shared by the extension modules. */
#ifndef UPLIFT_PRODUCT_H
#define UPLIFT_PRODUCT_H

#include <stdint.h>

/* Row q of M^T at a time: the inner loop runs along contiguous memory without a reduction, so it
 * vectorises, and each out[r] sums over q = 0, 1, ... in that order (the bits do not depend on
 * the vector width). Four rows go through one pass over out when their four inputs are nonzero
 * (the same additions in the same order, a quarter of the loads and stores of out); zero inputs
 * are skipped. */
static inline void transposed_product(const double *restrict m_t, const double *restrict x, int64_t n_in,
                                      int64_t width, double *restrict out)
{
    for (int64_t r = 0; r < width; r++) {
        out[r] = 0.0;
    }
    int64_t q = 0;
    while (q < n_in) {
        if (q + 4 <= n_in && x[q] != 0.0 && x[q + 1] != 0.0 && x[q + 2] != 0.0 && x[q + 3] != 0.0) {
            const double x0 = x[q], x1 = x[q + 1], x2 = x[q + 2], x3 = x[q + 3];
            const double *row0 = m_t + q * width, *row1 = row0 + width, *row2 = row1 + width, *row3 = row2 + width;
            for (int64_t r = 0; r < width; r++) {
                out[r] = (((out[r] + row0[r] * x0) + row1[r] * x1) + row2[r] * x2) + row3[r] * x3;
            }
            q += 4;
            continue;
        }
        const double xq = x[q];
        if (xq != 0.0) {
            const double *row = m_t + q * width;
            for (int64_t r = 0; r < width; r++) {
                out[r] += row[r] * xq;
            }
        }
        q++;
    }
}

#endif
