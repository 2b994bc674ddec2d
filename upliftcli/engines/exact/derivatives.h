/* X' = A X and X'' = A X' of states at their samples, for the signals of a yielding run's rarely used states
 * (signal_maps.py, docs/theory.md 15.9), and the Python entry point derivatives(x, ids, matrices, first, second).
 * Included by _signals.c alone, after transpose_rows (numpy twin: response_numpy.derivatives). */

#ifndef UPLIFT_DERIVATIVES_H
#define UPLIFT_DERIVATIVES_H

#include "buffers.h"
#include "product.h"

/* X' = A X and X'' = A X' of each state x[i] (n x n_aug) with the A of its state (a_t + ids[i] n_aug^2: A^T), into
 * first and second (transposed_product) */
HOT_LOOP static void derivatives(const double *x, int64_t n, int64_t n_aug, const int64_t *ids, const double *a_t,
                                 double *first, double *second)
{
    for (int64_t i = 0; i < n; i++) {
        const double *m_t = a_t + ids[i] * n_aug * n_aug;
        transposed_product(m_t, x + i * n_aug, n_aug, n_aug, first + i * n_aug);
        transposed_product(m_t, first + i * n_aug, n_aug, n_aug, second + i * n_aug);
    }
}

/* A^T of each matrix of the sequence `matrices` (n x n float64 arrays) into a_t (n^2 each); 0 with the error set
 * at the first that is not */
static int transposed_matrices(PyObject *matrices, Py_ssize_t count, int64_t n, double *a_t)
{
    for (Py_ssize_t s = 0; s < count; s++) {
        Views item = {.count = 0};
        PyObject *matrix = PySequence_GetItem(matrices, s);
        Py_buffer *view = matrix ? take_view(&item, matrix, 'd', 2, 0, "matrices") : NULL;
        const int ok = view && view->shape[0] == n && view->shape[1] == n;
        if (ok) {
            transpose_rows(DOUBLES(view), n, n, a_t + s * n * n);
        } else if (view) {
            PyErr_SetString(PyExc_ValueError, "derivatives: inconsistent array shapes");
        }
        release_views(&item);
        Py_XDECREF(matrix);
        if (!ok) {
            return 0;
        }
    }
    return 1;
}

/* derivatives(x, ids, matrices, first, second): matrices a sequence of arrays */
static PyObject *py_derivatives(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 5, "derivatives")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL, *matrices = args[2];
    double *a_t = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "x"}, {1, 'q', 1, 0, "ids"}, {3, 'd', 2, 1, "first"},
        {4, 'd', 2, 1, "second"}};
    Py_buffer *b[4];
    const Py_ssize_t n_states = PySequence_Check(matrices) ? PySequence_Size(matrices) : -1;
    if (n_states < 0) {
        PyErr_SetString(PyExc_TypeError, "derivatives: matrices: a sequence of arrays is expected");
        goto done;
    }
    if (!take_views(&v, args, arrays, 4, b)) {
        goto done;
    }
    const int64_t n = b[0]->shape[0], n_aug = b[0]->shape[1];
    int ok = b[1]->shape[0] == n;
    for (int j = 2; j < 4; j++) {
        ok &= b[j]->shape[0] == n && b[j]->shape[1] == n_aug;
    }
    for (int64_t i = 0; ok && i < n; i++) {
        ok = INT64S(b[1])[i] >= 0 && INT64S(b[1])[i] < n_states;
    }
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "derivatives: inconsistent array shapes");
        goto done;
    }
    a_t = malloc((n_states * n_aug * n_aug + 1) * sizeof(double));
    if (!a_t) {
        PyErr_NoMemory();
        goto done;
    }
    if (!transposed_matrices(matrices, n_states, n_aug, a_t)) {
        goto done;
    }
    Py_BEGIN_ALLOW_THREADS
    derivatives(DOUBLES(b[0]), n, n_aug, INT64S(b[1]), a_t, DOUBLES(b[2]), DOUBLES(b[3]));
    Py_END_ALLOW_THREADS
    result = Py_NewRef(Py_None);
done:
    free(a_t);
    release_views(&v);
    return result;
}

#endif
