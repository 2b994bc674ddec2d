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

/* the Taylor polynomial is of degree 9 (four products), or 6 (three) where eta <= THETA_SIX: its coefficients
 * 1/k!; THETA the largest eta degree 9 is used at, after halvings (levels_numpy.THETA_TAYLOR, .THETA_SIX: the
 * remainder bound at most 2.8e-17 and 1.1e-16, below the unit round-off) */
static const double COEFFICIENT[10] = {1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0,
                                       1.0 / 5040.0, 1.0 / 40320.0, 1.0 / 362880.0};
#define THETA 0.1
#define THETA_SIX 0.0177

/* the width of the compact forms: m rounded up to a whole four columns (level_width), the padding columns zero,
 * so that no column is left over to matrix_product's one entry at a time; to four rather than PRODUCT_LANES
 * (eight): matrix_product takes the last four in a tile of their own, and m = 25..28 (a third of the README
 * deck's states) then costs 28 columns instead of 32 */
static inline int64_t level_width(int64_t m)
{
    return (m + 3) / 4 * 4;
}

/* c (rows x w) = x (rows x w, its first m columns) y (m x w): product.h's matrix_product (each sum over
 * k = 0..m-1 in that order from +0, four rows and eight or four columns at a time: the bits do not depend on
 * the tiles) */
static ALWAYS_INLINE void compact_product(const double *restrict x, const double *restrict y, double *restrict c,
                                          int64_t rows, int64_t m, int64_t w)
{
    matrix_product(x, w, y, w, c, w, rows, m, w);
}

#if defined(__GNUC__)
/* product_tile (four rows of x, `lanes` columns) over the k of `ks` alone: the other terms are zero */
static ALWAYS_INLINE void listed_tile(const double *restrict x, const double *restrict y, double *restrict c, int64_t w,
                                      const int64_t *restrict ks, int64_t count, int lanes)
{
    const product_vector zero = {0.0, 0.0, 0.0, 0.0};
    product_vector a0 = zero, b0 = zero, a1 = zero, b1 = zero, a2 = zero, b2 = zero, a3 = zero, b3 = zero;
#pragma GCC unroll 2
    for (int64_t t = 0; t < count; t++) {
        const int64_t k = ks[t];
        const double *row = y + k * w;
        const double y0 = x[k], y1 = x[w + k], y2 = x[2 * w + k], y3 = x[3 * w + k];
        const product_vector low = VECTOR_AT(row);
        a0 += low * y0;
        a1 += low * y1;
        a2 += low * y2;
        a3 += low * y3;
        if (lanes == 8) {
            const product_vector high = VECTOR_AT(row + 4);
            b0 += high * y0;
            b1 += high * y1;
            b2 += high * y2;
            b3 += high * y3;
        }
    }
    VECTOR_AT(c) = a0;
    VECTOR_AT(c + w) = a1;
    VECTOR_AT(c + 2 * w) = a2;
    VECTOR_AT(c + 3 * w) = a3;
    if (lanes == 8) {
        VECTOR_AT(c + 4) = b0;
        VECTOR_AT(c + w + 4) = b1;
        VECTOR_AT(c + 2 * w + 4) = b2;
        VECTOR_AT(c + 3 * w + 4) = b3;
    }
}
#endif

/* c = x y as compact_product, for a sparse x (the scaled A^T, whose columns of the modal displacements and plastic
 * drifts read the velocities alone: half its entries zero on the README deck): four rows at a time over the k
 * where one of the four is nonzero, listed in ks (per four rows: their count, then the k; room for
 * (rows / 4) (m + 1)) unless `listed` (the lists of the same x, kept from the call before), the rows left over by
 * compact_product. The same bits: the terms left out are zeros, which change no sum from +0 (product.h's
 * matrix_product). */
static ALWAYS_INLINE void sparse_product(const double *restrict x, const double *restrict y, double *restrict c,
                                         int64_t rows, int64_t m, int64_t w, int64_t *restrict ks, int listed)
{
    int64_t i = 0;
#if defined(__GNUC__)
    for (; i + 4 <= rows; i += 4) {
        const double *xi = x + i * w;
        int64_t *list = ks + i / 4 * (m + 1) + 1, count = 0;
        for (int64_t k = 0; !listed && k < m; k++) {
            list[count] = k;
            count += xi[k] != 0.0 || xi[w + k] != 0.0 || xi[2 * w + k] != 0.0 || xi[3 * w + k] != 0.0;
        }
        if (!listed) {
            list[-1] = count;
        }
        count = list[-1];
        int64_t j = 0;
        for (; j + 8 <= w; j += 8) {
            listed_tile(xi, y + j, c + i * w + j, w, list, count, 8);
        }
        if (j < w) { /* w is a multiple of four (level_width) */
            listed_tile(xi, y + j, c + i * w + j, w, list, count, 4);
        }
    }
#else
    (void)ks, (void)listed;
#endif
    compact_product(x + i * w, y, c + i * w, rows - i, m, w);
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
    int64_t n, m, w, levels, n_spans, n_runs; /* spans: the n_runs long active runs, then held runs, single indices */
    const int64_t *order, *position; /* the active indices (m), then the held ones; order's inverse */
    int64_t *ks;                     /* sparse_product's lists (n (n + 1) / 4 at most) */
    const Span *spans;
    double *a, *a2, *a3, *sum, *inner, *level, *next;
} Work;

/* The Taylor polynomial of the finest level into work->level: of degree 6 where eta <= THETA_SIX, else of
 * degree 9 and squared `halvings` times (the halvings that bring eta to THETA: levels_numpy.finest_level) */
static ALWAYS_INLINE void finest_level(Work *k)
{
    const int64_t n = k->n, m = k->m, w = k->w, size = n * w;
    const double *c = COEFFICIENT;
    sparse_product(k->a, k->a, k->a2, n, m, w, k->ks, 0);
    sparse_product(k->a, k->a2, k->a3, n, m, w, k->ks, 1); /* A A^2: the sparse factor first, its lists kept */
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
    const int six = eta <= THETA_SIX;
    if (!six) {
        combine(k->a, k->a2, k->a3, NULL, high, k->sum, size);
        compact_product(k->a3, k->sum, k->inner, n, m, w); /* A^3 (A/7! + A^2/8! + A^3/9!) */
    }
    combine(k->a, k->a2, k->a3, six ? NULL : k->inner, middle, k->sum, size); /* (...) + A/4! + A^2/5! + A^3/6! */
    compact_product(k->a3, k->sum, k->inner, n, m, w);
    double *t = k->level;
    for (int64_t i = 0; i < size; i++) { /* I + A + A^2/2 + A^3/6 + A^3 (...), added in that order: 0 off the */
        t[i] = (((0.0 + k->a[i]) + c[2] * k->a2[i]) + c[3] * k->a3[i]) + k->inner[i]; /* diagonal, */
    }
    for (int64_t p = 0; p < m; p++) { /* 1 on it */
        const int64_t i = p * w + p;
        t[i] = (((1.0 + k->a[i]) + c[2] * k->a2[i]) + c[3] * k->a3[i]) + k->inner[i];
    }
    for (int s = 0; s < halvings; s++) {
        compact_square(k->level, k->next, n, m, w);
        double *swap = k->level;
        k->level = k->next;
        k->next = swap;
    }
}

/* out (n x n) = the operator in compact form x, in the original order: out[order[p], order[q]] = x[p, q] for
 * q < m, and the held columns unit columns. The runs of more than SHORT_RUN active indices (the modal
 * coordinates) are copied row by row (memcpy), the other indices (a yielding story's plastic drift, the held
 * ones: elastic stories' plastic drifts, the constant entries) column by column, the held ones two at a time: a
 * call of memcpy or memset, or a pass of the loop over the spans, per row for each of them cost more than the
 * copy (callgrind). */
static ALWAYS_INLINE void scatter(const Work *k, const double *restrict x, double *restrict out)
{
    /* in locals: memcpy may write any memory the compiler cannot tell apart, so it would load them per call */
    const int64_t n = k->n, m = k->m, w = k->w, n_runs = k->n_runs, n_spans = k->n_spans;
    const int64_t *restrict position = k->position;
    const Span *restrict spans = k->spans;
    const Span first = n_runs ? spans[0] : (Span){.start = 0, .length = 0, .offset = 0};
    for (int64_t r = 0; r < n; r++) { /* the active runs: the first (the modal coordinates), then any other */
        const double *row = x + position[r] * w;
        double *target = out + r * n;
        memcpy(target + first.start, row + first.offset, (size_t)first.length * sizeof(double));
        for (int64_t s = 1; s < n_runs; s++) {
            memcpy(target + spans[s].start, row + spans[s].offset, (size_t)spans[s].length * sizeof(double));
        }
    }
    for (int64_t s = n_runs; s < n_spans; s++) { /* held runs and single indices */
        const Span span = spans[s];
        double *column = out + span.start;
        if (span.offset < 0) { /* held columns: zeros, two at a time (no loop a compiler makes a memset of) */
            int64_t c = 0;
            for (; c + 2 <= span.length; c += 2) {
                for (int64_t r = 0; r < n; r++) {
                    column[r * n + c] = column[r * n + c + 1] = 0.0;
                }
            }
            for (; c < span.length; c++) {
                for (int64_t r = 0; r < n; r++) {
                    column[r * n + c] = 0.0;
                }
            }
        } else {
            const double *source = x + span.offset;
#pragma GCC unroll 4
            for (int64_t r = 0; r < n; r++) {
                column[r * n] = source[position[r] * w];
            }
        }
    }
    for (int64_t p = m; p < n; p++) { /* the unit entries of the held columns */
        out[k->order[p] * n + k->order[p]] = 1.0;
    }
}

/* ops[j] = expm(A^T h / 2^j), j = levels..0: the finest level, then each the square of the next finer one */
HOT_LOOP static void state_levels(Work *k, const double *restrict matrix_t, double h, double *restrict ops)
{
    const int64_t n = k->n, m = k->m, w = k->w, lead = k->n_runs && !k->spans[0].start ? k->spans[0].length : 0;
    const double finest = ldexp(1.0, -(int)k->levels); /* a power of two: the division by 2^L exactly */
    for (int64_t p = 0; p < n; p++) { /* a = (A^T h) / 2^L in compact form: a[p, q] = A^T[order[p], order[q]] */
        const double *source = matrix_t + k->order[p] * n;
        double *row = k->a + p * w;
        for (int64_t q = 0; q < lead; q++) { /* the first run (from index 0 where it is active): order[q] = q */
            row[q] = (source[q] * h) * finest;
        }
        for (int64_t q = lead; q < m; q++) {
            row[q] = (source[k->order[q]] * h) * finest;
        }
        for (int64_t q = m; q < w; q++) {
            row[q] = 0.0;
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

/* the runs of consecutive active indices longer than this are written row by row, the others index by index
 * (scatter) */
#define SHORT_RUN 3

/* the spans of the runs of consecutive active or held indices (position: the compact index, held ones >= m):
 * the runs of more than SHORT_RUN active indices (`single` 0) or else the held runs and each index of the shorter
 * active runs alone (`single` 1), appended to spans[*n_spans] on */
static void add_spans(const int64_t *position, int64_t n, int64_t m, int single, Span *spans, int64_t *n_spans)
{
    for (int64_t r = 0, end = 0; r < n; r = end) {
        const int is_active = position[r] < m;
        end = r + 1;
        while (end < n && (position[end] < m) == is_active) {
            end++;
        }
        const int64_t length = end - r;
        const int whole = !single || !is_active; /* a long active run, or a held run: one span */
        for (int64_t i = r; single == (!is_active || length <= SHORT_RUN) && i < end; i += whole ? length : 1) {
            spans[(*n_spans)++] = (Span){.start = i, .length = whole ? length : 1, .offset = is_active ? position[i] : -1};
        }
    }
}

/* order (the active indices, then the held ones, each ascending), position (its inverse) and the spans of
 * consecutive active or held indices (add_spans: n_runs long runs, then single indices); returns m, the number of
 * active ones */
static int64_t active_first(const double *matrix, int64_t n, int64_t *order, int64_t *position, Span *spans,
                            int64_t *n_spans, int64_t *n_runs)
{
    int64_t m = 0, held = 0;
    for (int64_t r = 0; r < n; r++) { /* position[r]: whether row r of A is nonzero (active), until the loop below */
        int64_t any = 0;
        for (int64_t c = 0; c < n; c++) { /* the whole row, without a branch per entry */
            any |= matrix[r * n + c] != 0.0;
        }
        position[r] = any;
        m += any;
    }
    for (int64_t r = 0, count = 0; r < n; r++) {
        position[r] = position[r] ? count++ : m + held++;
        order[position[r]] = r;
    }
    *n_spans = 0;
    add_spans(position, n, m, 0, spans, n_spans);
    *n_runs = *n_spans;
    add_spans(position, n, m, 1, spans, n_spans);
    return m;
}

/* ops (L + 1, n, n) of A = matrix (n, n), matrix_t its transpose, at step h (state_levels), with the work space of
 * one state: order (2 n + n^2 + 1), spans (n + 1) and work (7 n padded_width(n), at least 7 n level_width(n)) */
static void matrix_levels(const double *matrix, const double *matrix_t, int64_t n, int64_t levels, double h,
                          double *ops, int64_t *order, Span *spans, double *work)
{
    int64_t *position = order + n, *ks = order + 2 * n, n_spans = 0, n_runs = 0;
    const int64_t m = active_first(matrix, n, order, position, spans, &n_spans, &n_runs);
    const int64_t width = level_width(m);
    Work k = {.n = n, .m = m, .w = width, .levels = levels, .n_spans = n_spans, .n_runs = n_runs,
              .order = order, .position = position, .ks = ks, .spans = spans};
    double **buffers[7] = {&k.a, &k.a2, &k.a3, &k.sum, &k.inner, &k.level, &k.next};
    for (int i = 0; i < 7; i++) {
        *buffers[i] = work + i * n * width;
    }
    state_levels(&k, matrix_t, h, ops);
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
