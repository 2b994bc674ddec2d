/* out = M x from the transposed matrix M^T (n_in, width): the matrix-vector products of the
 * compiled loops, for one vector (transposed_product: a chain of products; the stepping loop's steps
 * and event rows take the same sums in registers, transitions.h register_product) or four at once
 * (product_samples: the signal and response rows at the samples), with the same bits; and their
 * matrix-matrix product (matrix_product: the bisection levels' and the yielding mat's operators).
 * Shared by the extension modules. */
#ifndef UPLIFT_PRODUCT_H
#define UPLIFT_PRODUCT_H

#include "buffers.h" /* restrict on every compiler */
#include <math.h>
#include <stdint.h>

/* out[r] = sum_q table[q * stride + r] x[q], r < width: row q of the table (M^T, rows `stride` apart)
 * at a time. The inner loop runs along contiguous memory without a reduction, so it vectorises, and
 * each out[r] sums over q = 0, 1, ... in that order from +0 (the bits do not depend on the vector
 * width, and are a dot product's: the products of zero inputs, skipped, change no such sum). Four
 * rows go through one pass over out when their four inputs are nonzero (the same additions in the
 * same order, a quarter of the loads and stores of out). The products of levels.h (event rates),
 * derivatives.h, _signals.c and _peaks.c, and the stepping loop's wider than register_product takes
 * (transitions.h). */
static inline void strided_product(const double *restrict table, int64_t stride, const double *restrict x, int64_t n,
                                   int64_t width, double *restrict out)
{
    for (int64_t r = 0; r < width; r++) {
        out[r] = 0.0;
    }
    int64_t q = 0;
    while (q < n) {
        if (q + 4 <= n && x[q] != 0.0 && x[q + 1] != 0.0 && x[q + 2] != 0.0 && x[q + 3] != 0.0) {
            const double x0 = x[q], x1 = x[q + 1], x2 = x[q + 2], x3 = x[q + 3];
            const double *row0 = table + q * stride, *row1 = row0 + stride, *row2 = row1 + stride,
                         *row3 = row2 + stride;
            for (int64_t r = 0; r < width; r++) {
                out[r] = (((out[r] + row0[r] * x0) + row1[r] * x1) + row2[r] * x2) + row3[r] * x3;
            }
            q += 4;
            continue;
        }
        const double xq = x[q];
        if (xq != 0.0) {
            const double *row = table + q * stride;
            for (int64_t r = 0; r < width; r++) {
                out[r] += row[r] * xq;
            }
        }
        q++;
    }
}

/* out = M x from M^T (n_in, width), its rows contiguous (strided_product with stride = width). */
static inline void transposed_product(const double *restrict m_t, const double *restrict x, int64_t n_in,
                                      int64_t width, double *restrict out)
{
    strided_product(m_t, width, x, n_in, width, out);
}

/* The rows of signals hermite_peaks reads (10-20 of their 40 columns) have left the cache since
 * evaluate_signals wrote them, and the hardware does not foresee the stride: the cache lines of
 * the columns read are asked for this many samples ahead (a hint, nothing where unsupported). */
#define PREFETCH_SAMPLES 32
#if defined(__GNUC__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif

/* Outputs of product_samples are computed PRODUCT_LANES at a time for PRODUCT_SAMPLES samples at once. */
#define PRODUCT_LANES 8
#define PRODUCT_SAMPLES 4

/* m rounded up to whole PRODUCT_LANES (the width product_samples takes) */
static inline int64_t padded_width(int64_t m)
{
    return (m + PRODUCT_LANES - 1) / PRODUCT_LANES * PRODUCT_LANES;
}

#if defined(__GNUC__)
/* four doubles at any address of a double (GCC and Clang vector extension: one AVX2 register, or
 * two SSE2 ones); loads and stores through it are unaligned */
typedef double product_vector __attribute__((vector_size(4 * sizeof(double)), aligned(sizeof(double)), may_alias));
#define VECTOR_AT(p) (*(product_vector *)(p))
#endif

/* inlined even into a function compiled for another instruction set (the AVX2 version of a HOT_LOOP):
 * a copy of its own, compiled for the baseline set, runs several times slower */
#if defined(__GNUC__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

#if defined(__GNUC__)
/* c[s][l] = sum_k a[s][k] b[k][l] for s < 4 and l < lanes (4 or 8; a compile-time constant where inlined):
 * the sums over k = 0..inner-1 in that order from +0, kept in registers as in product_samples; the rows
 * of a, b and c are a_stride, b_stride and c_stride apart. Written in this order (the four a[s][k], then
 * both halves of row k of b), it ran as fast as the former copies in _levels.c and _soil_operators.c
 * (state_levels and soil_operators, A/B timing); other orders of the same statements, which GCC schedules
 * differently, ran 2-3.5 % slower in one or the other. */
static ALWAYS_INLINE void product_tile(const double *restrict a, int64_t a_stride, const double *restrict b,
                                       int64_t b_stride, double *restrict c, int64_t c_stride, int64_t inner, int lanes)
{
    const product_vector zero = {0.0, 0.0, 0.0, 0.0};
    product_vector a0 = zero, b0 = zero, a1 = zero, b1 = zero, a2 = zero, b2 = zero, a3 = zero, b3 = zero;
    const double *x0 = a, *x1 = x0 + a_stride, *x2 = x1 + a_stride, *x3 = x2 + a_stride;
#pragma GCC unroll 2
    for (int64_t k = 0; k < inner; k++) {
        const double *row = b + k * b_stride;
        const double y0 = x0[k], y1 = x1[k], y2 = x2[k], y3 = x3[k];
        if (lanes == 8) {
            const product_vector low = VECTOR_AT(row), high = VECTOR_AT(row + 4);
            a0 += low * y0;
            b0 += high * y0;
            a1 += low * y1;
            b1 += high * y1;
            a2 += low * y2;
            b2 += high * y2;
            a3 += low * y3;
            b3 += high * y3;
        } else {
            const product_vector low = VECTOR_AT(row);
            a0 += low * y0;
            a1 += low * y1;
            a2 += low * y2;
            a3 += low * y3;
        }
    }
    VECTOR_AT(c) = a0;
    VECTOR_AT(c + c_stride) = a1;
    VECTOR_AT(c + 2 * c_stride) = a2;
    VECTOR_AT(c + 3 * c_stride) = a3;
    if (lanes == 8) {
        VECTOR_AT(c + 4) = b0;
        VECTOR_AT(c + c_stride + 4) = b1;
        VECTOR_AT(c + 2 * c_stride + 4) = b2;
        VECTOR_AT(c + 3 * c_stride + 4) = b3;
    }
}

/* c[l] = sum_k a[k] b[k][l] for l < lanes (4 or 8): one row of product_tile, the rows left over by its four (the
 * sums in registers over k = 0..inner-1 in that order from +0, as there) */
static ALWAYS_INLINE void product_row_tile(const double *restrict a, const double *restrict b, int64_t b_stride,
                                           double *restrict c, int64_t inner, int lanes)
{
    const product_vector zero = {0.0, 0.0, 0.0, 0.0};
    product_vector low = zero, high = zero;
#pragma GCC unroll 2
    for (int64_t k = 0; k < inner; k++) {
        const double *row = b + k * b_stride;
        const double y = a[k];
        low += VECTOR_AT(row) * y;
        if (lanes == 8) {
            high += VECTOR_AT(row + 4) * y;
        }
    }
    VECTOR_AT(c) = low;
    if (lanes == 8) {
        VECTOR_AT(c + 4) = high;
    }
}
#endif

/* c = a b (rows x cols) with a (rows x inner) and b (inner x cols), the rows of each a_stride, b_stride and
 * c_stride apart: the matrix-matrix product of the compiled loops (the bisection levels' Taylor polynomial
 * and squarings, _levels.c; the yielding mat's block exponentials, _soil_operators.c). Four rows at a time
 * in tiles of 8 and then 4 columns (product_tile), the columns left over one entry at a time, the rows left
 * over one row at a time (in tiles of 8 and 4 columns, product_row_tile, where no column is left over); every
 * c[i][j] sums over k = 0..inner-1 in that order from +0, so the bits do not depend on the tiling (nor on
 * skipping zero a[i][k]: their products change no such sum). */
static ALWAYS_INLINE void matrix_product(const double *restrict a, int64_t a_stride, const double *restrict b,
                                         int64_t b_stride, double *restrict c, int64_t c_stride, int64_t rows,
                                         int64_t inner, int64_t cols)
{
    int64_t i = 0;
#if defined(__GNUC__)
    const int64_t wide = cols / 8 * 8, quarter = cols / 4 * 4;
    for (; i + 4 <= rows; i += 4) {
        const double *ai = a + i * a_stride;
        double *ci = c + i * c_stride;
        for (int64_t j = 0; j < wide; j += 8) {
            product_tile(ai, a_stride, b + j, b_stride, ci + j, c_stride, inner, 8);
        }
        if (quarter > wide) {
            product_tile(ai, a_stride, b + wide, b_stride, ci + wide, c_stride, inner, 4);
        }
        for (int64_t s = 0; s < 4; s++) {
            for (int64_t j = quarter; j < cols; j++) {
                double sum = 0.0;
                for (int64_t k = 0; k < inner; k++) {
                    sum += b[k * b_stride + j] * ai[s * a_stride + k];
                }
                ci[s * c_stride + j] = sum;
            }
        }
    }
    for (; i < rows && quarter == cols; i++) { /* the rows left over, where no column is */
        const double *ai = a + i * a_stride;
        double *ci = c + i * c_stride;
        for (int64_t j = 0; j < wide; j += 8) {
            product_row_tile(ai, b + j, b_stride, ci + j, inner, 8);
        }
        if (quarter > wide) {
            product_row_tile(ai, b + wide, b_stride, ci + wide, inner, 4);
        }
    }
#endif
    for (; i < rows; i++) {
        double *restrict ci = c + i * c_stride;
        for (int64_t j = 0; j < cols; j++) {
            ci[j] = 0.0;
        }
        for (int64_t k = 0; k < inner; k++) {
            const double aik = a[i * a_stride + k];
            const double *restrict bk = b + k * b_stride;
            for (int64_t j = 0; j < cols; j++) {
                ci[j] += bk[j] * aik;
            }
        }
    }
}

/* out[s * width + r] = sum_q m_t[q * width + r] x[s * n_in + q] for PRODUCT_SAMPLES samples s at once
 * (the signal and response rows at the samples); width a multiple of PRODUCT_LANES: matrix_product of
 * the samples' rows by M^T, each row of M^T loaded once for the four samples, the sums in registers. The
 * terms are added in the order q = 0, 1, ... from +0, as in transposed_product, so the bits are its
 * bits: the products of zero inputs, which it skips, change no sum (a sum from +0 never becomes -0:
 * x + (-x) is +0). */
static ALWAYS_INLINE void product_samples(const double *restrict m_t, const double *restrict x, int64_t n_in,
                                          int64_t width, double *restrict out)
{
    matrix_product(x, n_in, m_t, width, out, width, PRODUCT_SAMPLES, n_in, width);
}

/* the 1-norm (the largest column sum of magnitudes) of the first `cols` columns of x (rows x cols, its rows
 * `stride` apart): the scaling of the exponentials (_levels.c, pade.h) */
static ALWAYS_INLINE double one_norm(const double *restrict x, int64_t rows, int64_t cols, int64_t stride)
{
    double largest = 0.0;
    for (int64_t q = 0; q < cols; q++) {
        double sum = 0.0;
        for (int64_t p = 0; p < rows; p++) {
            sum += fabs(x[p * stride + q]);
        }
        largest = sum > largest ? sum : largest;
    }
    return largest;
}

#endif
