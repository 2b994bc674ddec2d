/* out = M x from the transposed matrix M^T (n_in, width): the one matrix-vector product of the
 * compiled loops (step operators, signal rows, response rows). Shared by the extension modules. */
#ifndef UPLIFT_PRODUCT_H
#define UPLIFT_PRODUCT_H

#include <stdint.h>

/* Row q of M^T at a time: the inner loop runs along contiguous memory without a reduction, so it
 * vectorises, and each out[r] sums over q = 0, 1, ... in that order (the bits do not depend on
 * the vector width). Zero entries of x are skipped. */
static inline void transposed_product(const double *restrict m_t, const double *restrict x, int64_t n_in,
                                      int64_t width, double *restrict out)
{
    for (int64_t r = 0; r < width; r++) {
        out[r] = 0.0;
    }
    for (int64_t q = 0; q < n_in; q++) {
        const double xq = x[q];
        if (xq != 0.0) {
            const double *row = m_t + q * width;
            for (int64_t r = 0; r < width; r++) {
                out[r] += row[r] * xq;
            }
        }
    }
}

#endif
