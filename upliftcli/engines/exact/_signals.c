/* Compiled loop of the exact engine's post-processing: the signals at the samples, each sample
 * with its own contact state's rows (the peaks between samples: _peaks.c; reactions and uplift
 * statistics: _contact.c; work integrals: _energy.c). See response_kernels.py for the arguments;
 * the numpy twins are in tests/test_response_kernels.py. */

#include "buffers.h"
#include "product.h"
#include <stdlib.h>

/* the integers of a split state per signal row: dense_output 1, sparse 3 (with picks), copies 2, shorts 6 */
#define INTEGERS_PER_ROW 12

/* a state's rows are split (split_rows) when they serve at least this many products */
#define SPLIT_USES 32

/* The rows of one contact state, each output computed the cheapest way that gives the bits of the
 * dense product R x (transposed_product): an output equal to an earlier one is copied; one with few
 * nonzero coefficients sums them alone (the terms left out are zero and the others are added in
 * the same order, so the sum is the same); the others come from one dense product over their
 * columns; one whose only nonzero coefficient is 1 is that input (+0, as its sum from +0), one of two nonzero
 * coefficients their sum from +0 in one expression (a pair). Each list holds output
 * indices (and where from), in increasing order. */
typedef struct {
    const double *whole;   /* R (width, n_aug) of a state not split (NULL: split), used transposed (transpose_rows) */
    int64_t width;
    int64_t n_dense, n_sparse, n_copies, n_entries, n_picks;
    int64_t n_short[3];    /* rows of 2, 3 and 4 nonzero coefficients */
    int64_t dense_width;   /* n_dense rounded up to whole PRODUCT_LANES */
    double *dense;         /* (n_aug, dense_width): the rows computed densely, transposed (zeros past n_dense) */
    int64_t *dense_output; /* n_dense: the output of each dense column */
    int64_t *sparse;       /* n_sparse: the output of each sparse row */
    int64_t *copies;       /* n_copies x (output, the earlier output it equals) */
    int64_t *picks;        /* n_picks x (output, input) of the rows whose one nonzero coefficient is 1 */
    int64_t *shorts;       /* (output, first entry) of each row of 2, 3 and 4 nonzero coefficients, from
                            * shorts + 2 width (c - 2) for c coefficients; their entries are at the end of the
                            * entry arrays (filled from the end down) */
    int64_t capacity;      /* the length of the entry arrays */
    int64_t *entry_input;  /* sparse entries: input index, output index and coefficient, by output and input */
    int64_t *entry_output;
    double *entry_value;
} SplitRows;

/* Split R^T (n_aug, width) into `split`, whose arrays have room for the worst case: dense
 * n_aug padded_width(width) doubles, entry_value n_aug width, dense_output and sparse width, picks and
 * copies 2 width each, shorts 6 width, entry_input and entry_output n_aug width integers each; nonzeros and sums: work space
 * of width each. */
static void split_rows(const double *rows_t, int64_t n_aug, int64_t width, SplitRows *split, int64_t *nonzeros,
                       double *sums)
{
    split->n_dense = split->n_sparse = split->n_copies = split->n_entries = split->n_picks = 0;
    split->n_short[0] = split->n_short[1] = split->n_short[2] = 0;
    int64_t top = split->capacity; /* the entries of the short rows, from the end down */
    /* each row's count of nonzero coefficients and their sum: equal rows agree in both, so only
     * such pairs are compared entry by entry (comparing every pair cost a yielding run with
     * hundreds of states a sixth of its time, measured) */
    for (int64_t r = 0; r < width; r++) {
        nonzeros[r] = 0;
        sums[r] = 0.0;
    }
    for (int64_t q = 0; q < n_aug; q++) {
        for (int64_t r = 0; r < width; r++) {
            nonzeros[r] += rows_t[q * width + r] != 0.0;
            sums[r] += rows_t[q * width + r];
        }
    }
    for (int64_t r = 0; r < width; r++) {
        int64_t same = -1;
        for (int64_t earlier = 0; earlier < r && same < 0; earlier++) {
            if (nonzeros[earlier] != nonzeros[r] || sums[earlier] != sums[r]) {
                continue;
            }
            int equal = 1;
            for (int64_t q = 0; q < n_aug && equal; q++) {
                equal = rows_t[q * width + r] == rows_t[q * width + earlier];
            }
            same = equal ? earlier : -1;
        }
        const int64_t nonzero = nonzeros[r];
        if (same >= 0) {
            int64_t *copy = split->copies + 2 * split->n_copies++;
            copy[0] = r;
            copy[1] = same;
        } else if (nonzero == 1 && sums[r] == 1.0) {
            int64_t q = 0;
            while (rows_t[q * width + r] == 0.0) {
                q++;
            }
            int64_t *pick = split->picks + 2 * split->n_picks++;
            pick[0] = r;
            pick[1] = q;
        } else if (nonzero >= 2 && nonzero <= 4 && 4 * nonzero <= n_aug) {
            top -= nonzero;
            int64_t *row = split->shorts + 2 * width * (nonzero - 2) + 2 * split->n_short[nonzero - 2]++;
            row[0] = r;
            row[1] = top;
            for (int64_t q = 0, e = top; q < n_aug; q++) {
                if (rows_t[q * width + r] != 0.0) {
                    split->entry_input[e] = q;
                    split->entry_value[e++] = rows_t[q * width + r];
                }
            }
        } else if (4 * nonzero <= n_aug) {
            split->sparse[split->n_sparse++] = r;
            for (int64_t q = 0; q < n_aug; q++) {
                if (rows_t[q * width + r] != 0.0) {
                    const int64_t e = split->n_entries++;
                    split->entry_input[e] = q;
                    split->entry_output[e] = r;
                    split->entry_value[e] = rows_t[q * width + r];
                }
            }
        } else {
            split->dense_output[split->n_dense++] = r;
        }
    }
    split->dense_width = padded_width(split->n_dense);
    for (int64_t c = 0; c < split->dense_width; c++) {
        for (int64_t q = 0; q < n_aug; q++) {
            split->dense[q * split->dense_width + c] =
                c < split->n_dense ? rows_t[q * width + split->dense_output[c]] : 0.0;
        }
    }
}

/* out = R x with the rows split by split_rows, the dense rows' outputs dense_out (their product
 * with x) given */
static inline void split_rest(const SplitRows *split, const double *restrict x, const double *restrict dense_out,
                              double *restrict out)
{
    const int64_t *dense_output = split->dense_output;
    for (int64_t c = 0, n_dense = split->n_dense; c < n_dense; c++) {
        out[dense_output[c]] = dense_out[c];
    }
    /* every sparse output from +0, then its entries in order, in one flat pass (the rows are short:
     * a loop per row cost more than its terms) */
    for (int64_t j = 0; j < split->n_sparse; j++) {
        out[split->sparse[j]] = 0.0;
    }
    for (int64_t e = 0; e < split->n_entries; e++) {
        out[split->entry_output[e]] += split->entry_value[e] * x[split->entry_input[e]];
    }
    /* the short rows: +0, then their entries in order, in one expression */
    const double *value = split->entry_value;
    const int64_t *input = split->entry_input, *row = split->shorts;
    for (int64_t p = 0; p < split->n_short[0]; p++, row += 2) {
        const int64_t e = row[1];
        out[row[0]] = (0.0 + value[e] * x[input[e]]) + value[e + 1] * x[input[e + 1]];
    }
    row = split->shorts + 2 * split->width;
    for (int64_t p = 0; p < split->n_short[1]; p++, row += 2) {
        const int64_t e = row[1];
        out[row[0]] = ((0.0 + value[e] * x[input[e]]) + value[e + 1] * x[input[e + 1]]) + value[e + 2] * x[input[e + 2]];
    }
    row = split->shorts + 4 * split->width;
    for (int64_t p = 0; p < split->n_short[2]; p++, row += 2) {
        const int64_t e = row[1];
        out[row[0]] = (((0.0 + value[e] * x[input[e]]) + value[e + 1] * x[input[e + 1]]) + value[e + 2] * x[input[e + 2]])
                      + value[e + 3] * x[input[e + 3]];
    }
    /* the pairs through pointers to their ends (indexing split's arrays afresh in each pass cost twice the
     * instructions of these loops, which run 60 times per sample of a yielding run) */
    for (const int64_t *pick = split->picks, *last = pick + 2 * split->n_picks; pick < last; pick += 2) {
        out[pick[0]] = x[pick[1]] + 0.0; /* +0 + 1 x, as the sum of its one entry */
    }
    for (const int64_t *copy = split->copies, *last = copy + 2 * split->n_copies; copy < last; copy += 2) {
        out[copy[0]] = out[copy[1]];
    }
}

/* R^T (n_aug, width) of the rows R (width, n_aug) of a state, four rows at a time (each column of four a
 * contiguous store) */
static void transpose_rows(const double *restrict rows, int64_t width, int64_t n_aug, double *restrict rows_t)
{
    int64_t r = 0;
    for (; r + 4 <= width; r += 4) {
        const double *a = rows + r * n_aug, *b = a + n_aug, *c = b + n_aug, *d = c + n_aug;
        for (int64_t q = 0; q < n_aug; q++) {
            double *out = rows_t + q * width + r;
            out[0] = a[q];
            out[1] = b[q];
            out[2] = c[q];
            out[3] = d[q];
        }
    }
    for (; r < width; r++) {
        for (int64_t q = 0; q < n_aug; q++) {
            rows_t[q * width + r] = rows[r * n_aug + q];
        }
    }
}

/* out = R x with the rows split by split_rows, or by the whole rows of a state not split (whole_t: their
 * transpose, transpose_rows); dense_out: dense_width doubles of work space */
static inline void split_product(const SplitRows *split, const double *restrict whole_t, const double *restrict x,
                                 int64_t n_aug, double *restrict dense_out, double *restrict out)
{
    if (split->whole) {
        transposed_product(whole_t, x, n_aug, split->width, out);
        return;
    }
    transposed_product(split->dense, x, n_aug, split->dense_width, dense_out);
    split_rest(split, x, dense_out, out);
}

/* Signal values and slopes at every sample, each sample with its own contact state's rows
 * (split[s], or its whole rows); the left limits at the end of every interval that ends at a transition, in order.
 * PRODUCT_SAMPLES samples in the same state have their dense rows computed together
 * (product_samples). acc: width + (PRODUCT_SAMPLES + 1) padded_width(width) doubles of work space; whole_t:
 * n_aug width, the transposed rows of the last state not split met (transposed as its samples begin). */
HOT_LOOP static void evaluate_signals(const double *states, int64_t n, int64_t n_aug, const int64_t *ids,
                                      const SplitRows *split, int64_t k, int64_t k_s, double *values, double *slopes,
                                      double *ends, double *acc, double *whole_t)
{
    const int64_t width = k + k_s;
    double *dense_out = acc + width, *dense_block = dense_out + padded_width(width);
    int64_t n_switch = 0, transposed = -1;
    for (int64_t i0 = 0; i0 < n; i0 += PRODUCT_SAMPLES) {
        const int64_t count = n - i0 < PRODUCT_SAMPLES ? n - i0 : PRODUCT_SAMPLES;
        int same = count == PRODUCT_SAMPLES && ids[i0] >= 0 && !split[ids[i0]].whole;
        for (int64_t i = i0 + 1; i < i0 + count; i++) {
            same &= ids[i] == ids[i0];
        }
        if (same) {
            const SplitRows *rows = split + ids[i0];
            product_samples(rows->dense, states + i0 * n_aug, n_aug, rows->dense_width, dense_block);
        }
        for (int64_t i = i0; i < i0 + count; i++) {
            if (ids[i] < 0) { /* a sample the caller evaluates (of a state the caller names by a negative id), and
                               * the left limit at the end of its interval */
                n_switch += i + 1 < n && ids[i + 1] != ids[i];
                continue;
            }
            const SplitRows *rows = split + ids[i];
            if (rows->whole && transposed != ids[i]) {
                transpose_rows(rows->whole, width, n_aug, whole_t);
                transposed = ids[i];
            }
            if (same) {
                split_rest(rows, states + i * n_aug, dense_block + (i - i0) * rows->dense_width, acc);
            } else {
                split_product(rows, whole_t, states + i * n_aug, n_aug, dense_out, acc);
            }
            memcpy(values + i * k, acc, k * sizeof(double));
            memcpy(slopes + i * k_s, acc + k, k_s * sizeof(double));
            if (i + 1 < n && ids[i + 1] != ids[i]) {
                split_product(rows, whole_t, states + (i + 1) * n_aug, n_aug, dense_out, ends + n_switch * width);
                n_switch++;
            }
        }
    }
}

/* ---------------------------------------------------------------------------- Python entry point */

/* evaluate_signals(states, ids, rows, values, slopes, ends) */
static PyObject *py_evaluate_signals(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 6, "evaluate_signals")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "states"}, {1, 'q', 1, 0, "ids"}, {2, 'd', 3, 0, "rows"},
        {3, 'd', 2, 1, "values"}, {4, 'd', 2, 1, "slopes"}, {5, 'd', 2, 1, "ends"}};
    Py_buffer *b[6];
    int taken = take_views(&v, args, arrays, 6, b);
    Py_buffer *states = b[0], *ids = b[1], *rows_in = b[2], *values = b[3], *slopes = b[4], *ends = b[5];
    if (!taken) {
        goto done;
    }
    const int64_t n = states->shape[0], n_aug = states->shape[1], k = values->shape[1], k_s = slopes->shape[1];
    int64_t transitions = 0;
    int ids_ok = 1;
    for (int64_t i = 0; i < ids->shape[0]; i++) {
        ids_ok &= INT64S(ids)[i] < rows_in->shape[0];
        transitions += i > 0 && INT64S(ids)[i] != INT64S(ids)[i - 1];
    }
    if (ids->shape[0] != n || rows_in->shape[2] != n_aug || rows_in->shape[1] != k + k_s || values->shape[0] != n
        || slopes->shape[0] != n || ends->shape[0] < transitions || ends->shape[1] != k + k_s || !ids_ok) {
        PyErr_SetString(PyExc_ValueError, "evaluate_signals: inconsistent array shapes");
        goto done;
    }
    const int64_t width = k + k_s, n_states = rows_in->shape[0], per_state = n_aug * width;
    /* the states used at least SPLIT_USES times (samples and left limits) are split (split_rows);
     * the others' rows are used whole (a yielding run meets hundreds of states, most at a few
     * samples, and splitting each cost it more than the products it saves: measured) */
    int64_t *uses = calloc(n_states + 2, sizeof(int64_t)); /* uses[s + 1]: state s's (uses[0]: the caller's states') */
    if (!uses) {
        PyErr_NoMemory();
        goto done;
    }
    for (int64_t i = 0; i < n; i++) { /* a sample, and the left limit of the state before a transition */
        uses[INT64S(ids)[i] < 0 ? 0 : INT64S(ids)[i] + 1]++;
        if (i > 0 && INT64S(ids)[i] != INT64S(ids)[i - 1]) {
            uses[INT64S(ids)[i - 1] < 0 ? 0 : INT64S(ids)[i - 1] + 1]++;
        }
    }
    int64_t n_split = 0;
    for (int64_t s = 0; s < n_states; s++) {
        n_split += uses[s + 1] >= SPLIT_USES;
    }
    /* work space: the products (evaluate_signals) and, per state split, its split rows (split_rows), the sums of
     * split_rows and the transposed rows of one state (whole_t) */
    const int64_t n_acc = width + (PRODUCT_SAMPLES + 1) * padded_width(width), n_dense = n_aug * padded_width(width);
    double *doubles = malloc((n_acc + n_split * (n_dense + per_state) + width + per_state + 1) * sizeof(double));
    int64_t *integers = malloc((INTEGERS_PER_ROW * n_split * width + 2 * n_split * per_state + width + 1)
                               * sizeof(int64_t));
    SplitRows *split = malloc((n_states + 1) * sizeof(SplitRows));
    if (!doubles || !integers || !split) {
        free(uses);
        free(doubles);
        free(integers);
        free(split);
        PyErr_NoMemory();
        goto done;
    }
    double *whole_t = doubles + n_acc + n_split * (n_dense + per_state) + width;
    Py_BEGIN_ALLOW_THREADS
    for (int64_t s = 0, j = 0; s < n_states; s++) {
        SplitRows *rows = split + s;
        rows->width = width;
        rows->whole = uses[s + 1] >= SPLIT_USES ? NULL : DOUBLES(rows_in) + s * per_state;
        if (rows->whole) {
            continue;
        }
        rows->dense = doubles + n_acc + j * n_dense;
        rows->entry_value = doubles + n_acc + n_split * n_dense + j * per_state;
        rows->dense_output = integers + INTEGERS_PER_ROW * j * width;
        rows->sparse = rows->dense_output + width;
        rows->picks = rows->sparse + width;
        rows->copies = rows->sparse + 3 * width;
        rows->shorts = rows->copies + 2 * width;
        rows->capacity = per_state;
        rows->entry_input = integers + INTEGERS_PER_ROW * n_split * width + 2 * j * per_state;
        rows->entry_output = rows->entry_input + per_state;
        transpose_rows(DOUBLES(rows_in) + s * per_state, width, n_aug, whole_t);
        split_rows(whole_t, n_aug, width, rows,
                   integers + n_split * (INTEGERS_PER_ROW * width + 2 * per_state),
                   doubles + n_acc + n_split * (n_dense + per_state));
        j++;
    }
    evaluate_signals(DOUBLES(states), n, n_aug, INT64S(ids), split, k, k_s, DOUBLES(values), DOUBLES(slopes),
                     DOUBLES(ends), doubles, whole_t);
    Py_END_ALLOW_THREADS
    free(uses);
    free(doubles);
    free(integers);
    free(split);
    result = Py_NewRef(Py_None);
done:
    release_views(&v);
    return result;
}


#include "derivatives.h" /* derivatives and its entry point (after transpose_rows) */

static PyMethodDef methods[] = {
    FASTCALL(evaluate_signals, "Signals at the samples."),
    FASTCALL(derivatives, "The derivatives of states."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_signals, "Compiled loop of the exact engine: the signals at the samples.")
