/* The states of yielding stories the stepping loop builds itself (_stepping.c): those story_requests.py's quick
 * path builds (story_requests.quick_request: a valid pattern whose foundation pattern has a base, with room for
 * it, some story yielding or an A built before), with the same compiled code (levels.h: story_rows, then
 * state_levels, or the slot of the state of the same A), written into the same arrays in the same order, so that
 * a yielding run returns to Python a handful of times instead of once per state (docs/theory.md 15.9). Python
 * hands the loop what those need (stepping_kernels.Builds) and makes the ContactState of each state built
 * (story_requests.adopt). Included by _stepping.c alone, after transitions.h. */

#ifndef UPLIFT_BUILDS_H
#define UPLIFT_BUILDS_H

#include "levels.h"
#include "transitions.h"

/* the bases handed to the loop at most (a rigid or bonded run has one: its foundation never switches) */
#define MAX_BASES 8

/* What the loop builds states with, and where it writes them (stepping_kernels.Builds): the arrays of Model,
 * writable, and per state its rows (A, then its event rows: ContactState.matrix, .events), its stories' fields
 * and its key of A where its operators are its own (story_states.matrix_key; -1 where shared); per base its
 * foundation pattern, table and picks; the foundation's rows (zero: a rigid or bonded run), the stories, the
 * elements (with a bearing capacity: settles), the state limit (Operators.most_states), room (the states the
 * arrays hold) and the work space of state_levels. */
typedef struct {
    double *ops, *events, *rates, *matrices, *rows;
    int64_t *slots, *patterns, *fields, *keys, *count;
    int64_t n_bases, soil[MAX_BASES], table_rows[MAX_BASES];
    const double *tables[MAX_BASES];
    const int64_t *picks[MAX_BASES];
    int64_t total, n_y, n_soil, n_elements, settles, most, room;
    double h;
    int64_t *order;
    Span *spans;
    double *work;
} Builder;

/* bits 0, 2, .., 2 count - 2 (stories.EVEN_BITS) */
static inline int64_t even_bits(int64_t count)
{
    return (int64_t)(0x5555555555555555ULL & ((count >= 32 ? 0ULL : (1ULL << (2 * count))) - 1ULL));
}

/* whether the pattern is a state: no element lifted and yielding (yielding.valid_pattern), no story yielding
 * both ways (stories.valid_story_pattern) */
static inline int valid_state(const Builder *b, int64_t pattern)
{
    const int64_t ne = b->n_elements, bits = pattern >> b->n_soil;
    if (b->settles && (pattern & (pattern >> ne) & ((INT64_C(1) << ne) - 1))) {
        return 0;
    }
    return !(bits & (bits >> 1) & even_bits(b->n_y));
}

/* the base of a foundation pattern, -1 without one */
static inline int64_t base_of(const Builder *b, int64_t soil)
{
    for (int64_t k = 0; k < b->n_bases; k++) {
        if (b->soil[k] == soil) {
            return k;
        }
    }
    return -1;
}

/* the state whose operators the states of key (soil, yielding) share (Operators.by_matrix), -1 without one */
static inline int64_t source_of(const Builder *b, int64_t count, int64_t soil, int64_t yielding)
{
    for (int64_t s = 0; s < count; s++) {
        if (b->keys[2 * s] == soil && b->keys[2 * s + 1] == yielding) {
            return s;
        }
    }
    return -1;
}

/* the operators of state `index` (A: its first n rows, A^T: its matrix, story_rows), or the slot of `source`'s; its
 * key kept where its own */
static void state_operators(Model *m, Builder *b, int64_t index, int64_t source, int64_t soil, int64_t yielding)
{
    const int64_t n = m->n;
    b->slots[index] = source < 0 ? index : b->slots[source];
    b->keys[2 * index] = source < 0 ? soil : -1;
    b->keys[2 * index + 1] = source < 0 ? yielding : -1;
    if (source < 0) {
        matrix_levels(b->rows + index * b->total * n, b->matrices + index * n * n, n, m->levels, b->h,
                      b->ops + index * (m->levels + 1) * n * n, b->order, b->spans, b->work);
    }
}

/* Build the state of `pattern` as story_requests._added does (its rows, event rows, rates and A^T: story_rows;
 * its operators: state_operators) and count it; its index, or -1 where the loop does not build it (Python does,
 * or says why it cannot: NEED_STATE). */
static int64_t build_state(Model *m, Builder *b, int64_t pattern)
{
    const int64_t index = m->count, n = m->n, n_e = m->n_events, soil = pattern & ((INT64_C(1) << b->n_soil) - 1);
    const int64_t k = base_of(b, soil);
    if (k < 0 || index >= b->room || index >= b->most || !valid_state(b, pattern)) {
        return -1;
    }
    const int64_t bits = pattern >> b->n_soil, yielding = (bits | (bits >> 1)) & even_bits(b->n_y);
    const int64_t source = source_of(b, index, soil, yielding);
    if (source < 0 && !yielding) { /* the elastic stories' A: add_states' */
        return -1;
    }
    if (story_rows(bits, b->tables[k], b->table_rows[k], b->picks[k], b->rows + index * b->total * n,
                   b->events + index * n_e * n, b->rates + index * n_e * n, b->matrices + index * n * n,
                   b->fields + index * b->n_y, n, b->total, b->n_y, b->n_soil, b->n_soil) < 0) {
        return -1;
    }
    state_operators(m, b, index, source, soil, yielding);
    b->patterns[index] = pattern;
    m->count = *b->count = index + 1;
    return index;
}

/* base k of b from (foundation pattern, table (T, n), picks (3, n + n_e)); 0 where it is not that */
static int take_base(Views *v, PyObject *base, Builder *b, int64_t k, int64_t n)
{
    PyObject *items[3];
    static const ArraySpec arrays[] = {{1, 'd', 2, 0, "table"}, {2, 'q', 2, 0, "picks"}};
    Py_buffer *a[2];
    if (!unpack(base, 3, "integrate", "base", items) || !take_views(v, items, arrays, 2, a)) {
        return 0;
    }
    b->soil[k] = PyLong_AsLongLong(items[0]);
    b->tables[k] = DOUBLES(a[0]);
    b->table_rows[k] = a[0]->shape[0];
    b->picks[k] = INT64S(a[1]);
    return !PyErr_Occurred() && a[0]->shape[1] == n && a[1]->shape[0] == 3 && a[1]->shape[1] == b->total;
}

/* Builds = (rows, fields, keys, count, bases, h, most_states, n_soil, n_elements, settles), bases a tuple of
 * (foundation pattern, table, picks) (stepping_kernels.Builds), into b with its work space (free_builder): 0 with
 * the error set where they do not fit the model m */
static int take_builds(Views *v, PyObject *builds, const Model *m, Builder *b)
{
    PyObject *items[10], *bases;
    static const ArraySpec arrays[] = {{0, 'd', 3, 1, "rows"}, {1, 'q', 2, 1, "fields"}, {2, 'q', 2, 1, "keys"},
        {3, 'q', 1, 1, "count"}};
    Py_buffer *a[4];
    if (!unpack(builds, 10, "integrate", "builds", items) || !take_views(v, items, arrays, 4, a)) {
        return 0;
    }
    bases = items[4];
    b->h = PyFloat_AsDouble(items[5]);
    b->most = PyLong_AsLongLong(items[6]);
    b->n_soil = PyLong_AsLongLong(items[7]);
    b->n_elements = PyLong_AsLongLong(items[8]);
    b->settles = PyObject_IsTrue(items[9]);
    if (PyErr_Occurred() || b->settles < 0 || !PyTuple_Check(bases) || PyTuple_Size(bases) > MAX_BASES) {
        return 0;
    }
    const int64_t n = m->n, n_e = m->n_events;
    b->total = a[0]->shape[1];
    b->n_y = a[1]->shape[1];
    b->n_bases = PyTuple_Size(bases);
    int ok = a[0]->shape[2] == n && b->total == n + n_e && b->n_y <= 31 && b->n_soil >= 0
             && b->n_soil + 2 * b->n_y == n_e && b->n_elements >= 0 && b->n_elements <= 62 && a[2]->shape[1] == 2
             && a[3]->shape[0] >= 1 && isfinite(b->h);
    for (int64_t k = 0; ok && k < b->n_bases; k++) {
        ok = take_base(v, PyTuple_GetItem(bases, k), b, k, n);
    }
    if (!ok) {
        return 0;
    }
    b->rows = DOUBLES(a[0]);
    b->fields = INT64S(a[1]);
    b->keys = INT64S(a[2]);
    b->count = INT64S(a[3]);
    b->room = a[0]->shape[0] < a[1]->shape[0] ? a[0]->shape[0] : a[1]->shape[0];
    b->room = a[2]->shape[0] < b->room ? a[2]->shape[0] : b->room;
    const int64_t width = padded_width(n);
    b->order = PyMem_Malloc((size_t)(2 * n + n * n + 1) * sizeof(int64_t));
    b->spans = PyMem_Malloc((size_t)(n + 1) * sizeof(Span));
    b->work = PyMem_Malloc((size_t)(7 * n * width + 1) * sizeof(double));
    if (!b->order || !b->spans || !b->work) {
        PyErr_NoMemory();
        return 0;
    }
    return 1;
}

/* the states' arrays (Model's, written where the loop builds a state); room: the states they all hold */
static void builder_arrays(Builder *b, Py_buffer *ops, Py_buffer *slots, Py_buffer *events, Py_buffer *rates,
                           Py_buffer *matrices, Py_buffer *patterns)
{
    Py_buffer *all[6] = {ops, slots, events, rates, matrices, patterns};
    for (int i = 0; i < 6; i++) {
        b->room = all[i]->shape[0] < b->room ? all[i]->shape[0] : b->room;
    }
    b->ops = DOUBLES(ops);
    b->slots = INT64S(slots);
    b->events = DOUBLES(events);
    b->rates = DOUBLES(rates);
    b->matrices = DOUBLES(matrices);
    b->patterns = INT64S(patterns);
}

/* the work space of take_builds */
static void free_builder(Builder *b)
{
    PyMem_Free(b->order);
    PyMem_Free(b->spans);
    PyMem_Free(b->work);
}

#endif
