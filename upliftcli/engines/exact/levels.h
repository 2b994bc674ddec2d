/* The step operators of one contact state at every bisection level: ops[j] = expm(A h / 2^j)^T,
 * j = 0..L, by the Taylor polynomial of the finest level and squarings (level_operators.py,
 * docs/theory.md 15.9). The numpy twin is levels_numpy.py, the same arithmetic in the same order but
 * for the order of the sums of the matrix products.
 *
 * The rows of A that are zero (the plastic drifts of elastic stories, the settlements of elements that
 * do not yield, the constant forcing entries) are unit rows of every exp(A t): they are left out of the
 * products. In M = A^T, with its indices ordered active first (the m indices of nonzero rows of A) and
 * held last, every operator is [[X11, 0], [X21, I]] and a power of M [[P, 0], [Q, 0]], each kept as its
 * first m columns (n x m, the "compact" form): a product costs n m^2 multiplications instead of n^3
 * (half of them on the README example, 24 active of 33).
 *
 * The one copy of this code (state_levels, story_rows), included by _levels.c (their Python entry points)
 * and _stepping.c (whose loop builds the states of yielding stories itself: builds.h). */

#ifndef UPLIFT_LEVELS_H
#define UPLIFT_LEVELS_H

#include "buffers.h"
#include "product.h"
#include <math.h>
#include <string.h>

/* the degree of the Taylor polynomial is 9: its coefficients 1/k!; THETA the largest eta it is used at
 * (levels_numpy.THETA_TAYLOR) */
static const double COEFFICIENT[10] = {1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0,
                                       1.0 / 5040.0, 1.0 / 40320.0, 1.0 / 362880.0};
#define THETA 0.1

/* c (rows x w) = x (rows x w, its first m columns) y (m x w): product.h's matrix_product (each sum over
 * k = 0..m-1 in that order from +0, four rows and eight columns at a time; w is padded to whole
 * PRODUCT_LANES, padded_width, the padding columns zero, so no columns are left over) */
static ALWAYS_INLINE void compact_product(const double *restrict x, const double *restrict y, double *restrict c,
                                          int64_t rows, int64_t m, int64_t w)
{
    matrix_product(x, w, y, w, c, w, rows, m, w);
}

/* c = x^2 of an operator [[X11, 0], [X21, I]] in compact form: x y[:m], then its held rows (p >= m) plus x's */
static ALWAYS_INLINE void compact_square(const double *restrict x, double *restrict c, int64_t n, int64_t m, int64_t w)
{
    compact_product(x, x, c, n, m, w);
    for (int64_t i = m * w; i < n * w; i++) {
        c[i] += x[i];
    }
}

/* out = c_a a + c_b b + c_c c (+ d where given), elementwise over n x w, added in that order */
static ALWAYS_INLINE void combine(const double *restrict a, const double *restrict b, const double *restrict c,
                                  const double *restrict d, const double coefficients[3], double *restrict out,
                                  int64_t size)
{
    const double ca = coefficients[0], cb = coefficients[1], cc = coefficients[2];
    for (int64_t i = 0; i < size; i++) {
        out[i] = (ca * a[i] + cb * b[i]) + cc * c[i];
    }
    if (d) {
        for (int64_t i = 0; i < size; i++) {
            out[i] += d[i];
        }
    }
}

/* a run of consecutive indices that are all active (offset: the compact column of the first) or all held
 * (offset -1) */
typedef struct {
    int64_t start, length, offset;
} Span;

/* The working arrays of one state: the compact forms (n x w each), where each index is (position[r]: its
 * compact row) and the spans of active and held indices. */
typedef struct {
    int64_t n, m, w, levels, n_spans;
    const int64_t *order, *position; /* the active indices (m), then the held ones; order's inverse */
    const Span *spans;
    double *a, *a2, *a3, *sum, *inner, *level, *next;
} Work;

/* The Taylor polynomial of the finest level into work->level, squared `halvings` times (the halvings that
 * bring eta to THETA: levels_numpy.finest_level) */
static ALWAYS_INLINE void finest_level(Work *k)
{
    const int64_t n = k->n, m = k->m, w = k->w, size = n * w;
    const double *c = COEFFICIENT;
    compact_product(k->a, k->a, k->a2, n, m, w);
    compact_product(k->a2, k->a, k->a3, n, m, w);
    /* the 1-norms of the compact powers [[P, 0], [Q, 0]]: their first m columns */
    const double eta = fmax(sqrt(one_norm(k->a2, n, m, w)), cbrt(one_norm(k->a3, n, m, w)));
    int halvings = 0;
    if (eta > THETA && isfinite(eta)) { /* powers of two: the powers of the scaled matrix exactly */
        halvings = (int)ceil(log2(eta / THETA));
        const double scale = ldexp(1.0, -halvings), scale2 = scale * scale, scale3 = scale2 * scale;
        for (int64_t i = 0; i < size; i++) {
            k->a[i] *= scale;
            k->a2[i] *= scale2;
            k->a3[i] *= scale3;
        }
    }
    const double high[3] = {c[7], c[8], c[9]}, middle[3] = {c[4], c[5], c[6]};
    combine(k->a, k->a2, k->a3, NULL, high, k->sum, size);
    compact_product(k->a3, k->sum, k->inner, n, m, w);           /* A^3 (A/7! + A^2/8! + A^3/9!) */
    combine(k->a, k->a2, k->a3, k->inner, middle, k->sum, size); /* ... + A/4! + A^2/5! + A^3/6! */
    compact_product(k->a3, k->sum, k->inner, n, m, w);
    double *t = k->level;
    for (int64_t p = 0; p < n; p++) { /* I + A + A^2/2 + A^3/6 + A^3 (...), added in that order */
        for (int64_t q = 0; q < w; q++) {
            const int64_t i = p * w + q;
            t[i] = (((p == q && q < m ? 1.0 : 0.0) + k->a[i]) + c[2] * k->a2[i]) + c[3] * k->a3[i];
            t[i] += k->inner[i];
        }
    }
    for (int s = 0; s < halvings; s++) {
        compact_square(k->level, k->next, n, m, w);
        double *swap = k->level;
        k->level = k->next;
        k->next = swap;
    }
}

/* out (n x n) = the operator in compact form x, in the original order: out[order[p], order[q]] = x[p, q] for
 * q < m, and the held columns unit columns; row by row, span by span */
static ALWAYS_INLINE void scatter(const Work *k, const double *restrict x, double *restrict out)
{
    const int64_t n = k->n, m = k->m, w = k->w;
    for (int64_t r = 0; r < n; r++) {
        const double *row = x + k->position[r] * w;
        double *target = out + r * n;
        for (int64_t s = 0; s < k->n_spans; s++) {
            const Span span = k->spans[s];
            for (int64_t c = 0; c < span.length; c++) {
                target[span.start + c] = span.offset < 0 ? 0.0 : row[span.offset + c];
            }
        }
        if (k->position[r] >= m) {
            target[r] = 1.0;
        }
    }
}

/* ops[j] = expm(A^T h / 2^j), j = levels..0: the finest level, then each the square of the next finer one */
HOT_LOOP static void state_levels(Work *k, const double *restrict matrix, double h, double *restrict ops)
{
    const int64_t n = k->n, m = k->m, w = k->w;
    const double finest = ldexp(1.0, -(int)k->levels); /* a power of two: the division by 2^L exactly */
    for (int64_t p = 0; p < n; p++) { /* a = (A^T h) / 2^L in compact form: a[p, q] = A[order[q], order[p]] */
        for (int64_t q = 0; q < w; q++) {
            k->a[p * w + q] = q < m ? (matrix[k->order[q] * n + k->order[p]] * h) * finest : 0.0;
        }
    }
    finest_level(k);
    scatter(k, k->level, ops + k->levels * n * n);
    for (int64_t j = k->levels - 1; j >= 0; j--) {
        compact_square(k->level, k->next, n, m, w);
        double *swap = k->level;
        k->level = k->next;
        k->next = swap;
        scatter(k, k->level, ops + j * n * n);
    }
}

/* Whether row r of the matrix (n x n) has a nonzero entry (an active index). */
static int active(const double *matrix, int64_t n, int64_t r)
{
    for (int64_t c = 0; c < n; c++) {
        if (matrix[r * n + c] != 0.0) {
            return 1;
        }
    }
    return 0;
}

/* order (the active indices, then the held ones, each ascending), position (its inverse) and the spans of
 * consecutive active or held indices; returns m, the number of active ones */
static int64_t active_first(const double *matrix, int64_t n, int64_t *order, int64_t *position, Span *spans,
                            int64_t *n_spans)
{
    int64_t m = 0, held = 0;
    for (int64_t r = 0; r < n; r++) {
        m += active(matrix, n, r);
    }
    *n_spans = 0;
    for (int64_t r = 0, count = 0; r < n; r++) {
        const int is_active = active(matrix, n, r);
        position[r] = is_active ? count++ : m + held++;
        order[position[r]] = r;
        if (r == 0 || is_active != (spans[*n_spans - 1].offset >= 0)) { /* a new span starts at r */
            Span *span = &spans[(*n_spans)++];
            span->start = r;
            span->length = 0;
            span->offset = is_active ? position[r] : -1;
        }
        spans[*n_spans - 1].length++;
    }
    return m;
}

/* ops (L + 1, n, n) of A = matrix (n, n) at step h (state_levels), with the work space of one state: order
 * (2 n + 1), spans (n + 1) and work (7 n padded_width(n)) */
static void matrix_levels(const double *matrix, int64_t n, int64_t levels, double h, double *ops, int64_t *order,
                          Span *spans, double *work)
{
    int64_t *position = order + n, n_spans = 0;
    const int64_t m = active_first(matrix, n, order, position, spans, &n_spans);
    const int64_t width = padded_width(m);
    Work k = {.n = n, .m = m, .w = width, .levels = levels, .n_spans = n_spans, .order = order,
              .position = position, .spans = spans};
    double **buffers[7] = {&k.a, &k.a2, &k.a3, &k.sum, &k.inner, &k.level, &k.next};
    for (int i = 0; i < 7; i++) {
        *buffers[i] = work + i * n * width;
    }
    state_levels(&k, matrix, h, ops);
}

/* The rows of one state of yielding stories taken from its base's table, and the rates of its stories' event
 * rows (levels_numpy.story_rows): 0, or -1 where a pick falls outside the table */
HOT_LOOP static int story_rows(long long bits, const double *restrict table, int64_t table_rows, const int64_t *restrict picks,
                      double *restrict rows, double *restrict events, double *restrict rates, double *restrict matrix_t,
                      int64_t *restrict fields, int64_t n, int64_t total, int64_t n_y, int64_t zero_rows,
                      int64_t soil_rows)
{
    for (int64_t j = 0; j < n_y; j++) {
        fields[j] = (bits >> (2 * j)) & 3;
    }
    const int64_t *base = picks, *step = picks + total, *story = picks + 2 * total;
    for (int64_t r = 0; r < total; r++) {
        if (story[r] < 0 || story[r] >= n_y) {
            return -1;
        }
        const int64_t pick = base[r] + step[r] * fields[story[r]];
        if (pick < 0 || pick >= table_rows) {
            return -1;
        }
        memcpy(rows + r * n, table + pick * n, (size_t)n * sizeof(double));
    }
    for (int64_t i = 0; i < total - n; i++) { /* the event rows, the first zero_rows zero */
        for (int64_t c = 0; c < n; c++) {
            events[i * n + c] = i < zero_rows ? 0.0 : rows[(n + i) * n + c];
        }
    }
    for (int64_t i = 0; i < n; i++) {
        for (int64_t j = 0; j < n; j++) {
            matrix_t[i * n + j] = rows[j * n + i];
        }
    }
    /* the rates: zero rows zero, the foundation's rows left to the caller, the stories' rows G_i A, each entry
     * summed over k = 0..n-1 in that order from +0 (product.h's strided_product: A's rows by the event row) */
    for (int64_t i = 0; i < total - n; i++) {
        if (i < zero_rows) {
            memset(rates + i * n, 0, (size_t)n * sizeof(double));
        } else if (i >= soil_rows) {
            strided_product(rows, n, events + i * n, n, n, rates + i * n);
        }
    }
    return 0;
}

#endif
