/* Compiled step operators of one contact state at every bisection level, ops[j] = expm(A h / 2^j)^T, j = 0..L,
 * and the rows of a state of yielding stories from its base's table: the Python entry points of levels.h
 * (level_operators.py, docs/theory.md 15.9; the numpy twin is levels_numpy.py). */

#include "levels.h"

/* state_levels(matrix, h, ops): see level_operators.state_levels */
static PyObject *py_state_levels(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 3, "state_levels")) {
        return NULL;
    }
    Views v = {.count = 0};
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "matrix"}, {2, 'd', 3, 1, "ops"}};
    Py_buffer *b[2];
    const double h = PyFloat_AsDouble(args[1]);
    if (PyErr_Occurred() || !take_views(&v, args, arrays, 2, b)) {
        release_views(&v);
        return NULL;
    }
    const int64_t n = b[0]->shape[0], levels = b[1]->shape[0] - 1;
    if (b[0]->shape[1] != n || b[1]->shape[1] != n || b[1]->shape[2] != n || levels < 0 || levels > 60 || !isfinite(h)) {
        release_views(&v);
        PyErr_SetString(PyExc_ValueError, "state_levels: matrix (n, n), a finite step and ops (L + 1, n, n) expected");
        return NULL;
    }
    const int64_t w = padded_width(n);
    int64_t *order = PyMem_Malloc((size_t)(2 * n + n * n + 1) * sizeof(int64_t));
    Span *spans = PyMem_Malloc((size_t)(n + 1) * sizeof(Span));
    double *work = PyMem_Malloc((size_t)(7 * n * w + n * n + 1) * sizeof(double)), *matrix_t = work + 7 * n * w;
    if (!order || !spans || !work) {
        PyMem_Free(order);
        PyMem_Free(spans);
        PyMem_Free(work);
        release_views(&v);
        return PyErr_NoMemory();
    }
    const double *matrix = DOUBLES(b[0]);
    for (int64_t i = 0; i < n * n; i++) { /* A^T */
        matrix_t[i] = matrix[i % n * n + i / n];
    }
    matrix_levels(matrix, matrix_t, n, levels, h, DOUBLES(b[1]), order, spans, work);
    PyMem_Free(order);
    PyMem_Free(spans);
    PyMem_Free(work);
    release_views(&v);
    Py_RETURN_NONE;
}

/* story_rows(bits, table, picks, rows, events, rates, matrix_t, fields, zero_rows, soil_rows): see
 * level_operators.story_rows */
static PyObject *py_story_rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 10, "story_rows")) {
        return NULL;
    }
    const long long bits = PyLong_AsLongLong(args[0]), zero_rows = PyLong_AsLongLong(args[8]),
                    soil_rows = PyLong_AsLongLong(args[9]);
    if (PyErr_Occurred()) {
        return NULL;
    }
    Views v = {.count = 0};
    static const ArraySpec arrays[] = {{1, 'd', 2, 0, "table"},    {2, 'q', 2, 0, "picks"},
                                       {3, 'd', 2, 1, "rows"},     {4, 'd', 2, 1, "events"},
                                       {5, 'd', 2, 1, "rates"},    {6, 'd', 2, 1, "matrix_t"},
                                       {7, 'q', 1, 1, "fields"}};
    Py_buffer *b[7];
    if (!take_views(&v, args, arrays, 7, b)) {
        release_views(&v);
        return NULL;
    }
    const int64_t n = b[2]->shape[1], total = b[2]->shape[0], n_y = b[6]->shape[0];
    const int valid = b[0]->shape[1] == n && b[1]->shape[0] == 3 && b[1]->shape[1] == total && total >= n &&
                      b[3]->shape[0] == total - n && b[3]->shape[1] == n && b[4]->shape[0] == total - n &&
                      b[4]->shape[1] == n && b[5]->shape[0] == n && b[5]->shape[1] == n && n_y <= 31 && bits >= 0 &&
                      zero_rows >= 0 && zero_rows <= soil_rows && soil_rows <= total - n;
    if (!valid || story_rows(bits, DOUBLES(b[0]), b[0]->shape[0], INT64S(b[1]), DOUBLES(b[2]), DOUBLES(b[3]),
                             DOUBLES(b[4]), DOUBLES(b[5]), INT64S(b[6]), n, total, n_y, zero_rows, soil_rows) < 0) {
        release_views(&v);
        PyErr_SetString(PyExc_ValueError, "story_rows: a table (T, n), picks (3, n + n_e) into it, rows (n + n_e, n), "
                                          "events and rates (n_e, n), matrix_t (n, n), fields (n_y <= 31) and "
                                          "0 <= zero_rows <= soil_rows <= n_e expected");
        return NULL;
    }
    release_views(&v);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    FASTCALL(state_levels, "ops[j] = expm(A h / 2^j)^T, j = 0..L, of one contact state."),
    FASTCALL(story_rows, "The rows of one state of yielding stories from its base's table, and their rates."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_levels, "The step operators of one contact state at every bisection level.")
