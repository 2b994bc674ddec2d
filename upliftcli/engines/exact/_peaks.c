/* Compiled loop of the exact engine's post-processing: the peaks of the responses between samples,
 * on the quintic Hermite interpolant through the signals (_signals.c). See response_kernels.py for
 * the arguments; the numpy twins are in tests/test_response_kernels.py. */

#include "buffers.h"
#include "peak_products.h"
#include "product.h"
#include "response_lanes.h"
#include <math.h>
#include <stdlib.h>

/* Largest |p(s)| for s in [0, 1] of the quintic Hermite p with p, p', p'' given at both ends
 * (slopes times the interval length, second derivatives times its square); *where = s. The
 * stationary points are bracketed on 8 sub-intervals and bisected. */
static double quintic_extremum(double p0, double p1, double d0, double d1, double c0, double c1, double *where)
{
    const double a2 = 0.5 * c0;
    const double a3 = -1.5 * c0 + 0.5 * c1 - 6.0 * d0 - 4.0 * d1 - 10.0 * p0 + 10.0 * p1;
    const double a4 = 1.5 * c0 - c1 + 8.0 * d0 + 7.0 * d1 + 15.0 * p0 - 15.0 * p1;
    const double a5 = -0.5 * c0 + 0.5 * c1 - 3.0 * d0 - 3.0 * d1 - 6.0 * p0 + 6.0 * p1;
    double best = fabs(p0);
    *where = 0.0;
    if (fabs(p1) > best) {
        best = fabs(p1);
        *where = 1.0;
    }
    double lo = 0.0, g_lo = d0;
    for (int k = 1; k < 9; k++) {
        double hi = k / 8.0;
        double g_hi = (((5.0 * a5 * hi + 4.0 * a4) * hi + 3.0 * a3) * hi + 2.0 * a2) * hi + d0;
        if ((g_lo > 0.0) != (g_hi > 0.0) || g_hi == 0.0) {
            double left = lo, right = hi, g_left = g_lo;
            for (int it = 0; it < 40; it++) {
                double mid = 0.5 * (left + right);
                double g_mid = (((5.0 * a5 * mid + 4.0 * a4) * mid + 3.0 * a3) * mid + 2.0 * a2) * mid + d0;
                if ((g_mid > 0.0) == (g_left > 0.0) && g_mid != 0.0) {
                    left = mid;
                    g_left = g_mid;
                } else {
                    right = mid;
                }
            }
            double root = 0.5 * (left + right);
            double value = fabs((((((a5 * root + a4) * root + a3) * root + a2) * root + d0) * root) + p0);
            if (value > best) {
                best = value;
                *where = root;
            }
        }
        lo = hi;
        g_lo = g_hi;
    }
    return best;
}

/* True if the quintic Hermite p of quintic_extremum (same arguments) stays below `peak` on [0, 1]
 * by a margin far above round-off: p lies in the hull of its Bernstein coefficients, p0, p0 + d0/5,
 * p0 + 2 d0/5 + c0/20, p1 - 2 d1/5 + c1/20, p1 - d1/5, p1. Such an interval cannot raise the
 * peak found so far, so skipping it leaves the result as it is, to the bit. */
static inline int hull_below(double p0, double p1, double d0, double d1, double c0, double c1, double peak)
{
    const double b[6] = {p0, p0 + d0 / 5.0, p0 + 2.0 * d0 / 5.0 + c0 / 20.0, p1 - 2.0 * d1 / 5.0 + c1 / 20.0,
                         p1 - d1 / 5.0, p1};
    double hull = 0.0;
    for (int i = 0; i < 6; i++) {
        hull = fabs(b[i]) > hull ? fabs(b[i]) : hull;
    }
    return hull * (1.0 + 1e-9) < peak;
}

typedef struct {
    const double *values, *slopes, *end_values, *end_slopes, *rows_t, *lengths, *fractions;
    const int64_t *switch_, *value_columns, *rate_columns, *curvature_columns;
    int64_t n, k, k_s, width_end_slopes, n_basis, m;
} PeakInput;

/* The rate and curvature of response j at one sample (or left limit): sum_q R[j, q] s_q' and sum_q R[j, q] s_q''
 * from the sample's values (the rate columns) and slopes (the curvature columns), each from +0 in the order of q */
static ALWAYS_INLINE void rates_at(const PeakInput *in, int64_t j, const double *restrict values,
                                   const double *restrict slopes, double *rate, double *curvature)
{
    double d = 0.0, c = 0.0;
    for (int64_t q = 0; q < in->n_basis; q++) {
        const double rq = in->rows_t[q * in->m + j];
        d += rq * values[in->rate_columns[q]];
        c += rq * slopes[in->curvature_columns[q]];
    }
    *rate = d;
    *curvature = c;
}

/* The rates and curvatures of the responses lo <= j < hi at one sample (or left limit), rate[j] and curvature[j],
 * from R^T padded to padded_width(m): the products rates_at makes one response at a time, summed in the same order
 * from +0 (lanes_product_pair), so the same bits; y: 2 n_basis doubles of work space */
static ALWAYS_INLINE void rates_of_all(const PeakInput *in, const double *restrict padded, const double *restrict values,
                                       const double *restrict slopes, int64_t lo, int64_t hi, double *restrict y,
                                       double *restrict rate, double *restrict curvature)
{
    const int64_t width = padded_width(in->m);
    for (int64_t q = 0; q < in->n_basis; q++) {
        y[q] = values[in->rate_columns[q]];
        y[in->n_basis + q] = slopes[in->curvature_columns[q]];
    }
    lanes_product_pair(padded, y, y + in->n_basis, in->n_basis, width, lo, hi, rate, curvature);
}

/* an interval with at least m / ALL_RATES_SHARE responses to search has the rates of all of them taken at once
 * (rates_of_all: one vectorised product; a yielding story's shear plateaus near its strength, so that dozens
 * of responses are searched in the same intervals), one with fewer one response at a time (rates_at) */
#define ALL_RATES_SHARE 4

/* The responses of interval i to search, into todo (their count returned): those with a sampled value (r0 at
 * its start, r1 at its end) at or above their threshold */
static ALWAYS_INLINE int64_t to_search(const double *restrict r0, const double *restrict r1,
                                       const double *restrict threshold, int64_t m, int64_t *restrict todo)
{
    int64_t count = 0;
    for (int64_t j = 0; j < m; j++) {
        if (j % 4 == 0 && all_below(r0 + j, r1 + j, threshold + j)) { /* four responses below at both ends */
            j += 3;
            continue;
        }
        if (fabs(r0[j]) < threshold[j] && fabs(r1[j]) < threshold[j]) {
            continue;
        }
        todo[count++] = j;
    }
    return count;
}

/* Peak |r| of each response r = R s between samples and where it is (interval index +
 * fraction), from the quintic Hermite interpolant through the samples with the exact first and
 * second derivatives (response_kernels.hermite_peaks). Work space: sampled (n rounded up to
 * whole PRODUCT_SAMPLES, padded_width(m)), padded (n_basis, padded_width(m)), flagged (n), end and
 * threshold (padded_width(m) each), y (PRODUCT_SAMPLES n_basis), best and where (padded_width(m) each: copied to
 * best_out, where_out at the end), next_rate, next_curvature and next_at (m each), rates (4 padded_width(m): the
 * rates and curvatures of all responses at an interval's start and end, rates_of_all), todo (m) and ranges
 * (2 width / PRODUCT_LANES: tile_ranges). */
HOT_LOOP static void hermite_peaks(const PeakInput *in, double *best_out, double *where_out, double *sampled,
                                   double *padded, unsigned char *flagged, double *end, double *threshold, double *y,
                                   double *best, double *where, double *next_rate, double *next_curvature,
                                   int64_t *next_at, double *rates, int64_t *todo, int64_t *ranges)
{
    const int64_t n = in->n, m = in->m, n_b = in->n_basis, k = in->k, k_s = in->k_s, k_e = in->width_end_slopes;
    const int64_t width = padded_width(m);
    double *rate0 = rates, *curvature0 = rates + width, *rate1 = rates + 2 * width, *curvature1 = rates + 3 * width;
    /* best, where and threshold have `width` entries: the zero columns past m (their responses are +0, or NaN
     * from an infinite signal) never exceed a peak of 0 nor reach a threshold of +inf, and no loop over the
     * responses has a remainder */
    for (int64_t j = 0; j < width; j++) {
        best[j] = 0.0;
        where[j] = 0.0;
        threshold[j] = INFINITY;
        end[j] = 0.0; /* combine writes the first m */
    }
    int64_t first_column = k, last_column = -1; /* the span of the signal columns read */
    for (int64_t q = 0; q < n_b; q++) {
        first_column = in->value_columns[q] < first_column ? in->value_columns[q] : first_column;
        last_column = in->value_columns[q] > last_column ? in->value_columns[q] : last_column;
    }
    int64_t run = n_b > 0; /* the columns that follow the first one by one (gather_samples copies them) */
    while (run < n_b && in->value_columns[run] == in->value_columns[0] + run) {
        run++;
    }
    for (int64_t q = 0; q < n_b; q++) { /* R^T with zero columns up to the padded width */
        for (int64_t j = 0; j < width; j++) {
            padded[q * width + j] = j < m ? in->rows_t[q * m + j] : 0.0;
        }
    }
    tile_ranges(padded, n_b, width, ranges);
    /* pass 1: every response at every sample (kept), PRODUCT_SAMPLES samples at a time, and its
     * sampled peak (samples past the last are zeros) */
    for (int64_t i0 = 0; i0 < n; i0 += PRODUCT_SAMPLES) {
        for (int64_t i = i0 + PREFETCH_SAMPLES; last_column >= 0 && i < n && i < i0 + PREFETCH_SAMPLES + PRODUCT_SAMPLES;
             i++) { /* every cache line of the columns read, PREFETCH_SAMPLES ahead */
            for (int64_t c = first_column; c <= last_column; c += 8) {
                PREFETCH(in->values + i * k + c);
            }
            PREFETCH(in->values + i * k + last_column);
        }
        gather_samples(in->values, in->value_columns, run, i0, n, k, n_b, y);
        product_ranged(padded, y, n_b, width, ranges, sampled + i0 * width);
        keep_larger_block(sampled + i0 * width, width, n - i0 < PRODUCT_SAMPLES ? n - i0 : PRODUCT_SAMPLES, i0, width,
                          best, where);
    }
    /* the samples within the fraction of the peak of some response */
    for (int64_t j = 0; j < m; j++) {
        threshold[j] = in->fractions[j] * best[j];
    }
    for (int64_t i = 0; i < n; i++) {
        flagged[i] = (unsigned char)any_at_least(sampled + i * width, threshold, width);
    }
    /* pass 2: between samples, on the intervals with a flagged end or ending at a transition; the rates at the
     * sample that ended the interval before (when it was searched) are taken again: of the responses from the
     * first to the last searched (all_at: that sample, rate0 and curvature0 for all_lo <= j < all_hi), or of one
     * (next_at[j]) */
    for (int64_t j = 0; j < m; j++) {
        next_at[j] = -1;
    }
    int64_t all_at = -1, all_lo = 0, all_hi = 0;
    for (int64_t i = 0; i + 1 < n; i++) {
        const int64_t fix = in->switch_[i];
        if (!(flagged[i] || flagged[i + 1] || fix >= 0)) {
            continue;
        }
        const double *r0 = sampled + i * width, *r1 = sampled + (i + 1) * width;
        if (fix >= 0) { /* the interval ends at a transition: its left limit */
            combine(in->end_values + fix * k, in->value_columns, in->rows_t, n_b, m, y, end);
            r1 = end;
        }
        const int64_t count = to_search(r0, r1, threshold, m, todo);
        if (count == 0) {
            continue;
        }
        const double *end_values = fix >= 0 ? in->end_values + fix * k : in->values + (i + 1) * k;
        const double *end_slopes = fix >= 0 ? in->end_slopes + fix * k_e : in->slopes + (i + 1) * k_s;
        const int all = count * ALL_RATES_SHARE >= m;
        const int64_t lo = todo[0], hi = todo[count - 1] + 1;
        if (all) {
            if (all_at != i || lo < all_lo || hi > all_hi) {
                rates_of_all(in, padded, in->values + i * k, in->slopes + i * k_s, lo, hi, y, rate0, curvature0);
            }
            rates_of_all(in, padded, end_values, end_slopes, lo, hi, y, rate1, curvature1);
        }
        const double length = in->lengths[i];
        for (int64_t t = 0; t < count; t++) {
            const int64_t j = todo[t];
            double d0, d1, c0, c1;
            if (all || (all_at == i && j >= all_lo && j < all_hi)) {
                d0 = rate0[j];
                c0 = curvature0[j];
            } else if (next_at[j] == i) { /* sample i ended the interval before, searched for this response */
                d0 = next_rate[j];
                c0 = next_curvature[j];
            } else {
                rates_at(in, j, in->values + i * k, in->slopes + i * k_s, &d0, &c0);
            }
            if (all) {
                d1 = rate1[j];
                c1 = curvature1[j];
            } else {
                rates_at(in, j, end_values, end_slopes, &d1, &c1);
                next_at[j] = fix >= 0 ? -1 : i + 1;
                next_rate[j] = d1;
                next_curvature[j] = c1;
            }
            const double e0 = d0 * length, e1 = d1 * length, f0 = c0 * length * length, f1 = c1 * length * length;
            if (hull_below(r0[j], r1[j], e0, e1, f0, f1, best[j])) {
                continue;
            }
            double s;
            const double value = quintic_extremum(r0[j], r1[j], e0, e1, f0, f1, &s);
            if (value > best[j]) {
                best[j] = value;
                where[j] = i + s;
            }
        }
        if (all && fix < 0) { /* the end's rates are those of the next interval's start */
            double *swap = rate0;
            rate0 = rate1;
            rate1 = swap;
            swap = curvature0;
            curvature0 = curvature1;
            curvature1 = swap;
        }
        all_at = all && fix < 0 ? i + 1 : -1;
        all_lo = lo;
        all_hi = hi;
    }
    for (int64_t j = 0; j < m; j++) {
        best_out[j] = best[j];
        where_out[j] = where[j];
    }
}

/* ---------------------------------------------------------------------------- Python entry points */

/* hermite_peaks(values, slopes, end_values, end_slopes, switch, value_columns, rate_columns,
 *               curvature_columns, rows_t, lengths, fractions, best, where) */
static PyObject *py_hermite_peaks(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 13, "hermite_peaks")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {
        {0, 'd', 2, 0, "values"}, {1, 'd', 2, 0, "slopes"}, {2, 'd', 2, 0, "end_values"},
        {3, 'd', 2, 0, "end_slopes"}, {4, 'q', 1, 0, "switch"}, {5, 'q', 1, 0, "value_columns"},
        {6, 'q', 1, 0, "rate_columns"}, {7, 'q', 1, 0, "curvature_columns"}, {8, 'd', 2, 0, "rows_t"},
        {9, 'd', 1, 0, "lengths"}, {10, 'd', 1, 0, "fractions"}, {11, 'd', 1, 1, "best"}, {12, 'd', 1, 1, "where"},
    };
    Py_buffer *b[13];
    if (!take_views(&v, args, arrays, 13, b)) {
        goto done;
    }
    PeakInput in = {
        .values = DOUBLES(b[0]), .slopes = DOUBLES(b[1]), .end_values = DOUBLES(b[2]), .end_slopes = DOUBLES(b[3]),
        .switch_ = INT64S(b[4]), .value_columns = INT64S(b[5]), .rate_columns = INT64S(b[6]),
        .curvature_columns = INT64S(b[7]), .rows_t = DOUBLES(b[8]), .lengths = DOUBLES(b[9]),
        .fractions = DOUBLES(b[10]), .n = b[0]->shape[0], .k = b[0]->shape[1], .k_s = b[1]->shape[1],
        .width_end_slopes = b[3]->shape[1], .n_basis = b[8]->shape[0], .m = b[8]->shape[1],
    };
    int ok = b[1]->shape[0] == in.n && b[2]->shape[1] == in.k && b[3]->shape[0] == b[2]->shape[0]
             && b[4]->shape[0] >= in.n - 1 && b[5]->shape[0] == in.n_basis && b[6]->shape[0] == in.n_basis
             && b[7]->shape[0] == in.n_basis && b[9]->shape[0] >= in.n - 1 && b[10]->shape[0] == in.m
             && b[11]->shape[0] == in.m && b[12]->shape[0] == in.m;
    for (int64_t q = 0; ok && q < in.n_basis; q++) {
        ok = in.value_columns[q] >= 0 && in.value_columns[q] < in.k && in.rate_columns[q] >= 0
             && in.rate_columns[q] < in.k && in.curvature_columns[q] >= 0 && in.curvature_columns[q] < in.k_s
             && in.curvature_columns[q] < in.width_end_slopes;
    }
    for (int64_t i = 0; ok && i + 1 < in.n; i++) {
        ok = in.switch_[i] < b[2]->shape[0];
    }
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "hermite_peaks: inconsistent array shapes");
        goto done;
    }
    const int64_t width = padded_width(in.m), rows = (in.n + PRODUCT_SAMPLES - 1) / PRODUCT_SAMPLES * PRODUCT_SAMPLES;
    const int64_t n_sampled = rows * width, n_padded = in.n_basis * width;
    double *sampled = malloc((n_sampled + n_padded + 4 * width + PRODUCT_SAMPLES * in.n_basis + 1)
                             * sizeof(double));
    unsigned char *flagged = malloc(in.n + 1);
    double *next_rate = malloc((2 * in.m + 4 * width + 1) * sizeof(double));
    int64_t *next_at = malloc((2 * in.m + 2 * width / PRODUCT_LANES + 1) * sizeof(int64_t));
    if (!sampled || !flagged || !next_rate || !next_at) {
        free(sampled);
        free(flagged);
        free(next_rate);
        free(next_at);
        PyErr_NoMemory();
        goto done;
    }
    double *padded = sampled + n_sampled, *end = padded + n_padded, *threshold = end + width, *y = threshold + width;
    double *best = y + PRODUCT_SAMPLES * in.n_basis, *where = best + width;
    Py_BEGIN_ALLOW_THREADS
    hermite_peaks(&in, DOUBLES(b[11]), DOUBLES(b[12]), sampled, padded, flagged, end, threshold, y, best, where,
                  next_rate, next_rate + in.m, next_at, next_rate + 2 * in.m, next_at + in.m, next_at + 2 * in.m);
    Py_END_ALLOW_THREADS
    free(sampled);
    free(flagged);
    free(next_rate);
    free(next_at);
    result = Py_NewRef(Py_None);
done:
    release_views(&v);
    return result;
}

/* quintic_extremum(p0, p1, d0, d1, c0, c1) -> (value, s) (tests) */
static PyObject *py_quintic_extremum(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 6, "quintic_extremum")) {
        return NULL;
    }
    double p[6];
    for (int a = 0; a < 6; a++) {
        p[a] = PyFloat_AsDouble(args[a]);
    }
    if (PyErr_Occurred()) {
        return NULL;
    }
    double where;
    double value = quintic_extremum(p[0], p[1], p[2], p[3], p[4], p[5], &where);
    return Py_BuildValue("(dd)", value, where);
}

static PyMethodDef methods[] = {
    FASTCALL(hermite_peaks, "Peaks between samples."),
    FASTCALL(quintic_extremum, "Quintic Hermite peak."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_peaks, "Compiled loop of the exact engine: the peaks of the responses between samples.")
