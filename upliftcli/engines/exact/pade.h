/* The matrix exponential of a dense n x n matrix in C: scaling and squaring with the [13/13] Pade
 * approximant (expm.py's algorithm, N. J. Higham 2005), its products product.h's matrix_product. Used
 * by _soil_operators.c for the block exponentials of a yielding mat (docs/theory.md 14.3). */
#ifndef UPLIFT_PADE_H
#define UPLIFT_PADE_H

#include "buffers.h"
#include "product.h"
#include <math.h>
#include <stdint.h>

/* the coefficients b_0..b_13 of the [13/13] Pade approximant of exp, and the largest 1-norm at which
 * it is accurate to the unit round-off (expm.py) */
static const double PADE[14] = {64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0,
                                129060195264000.0, 10559470521600.0, 670442572800.0, 33522128640.0,
                                1323241920.0, 40840800.0, 960960.0, 16380.0, 182.0, 1.0};
static const double THETA_13 = 5.371920351148152;

/* c = a b (n x n, row-major): product.h's matrix_product (four rows at a time in tiles of 8 and 4 columns,
 * every sum over k in k order from +0) */
HOT_LOOP static void product(const double *restrict a, const double *restrict b, double *restrict c, int64_t n)
{
    matrix_product(a, n, b, n, c, n, n, n, n);
}

/* out = w_0 m_0 + w_1 m_1 + w_2 m_2 + w_3 I (n x n) */
static void combine(const double *m0, double w0, const double *m1, double w1, const double *m2, double w2, double w3,
                    double *out, int64_t n)
{
    for (int64_t q = 0; q < n * n; q++) {
        out[q] = w0 * m0[q] + w1 * m1[q] + w2 * m2[q];
    }
    for (int64_t i = 0; i < n; i++) {
        out[i * n + i] += w3;
    }
}

/* x := p^-1 x (n x n each, p overwritten by its LU factors with partial pivoting); 0 if p is singular */
HOT_LOOP static int solve(double *p, double *x, int64_t n)
{
    for (int64_t k = 0; k < n; k++) {
        int64_t pivot = k;
        for (int64_t i = k + 1; i < n; i++) {
            if (fabs(p[i * n + k]) > fabs(p[pivot * n + k])) {
                pivot = i;
            }
        }
        if (p[pivot * n + k] == 0.0) {
            return 0;
        }
        if (pivot != k) {
            for (int64_t j = 0; j < n; j++) {
                double t = p[k * n + j];
                p[k * n + j] = p[pivot * n + j];
                p[pivot * n + j] = t;
                t = x[k * n + j];
                x[k * n + j] = x[pivot * n + j];
                x[pivot * n + j] = t;
            }
        }
        for (int64_t i = k + 1; i < n; i++) {
            const double f = p[i * n + k] / p[k * n + k];
            if (f == 0.0) {
                continue;
            }
            for (int64_t j = k + 1; j < n; j++) {
                p[i * n + j] -= f * p[k * n + j];
            }
            for (int64_t j = 0; j < n; j++) {
                x[i * n + j] -= f * x[k * n + j];
            }
        }
    }
    for (int64_t k = n - 1; k >= 0; k--) {  /* row k of x at a time, along contiguous memory */
        double *restrict xk = x + k * n;
        for (int64_t i = k + 1; i < n; i++) {
            const double f = p[k * n + i];
            const double *restrict xi = x + i * n;
            for (int64_t j = 0; j < n; j++) {
                xk[j] -= f * xi[j];
            }
        }
        const double pivot = p[k * n + k];
        for (int64_t j = 0; j < n; j++) {
            xk[j] /= pivot;
        }
    }
    return 1;
}

/* e := the [13/13] Pade approximant of exp(a) (n x n) from a and its powers a^2, a^4, a^6 in work[0..3 n^2)
 * (work: 7 n x n matrices); 0 if the denominator is singular */
static int pade(const double *a, double *e, double *work, int64_t n)
{
    const int64_t nn = n * n;
    double *a2 = work, *a4 = work + nn, *a6 = work + 2 * nn, *t = work + 3 * nn, *u = work + 4 * nn,
           *v = work + 5 * nn, *w = work + 6 * nn;
    const double *b = PADE;
    combine(a6, b[13], a4, b[11], a2, b[9], 0.0, t, n);
    product(a6, t, w, n);
    combine(a6, b[7], a4, b[5], a2, b[3], b[1], t, n);
    for (int64_t q = 0; q < nn; q++) {
        t[q] += w[q];
    }
    product(a, t, u, n);
    combine(a6, b[12], a4, b[10], a2, b[8], 0.0, t, n);
    product(a6, t, w, n);
    combine(a6, b[6], a4, b[4], a2, b[2], b[0], v, n);
    for (int64_t q = 0; q < nn; q++) {
        v[q] += w[q];
        t[q] = v[q] - u[q];
        e[q] = v[q] + u[q];
    }
    return solve(t, e, n);
}

/* the squarings that bring the 1-norm of a (n x n) to THETA_13, where the [13/13] Pade approximant is
 * accurate to the unit round-off (expm.py) */
static int64_t pade_squarings(const double *a, int64_t n)
{
    const double norm = one_norm(a, n, n, n);
    return norm > THETA_13 ? (int64_t)ceil(log2(norm / THETA_13)) : 0;
}

/* e := exp(a) (n x n) by scaling and squaring with the [13/13] Pade approximant (expm.py's algorithm;
 * work: 7 n x n scratch matrices, a^2, a^4 and a^6 of the scaled a left in its first three); a is
 * overwritten; 0 if the denominator is singular */
static int exponential(double *a, double *e, double *work, int64_t n)
{
    const int64_t nn = n * n;
    const int squarings = (int)pade_squarings(a, n);
    const double scale = ldexp(1.0, squarings);
    for (int64_t q = 0; q < nn; q++) {
        a[q] /= scale;
    }
    product(a, a, work, n);
    product(work, work, work + nn, n);
    product(work, work + nn, work + 2 * nn, n);
    if (!pade(a, e, work, n)) {
        return 0;
    }
    for (int s = 0; s < squarings; s++) {
        product(e, e, work + 6 * nn, n);
        memcpy(e, work + 6 * nn, nn * sizeof(double));
    }
    return 1;
}

#endif
