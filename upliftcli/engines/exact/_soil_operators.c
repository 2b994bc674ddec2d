/* Compiled step operators of the contact states of a yielding mat of many elements (docs/theory.md
 * 14.3): per state, the exponential of a small block of A (the motion, the forcing entries and the
 * mat's two forces: 28 x 28 on a 20-element mat), its squarings for the bisection levels, and the
 * operators E_j^T written into the state's slot of Operators.ops, the rows left out of the block in
 * closed form. See soil_operators.py for the arguments; the numpy twin is soil_operators_numpy.py. */

#include "buffers.h"
#include "pade.h" /* exponential, product */
#include "product.h"
#include <math.h>
#include <stdlib.h>

typedef struct {
    const double *matrices, *loads, *displacement, *rates;
    const unsigned char *contact, *yielding, *relaxing;
    const int64_t *core, *settlements, *tops;
    double h;
    int64_t count, n_aug, n_e, n_c, n_motion, levels;
    double *out;
} Soil;

/* the block B (nb x nb, nb = n_c + 2) of state r, times length: the core rows and columns of A and
 * the two columns G of the mat's forces, from the columns of the settlements of the first and last
 * elements in contact (yielding.py, _load_columns); a state with none in contact has G = 0 */
static void block_of(const Soil *in, int64_t r, double length, double *block)
{
    const int64_t n = in->n_aug, n_c = in->n_c, nb = n_c + 2, n_e = in->n_e;
    const double *a = in->matrices + r * n * n;
    const unsigned char *contact = in->contact + r * n_e;
    memset(block, 0, nb * nb * sizeof(double));
    int64_t first = -1, last = -1;
    for (int64_t e = 0; e < n_e; e++) {
        if (contact[e]) {
            first = first < 0 ? e : first;
            last = e;
        }
    }
    for (int64_t p = 0; p < n_c; p++) {
        const double *row = a + in->core[p] * n;
        double *to = block + p * nb;
        for (int64_t q = 0; q < n_c; q++) {
            to[q] = row[in->core[q]] * length;
        }
        if (first < 0) {
            continue;
        }
        const double *l = in->loads;  /* (2, n_e): vertical force and moment per unit settlement */
        const double ri = row[in->settlements[first]];
        if (first == last) {
            const double norm = l[first] * l[first] + l[n_e + first] * l[n_e + first];
            to[n_c] = ri * l[first] / norm * length;
            to[n_c + 1] = ri * l[n_e + first] / norm * length;
            continue;
        }
        const double rj = row[in->settlements[last]];
        const double a0 = l[first], b0 = l[n_e + first], c0 = l[last], d0 = l[n_e + last];
        const double det = a0 * d0 - b0 * c0;
        to[n_c] = (ri * (d0 / det) + rj * (-b0 / det)) * length;
        to[n_c + 1] = (ri * (-c0 / det) + rj * (a0 / det)) * length;
    }
}

/* the yielding settlements' columns of out (one level, E^T): their rows of E are d_i E - d_i + the unit row,
 * so out[a][s_i] += sum_u out[a][reads[u]] d_i[reads[u]] - d_i[a], row by row; d_i reads the motion at the
 * `count` entries `reads` only (theta and v), and a row with none of them, where no d_i reads, is left */
static void yielding_columns(const Soil *in, const unsigned char *yielding, const int64_t *reads, int64_t count,
                             double *out)
{
    const int64_t n = in->n_aug, n_e = in->n_e;
    for (int64_t a = 0; a < n; a++) {
        double *row = out + a * n;
        double x[2] = {0.0, 0.0};
        int any = 0;
        for (int64_t u = 0; u < count; u++) {
            x[u] = row[reads[u]];
            any |= x[u] != 0.0 || reads[u] == a;
        }
        if (!any) {
            continue;
        }
        for (int64_t i = 0; i < n_e; i++) {
            if (!yielding[i]) {
                continue;
            }
            const double *d = in->displacement + i * n;
            double acc = 0.0;
            for (int64_t u = 0; u < count; u++) {
                acc += x[u] * d[reads[u]];
            }
            row[in->settlements[i]] += acc - d[a];
        }
    }
}

/* out[j] (n_aug x n_aug, any contents) := E_j^T of state r from the block exponentials levels[j] (nb x nb): the
 * core entries, the rows of the settlements in contact (the mat's two forces times k_i e_i), the unit
 * rows of the other settlements and tops, the relaxing tops in closed form, and the yielding
 * settlements' columns (yielding_columns; yielding.py, _assemble); every entry is written, each level
 * zeroed just before it is (in cache), so the slot needs no fill of its own */
static void assemble(const Soil *in, int64_t r, const double *levels, const int64_t *reads, int64_t count)
{
    const int64_t n = in->n_aug, n_c = in->n_c, nb = n_c + 2, n_e = in->n_e;
    const unsigned char *contact = in->contact + r * n_e, *yielding = in->yielding + r * n_e,
                        *relaxing = in->relaxing + r * n_e;
    for (int64_t j = 0; j <= in->levels; j++) {
        const double *e = levels + j * nb * nb;
        double *out = in->out + (r * (in->levels + 1) + j) * n * n;
        const double length = in->h / ldexp(1.0, (int)j);
        memset(out, 0, n * n * sizeof(double));  /* the slot may hold an earlier run's operators (kept.reused) */
        for (int64_t p = 0; p < n_c; p++) {
            double *row = out + in->core[p] * n;
            for (int64_t q = 0; q < n_c; q++) {
                row[in->core[q]] = e[q * nb + p];
            }
        }
        for (int64_t i = 0; i < n_e; i++) {
            double *row = out + in->settlements[i] * n;
            if (contact[i]) {
                const double l0 = in->loads[i], l1 = in->loads[n_e + i];
                for (int64_t q = 0; q < n_c; q++) {
                    row[in->core[q]] = l0 * e[q * nb + n_c] + l1 * e[q * nb + n_c + 1];
                }
            }
            row[in->settlements[i]] = 1.0;
            const int64_t z = in->tops[i];
            if (relaxing[i]) {
                out[z * n + z] = exp(-length * in->rates[i]);
                row[z] = -expm1(-length * in->rates[i]);
            } else {
                out[z * n + z] = 1.0;
            }
        }
        yielding_columns(in, yielding, reads, count, out);
    }
}

/* the squarings s by which exponential() would scale exp(B h) (the block times h: its 1-norm to THETA_13),
 * at most `levels` */
static int64_t squarings_of(const double *block, int64_t nb, int64_t levels)
{
    const int64_t s = pade_squarings(block, nb);
    return s < levels ? s : levels;
}

/* levels[j] := exp(B h / 2^j), j = 0..L, of state r: level s (squarings_of) by the exponential and the
 * coarser ones by squaring it, down to level 0 (the products exponential(B h) makes: level 0 as it gives
 * it), the finest by the exponential and the levels between by squaring it; 0 if singular */
static int exponentials(const Soil *in, int64_t r, double *block, double *levels, double *work)
{
    const int64_t nb = in->n_c + 2, nn = nb * nb, top = in->levels;
    block_of(in, r, in->h, block);
    const int64_t s = squarings_of(block, nb, top);
    block_of(in, r, in->h / ldexp(1.0, (int)s), block);
    if (!exponential(block, levels + s * nn, work, nb)) {
        return 0;
    }
    for (int64_t j = s - 1; j >= 0; j--) {
        product(levels + (j + 1) * nn, levels + (j + 1) * nn, levels + j * nn, nb);
    }
    if (s == top) {
        return 1;
    }
    /* the finest block is level s's scaled by 2^-(top - s), unscaled by exponential() (its norm is below
     * THETA_13 / 2): its powers are level s's scaled by powers of two, exactly the products they would be */
    block_of(in, r, in->h / ldexp(1.0, (int)top), block);
    const int d = (int)(top - s);
    /* times exact powers of two (2^-72 at most, a normal number): the correctly rounded x 2^-k that ldexp gives */
    const double f2 = ldexp(1.0, -2 * d), f4 = ldexp(1.0, -4 * d), f6 = ldexp(1.0, -6 * d);
    for (int64_t q = 0; q < nn; q++) {
        work[q] *= f2;
        work[nn + q] *= f4;
        work[2 * nn + q] *= f6;
    }
    if (!pade(block, levels + top * nn, work, nb)) {
        return 0;
    }
    for (int64_t j = top - 1; j > s; j--) {
        product(levels + (j + 1) * nn, levels + (j + 1) * nn, levels + j * nn, nb);
    }
    return 1;
}

/* every state's levels (exponentials), assembled into its slot of out; 0 if singular, -1 if the rows d_i
 * read more than two motion entries (theta and v) */
static int soil_operators(const Soil *in, double *scratch)
{
    const int64_t nb = in->n_c + 2, nn = nb * nb, nm = in->n_motion, n = in->n_aug;
    double *block = scratch, *levels = scratch + nn, *work = levels + (in->levels + 1) * nn;
    int64_t reads[2], count = 0;  /* the motion entries the rows d_i read (theta and v) */
    for (int64_t m = 0; m < nm && m < n; m++) {
        int64_t i = 0;
        while (i < in->n_e && in->displacement[i * n + m] == 0.0) {
            i++;
        }
        if (i < in->n_e) {
            if (count == 2) {
                return -1;
            }
            reads[count++] = m;
        }
    }
    for (int64_t r = 0; r < in->count; r++) {
        if (!exponentials(in, r, block, levels, work)) {
            return 0;
        }
        assemble(in, r, levels, reads, count);
    }
    return 1;
}

static int consistent(const Soil *in, Py_buffer *const *b)
{
    const int64_t n = in->n_aug, n_e = in->n_e;
    int ok = b[0]->shape[1] == n && b[0]->shape[2] == n && b[1]->shape[0] == in->count && b[1]->shape[1] == n_e
             && b[2]->shape[0] == in->count && b[2]->shape[1] == n_e && b[3]->shape[0] == in->count
             && b[3]->shape[1] == n_e && b[5]->shape[0] == n_e && b[6]->shape[0] == n_e && b[7]->shape[0] == 2
             && b[7]->shape[1] == n_e && b[8]->shape[0] == n_e && b[8]->shape[1] == n && b[9]->shape[0] == n_e
             && b[10]->shape[0] == in->count && b[10]->shape[1] >= 1 && b[10]->shape[2] == n && b[10]->shape[3] == n
             && in->n_motion >= 0 && in->n_motion <= n;
    for (int64_t p = 0; ok && p < in->n_c; p++) {
        ok = in->core[p] >= 0 && in->core[p] < n;
    }
    for (int64_t i = 0; ok && i < n_e; i++) {
        ok = in->settlements[i] >= 0 && in->settlements[i] < n && in->tops[i] >= 0 && in->tops[i] < n;
    }
    return ok;
}

static PyObject *py_soil_operators(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 13, "soil_operators")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 3, 0, "matrices"}, {1, '?', 2, 0, "contact"},
        {2, '?', 2, 0, "yielding"}, {3, '?', 2, 0, "relaxing"}, {4, 'q', 1, 0, "core"},
        {5, 'q', 1, 0, "settlements"}, {6, 'q', 1, 0, "tops"}, {7, 'd', 2, 0, "loads"},
        {8, 'd', 2, 0, "displacement"}, {9, 'd', 1, 0, "rates"}, {12, 'd', 4, 1, "out"}};
    Py_buffer *b[11];
    if (!take_views(&v, args, arrays, 11, b)) {
        goto done;
    }
    const double h = PyFloat_AsDouble(args[10]);
    const int64_t n_motion = PyLong_AsLongLong(args[11]);
    if (PyErr_Occurred()) {
        goto done;
    }
    Soil in = {
        .matrices = DOUBLES(b[0]), .contact = BOOLS(b[1]), .yielding = BOOLS(b[2]), .relaxing = BOOLS(b[3]),
        .core = INT64S(b[4]), .settlements = INT64S(b[5]), .tops = INT64S(b[6]), .loads = DOUBLES(b[7]),
        .displacement = DOUBLES(b[8]), .rates = DOUBLES(b[9]), .h = h, .count = b[0]->shape[0],
        .n_aug = b[0]->shape[1], .n_e = b[5]->shape[0], .n_c = b[4]->shape[0], .n_motion = n_motion,
        .levels = b[10]->shape[1] - 1, .out = DOUBLES(b[10]),
    };
    if (!consistent(&in, b)) {
        PyErr_SetString(PyExc_ValueError, "soil_operators: inconsistent array shapes");
        goto done;
    }
    const int64_t nn = (in.n_c + 2) * (in.n_c + 2);
    double *scratch = malloc((in.levels + 9) * nn * sizeof(double));
    if (!scratch) {
        PyErr_NoMemory();
        goto done;
    }
    int ok;
    Py_BEGIN_ALLOW_THREADS
    ok = soil_operators(&in, scratch);
    Py_END_ALLOW_THREADS
    free(scratch);
    if (ok < 0) {
        PyErr_SetString(PyExc_ValueError, "soil_operators: the displacement rows read more than two motion entries");
        goto done;
    }
    if (!ok) {
        PyErr_SetString(PyExc_ZeroDivisionError, "soil_operators: a singular Pade denominator");
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    release_views(&v);
    return result;
}

static PyMethodDef methods[] = {
    FASTCALL(soil_operators, "Step operators of yielding-mat contact states."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_soil_operators, "Step operators of the contact states of a yielding mat of many elements.")
