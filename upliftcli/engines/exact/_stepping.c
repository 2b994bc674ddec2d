/* Compiled stepping loop of the exact engine: see stepping_kernels.py for the method, the
 * arguments and the status codes (this file is its C body; the numpy twin is in
 * stepping_numpy.py). Operators and matrices are passed transposed (matvec). */

#include "buffers.h"
#include "events.h"
#include "transitions.h"
#include "builds.h"
#include <math.h>

enum { DONE, NEED_STATE, FULL, FLIGHT, NONFINITE, CHATTER };
#define MAX_EVENTS_PER_STEP 256
#define REFINE_LEVELS 5

typedef struct {
    int64_t status, step, state, n_out, pattern;
    double offset;
} Outcome;

/* the sample (t, x, state) at out_*[n_out]; n_out + 1 */
static inline int64_t kept_sample(double t, const double *x, int64_t state, int64_t n, double *out_t, double *out_x,
                                  int64_t *out_state, int64_t n_out)
{
    out_t[n_out] = t;
    memcpy(out_x + n_out * n, x, n * sizeof(double));
    out_state[n_out] = state;
    return n_out + 1;
}

HOT_LOOP static Outcome integrate(Model *m, const double *ground, const double *slopes, int64_t n_ground, double h,
                         int64_t index_acceleration, int64_t index_slope, double *x, double *out_x, double *out_t,
                         int64_t *out_state, int64_t capacity, int64_t state, int64_t step, double offset,
                         int64_t n_out, double *work, Builder *builder)
{
    const int64_t n = m->n, n_levels = m->levels, n_steps = n_ground - 1, n_e = m->n_events;
    double *trial = work, *left = work + n, *right = work + 2 * n, *tmp = work + 3 * n, *chunk = work + 4 * n;
    Outcome out;
    for (int64_t j = 0; j <= n_levels; j++) {
        chunk[j] = h / ldexp(1.0, (int)j);
    }
    const double smallest = chunk[n_levels];
    /* per state: whether it has event functions (a bonded run's are all zero), and what of their
     * values and rates at x stays known when a sample sets the ground acceleration and its slope
     * (those that do not depend on them); found when the loop first enters the state in this call
     * (classify), not for every state at every call: a yielding run meets hundreds of states and
     * calls this once per state, and a scan of them all cost it a sixth of its time (measured) */
    double *g_x = chunk + n_levels + 1, *d_x = g_x + n_e, *g_trial = d_x + n_e, *d_trial = g_trial + n_e,
           *scratch = d_trial + n_e;
    EventTables tables = {.tables = scratch + 3 * n_e, .slots = table_slots(m), .next = 0};
    tables.slot_of = (int64_t *)(tables.tables + tables.slots * n * 2 * n_e);
    tables.owner = tables.slot_of + m->room;
    unsigned char *active = (unsigned char *)(tables.owner + tables.slots), *ground_free = active + m->room;
    memset(active, UNCLASSIFIED, m->room);
    memset(tables.slot_of, 0xff, (m->room + tables.slots) * sizeof(int64_t)); /* -1: no slot, no state */
    const double *table = entered(m, state, index_acceleration, index_slope, active, ground_free, &tables);
    int known = 0;
#define RETURN(code, with_pattern)                                                                                    \
    do {                                                                                                               \
        out.status = (code);                                                                                           \
        out.step = step;                                                                                               \
        out.offset = offset;                                                                                           \
        out.state = state;                                                                                             \
        out.n_out = n_out;                                                                                             \
        out.pattern = (with_pattern);                                                                                  \
        return out;                                                                                                    \
    } while (0)
    while (step < n_steps) {
        if (n_out + MAX_EVENTS_PER_STEP + 1 > capacity) {
            RETURN(FULL, m->patterns[state]);
        }
        int64_t events_in_step = 0;
        if (offset == 0.0) {
            x[index_acceleration] = ground[step];
            x[index_slope] = slopes[step];
            known &= ground_free[state];
        }
        for (;;) {
            double remaining = h - offset;
            if (remaining < smallest * (1.0 - 1e-9)) {
                if (remaining > 0.0) {
                    known = 0;
                    /* sub-sliver close: second-order Taylor step (error ~ (|A| h 2^-L)^3) */
                    const double *matrix_t = m->matrices + state * n * n;
                    matvec(matrix_t, x, tmp, n);
                    matvec(matrix_t, tmp, trial, n);
                    for (int64_t i = 0; i < n; i++) {
                        x[i] += remaining * tmp[i] + 0.5 * remaining * remaining * trial[i];
                    }
                }
                break;
            }
            int64_t level = 0;
            while (level < n_levels && chunk[level] > remaining * (1.0 + 1e-12)) {
                level++;
            }
            const int64_t n_events = table ? n_e : 0;
            /* the event functions and their rates at x (g_x, then d_x), kept while they stay */
            if (!(known & VALUES)) {
                if (n_events) {
                    register_product(table, 2 * n_events, x, n, 2 * n_events, g_x);
                }
                known = VALUES | RATES;
            } else if (!(known & RATES)) {
                if (n_events) {
                    register_product(table + n_events, 2 * n_events, x, n, n_events, d_x);
                }
                known |= RATES;
            }
            matvec(op_of(m, state, level), x, trial, n);
            if (n_events) {
                register_product(table, 2 * n_events, trial, n, 2 * n_events, g_trial);
            }
            int crossed = any_above(g_trial, n_events);
            /* an event function may rise above zero and fall back inside the chunk: halve it
             * while its cubic interpolant says so (down to h / 2^REFINE_LEVELS) */
            while (!crossed && level < REFINE_LEVELS
                   && excursion_between(g_x, d_x, g_trial, d_trial, n_events, chunk[level])) {
                level++;
                matvec(op_of(m, state, level), x, trial, n);
                register_product(table, 2 * n_events, trial, n, 2 * n_events, g_trial); /* n_events > 0 here */
                crossed = any_above(g_trial, n_events);
            }
            if (!crossed) {
                memcpy(x, trial, n * sizeof(double));
                memcpy(g_x, g_trial, 2 * n_events * sizeof(double)); /* d_x and d_trial follow */
                offset += chunk[level];
                continue;
            }
            known = 0;
            double fraction;
            double start = crossing(m, state, table, x, level, chunk, g_x, g_trial, left, trial, right, &fraction,
                                    scratch);
            for (int64_t j = 0; j < n; j++) {
                x[j] = left[j] + fraction * (right[j] - left[j]);
            }
            offset += start + fraction * smallest;
            int64_t pattern = switch_pattern(m, state, table, m->patterns[state], x, scratch);
            if ((pattern & m->all_lifted) == m->all_lifted && !m->allow_flight) { /* story bits aside */
                RETURN(FLIGHT, pattern);
            }
            int64_t new_state = -1;
            for (int64_t s = 0; s < m->count; s++) {
                if (m->patterns[s] == pattern) {
                    new_state = s;
                    break;
                }
            }
            if (new_state < 0) {
                new_state = builder ? build_state(m, builder, pattern) : -1;
                if (new_state < 0) {
                    RETURN(NEED_STATE, pattern);
                }
                /* entered as the caller entered a state it built (stepping.Run.enter, then integrate again):
                 * the sample where it starts, the step's events counted afresh, a full buffer returned */
                state = new_state;
                table = entered(m, state, index_acceleration, index_slope, active, ground_free, &tables);
                n_out = kept_sample(step * h + offset, x, state, n, out_t, out_x, out_state, n_out);
                events_in_step = 0;
                if (n_out + MAX_EVENTS_PER_STEP + 1 > capacity) {
                    RETURN(FULL, m->patterns[state]);
                }
                if (offset == 0.0) {
                    x[index_acceleration] = ground[step];
                    x[index_slope] = slopes[step];
                }
                continue;
            }
            state = new_state;
            table = entered(m, state, index_acceleration, index_slope, active, ground_free, &tables);
            events_in_step++;
            if (events_in_step >= MAX_EVENTS_PER_STEP) {
                RETURN(CHATTER, pattern);
            }
            n_out = kept_sample(step * h + offset, x, state, n, out_t, out_x, out_state, n_out);
        }
        step++;
        offset = 0.0;
        x[index_acceleration] = ground[step];
        if (step < n_steps) {
            /* the sample opens the next interval: it carries that interval's ground slope */
            x[index_slope] = slopes[step];
        }
        known &= ground_free[state];
        int finite = 1;
        for (int64_t i = 0; i < n; i++) {
            if (!isfinite(x[i])) {
                finite = 0;
            }
        }
        if (!finite) {
            RETURN(NONFINITE, m->patterns[state]);
        }
        n_out = kept_sample(step * h, x, state, n, out_t, out_x, out_state, n_out);
    }
    RETURN(DONE, m->patterns[state]);
#undef RETURN
}

/* integrate(states, elements, grid, samples, state, step, offset, n_out[, builds]) with the tuples
 *   states = (ops, slots, events, event_rates, matrices, patterns, count),
 *   elements = (z_index, lift_rows, damped, all_lifted, allow_flight),
 *   grid = (ground, slopes, h, levels, index_acceleration, index_slope),
 *   samples = (x, out_x, out_t, out_state),
 *   builds = None or stepping_kernels.Builds (the states of yielding stories the loop builds: builds.h)
 * -> (status, step, offset, state, n_out, pattern). Every index the loop follows is checked first. */
static PyObject *py_integrate(PyObject *self, PyObject *const *call, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 9 && !expect_args(nargs, 8, "integrate")) {
        return NULL;
    }
    PyObject *builds = nargs == 9 && call[8] != Py_None ? call[8] : NULL;
    PyObject *args[26]; /* the items of the four tuples, then state, step, offset, n_out */
    if (!unpack(call[0], 7, "integrate", "states", args) || !unpack(call[1], 5, "integrate", "elements", args + 7)
        || !unpack(call[2], 6, "integrate", "grid", args + 12) || !unpack(call[3], 4, "integrate", "samples", args + 18)) {
        return NULL;
    }
    for (int i = 0; i < 4; i++) {
        args[22 + i] = call[4 + i];
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    Builder builder = {.n_bases = 0}, *building = NULL;
    static const ArraySpec specs[] = {{0, 'd', 4, 0, "ops"}, {1, 'q', 1, 0, "slots"}, {2, 'd', 3, 0, "events"},
        {3, 'd', 3, 0, "event_rates"}, {4, 'd', 3, 0, "matrices"}, {5, 'q', 1, 0, "patterns"}, {7, 'q', 1, 0, "z_index"},
        {8, 'd', 2, 0, "lift_rows"}, {9, '?', 1, 0, "damped"}, {12, 'd', 1, 0, "ground"}, {13, 'd', 1, 0, "slopes"},
        {18, 'd', 1, 1, "x"}, {19, 'd', 2, 1, "out_x"}, {20, 'd', 1, 1, "out_t"}, {21, 'q', 1, 1, "out_state"}};
    ArraySpec arrays[15]; /* the states' arrays written where the loop builds states (builds.h) */
    memcpy(arrays, specs, sizeof(arrays));
    for (int i = 0; i < 6; i++) {
        arrays[i].writable = builds != NULL;
    }
    Py_buffer *b[15];
    int taken = take_views(&v, args, arrays, 15, b);
    Py_buffer *ops = b[0], *op_slots = b[1], *events = b[2], *rates = b[3], *matrices = b[4], *patterns = b[5],
              *z_index = b[6], *lift_rows = b[7], *damped = b[8], *ground = b[9], *slopes = b[10], *x = b[11],
              *out_x = b[12], *out_t = b[13], *out_state = b[14];
    if (!taken) {
        goto done;
    }
    Model m = {
        .ops = DOUBLES(ops), .slots = INT64S(op_slots), .events = DOUBLES(events), .rates = DOUBLES(rates),
        .matrices = DOUBLES(matrices),
        .patterns = INT64S(patterns), .count = PyLong_AsLongLong(args[6]), .n_events = events->shape[1],
        .n = x->shape[0], .levels = PyLong_AsLongLong(args[15]), .z_index = INT64S(z_index),
        .lift_rows = DOUBLES(lift_rows), .damped = BOOLS(damped), .all_lifted = PyLong_AsLongLong(args[10]),
        .allow_flight = PyObject_IsTrue(args[11]),
    };
    double h = PyFloat_AsDouble(args[14]);
    int64_t index_acceleration = PyLong_AsLongLong(args[16]), index_slope = PyLong_AsLongLong(args[17]);
    int64_t state = PyLong_AsLongLong(args[22]), step = PyLong_AsLongLong(args[23]);
    double offset = PyFloat_AsDouble(args[24]);
    int64_t n_out = PyLong_AsLongLong(args[25]);
    if (PyErr_Occurred() || m.allow_flight < 0) {
        goto done;
    }
    const int64_t n = m.n, n_e = m.n_events, capacity = out_t->shape[0], n_steps = ground->shape[0] - 1;
    /* shapes: every state's arrays for `count` states, its slot of n x n operators at levels 0..L */
    int ok = n >= 1 && m.count >= 1 && m.count <= op_slots->shape[0] && m.count <= events->shape[0]
             && m.count <= matrices->shape[0] && m.count <= patterns->shape[0] && ops->shape[1] == m.levels + 1
             && ops->shape[2] == n && ops->shape[3] == n && matrices->shape[1] == n && matrices->shape[2] == n
             && events->shape[2] == n && rates->shape[0] == events->shape[0] && rates->shape[1] == n_e
             && rates->shape[2] == n;
    for (int64_t s = 0; ok && s < m.count; s++) {
        ok = m.slots[s] >= 0 && m.slots[s] < ops->shape[0];
    }
    /* elements: at most 62 (the contact pattern is a bit set), their state indices inside the state */
    ok = ok && n_e <= 62 && z_index->shape[0] == n_e && lift_rows->shape[0] == n_e && lift_rows->shape[1] == n
         && damped->shape[0] == n_e;
    for (int64_t i = 0; ok && i < n_e; i++) {
        ok = INT64S(z_index)[i] >= 0 && INT64S(z_index)[i] < n;
    }
    /* the grid, the bisection levels (the refinement uses levels up to REFINE_LEVELS) and where to start */
    ok = ok && n_steps >= 0 && slopes->shape[0] >= n_steps && isfinite(h) && h > 0.0 && m.levels >= REFINE_LEVELS
         && m.levels <= 60 && index_acceleration >= 0 && index_acceleration < n && index_slope >= 0
         && index_slope < n && state >= 0 && state < m.count && step >= 0 && step <= n_steps && isfinite(offset)
         && offset >= 0.0;
    /* the sample buffers: the loop writes at most MAX_EVENTS_PER_STEP + 1 samples past n_out per step and
     * returns FULL before a step that might not fit */
    ok = ok && out_x->shape[0] >= capacity && out_x->shape[1] == n && out_state->shape[0] >= capacity && n_out >= 0
         && n_out <= capacity;
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "integrate: inconsistent arguments (shapes, indices or limits)");
        goto done;
    }
    m.room = m.count;
    if (builds) {
        if (!take_builds(&v, builds, &m, &builder)) {
            if (!PyErr_Occurred()) {
                PyErr_SetString(PyExc_ValueError,
                                "integrate: builds inconsistent with the states (stepping_kernels.Builds)");
            }
            goto done;
        }
        builder_arrays(&builder, ops, op_slots, events, rates, matrices, patterns);
        m.room = builder.room > m.count ? builder.room : m.count;
        building = &builder;
    }
    /* work space of integrate: 4 states, the chunk lengths, 7 event vectors, the event tables (EventTables:
     * the tables, a slot per state, a state per slot), 2 flags per state */
    const int64_t slots = table_slots(&m);
    double *work = PyMem_Malloc((4 * n + m.levels + 1 + 7 * n_e + slots * n * 2 * n_e + m.room + slots
                                 + (2 * m.room) / sizeof(double) + 1) * sizeof(double));
    if (!work) {
        PyErr_NoMemory();
        goto done;
    }
    Outcome o;
    Py_BEGIN_ALLOW_THREADS
    o = integrate(&m, DOUBLES(ground), DOUBLES(slopes), ground->shape[0], h, index_acceleration, index_slope,
                  DOUBLES(x), DOUBLES(out_x), DOUBLES(out_t), INT64S(out_state), capacity, state, step, offset,
                  n_out, work, building);
    Py_END_ALLOW_THREADS
    PyMem_Free(work);
    result = Py_BuildValue("(LLdLLL)", (long long)o.status, (long long)o.step, o.offset, (long long)o.state,
                           (long long)o.n_out, (long long)o.pattern);
done:
    free_builder(&builder);
    release_views(&v);
    return result;
}

/* matvec(matrix_t, x, out): out = M x from M^T (tests) */
static PyObject *py_matvec(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 3, "matvec")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "matrix_t"}, {1, 'd', 1, 0, "x"}, {2, 'd', 1, 1, "out"}};
    Py_buffer *b[3];
    int taken = take_views(&v, args, arrays, 3, b);
    Py_buffer *matrix_t = b[0], *x = b[1], *out = b[2];
    if (taken) {
        int64_t n = x->shape[0];
        if (matrix_t->shape[0] != n || matrix_t->shape[1] != n || out->shape[0] != n) {
            PyErr_SetString(PyExc_ValueError, "matvec: inconsistent array shapes");
        } else {
            matvec(DOUBLES(matrix_t), DOUBLES(x), DOUBLES(out), n);
            result = Py_NewRef(Py_None);
        }
    }
    release_views(&v);
    return result;
}

/* excursion(events, rates, x, y, length) -> bool (tests) */
static PyObject *py_excursion(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 5, "excursion")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "events"}, {1, 'd', 2, 0, "rates"}, {2, 'd', 1, 0, "x"},
        {3, 'd', 1, 0, "y"}};
    Py_buffer *b[4];
    int taken = take_views(&v, args, arrays, 4, b);
    Py_buffer *events = b[0], *rates = b[1], *x = b[2], *y = b[3];
    double length = taken ? PyFloat_AsDouble(args[4]) : 0.0;
    if (taken && !PyErr_Occurred()) {
        int64_t n = x->shape[0];
        if (events->shape[1] != n || rates->shape[1] != n || rates->shape[0] != events->shape[0] || y->shape[0] != n) {
            PyErr_SetString(PyExc_ValueError, "excursion: inconsistent array shapes");
        } else {
            double *work = PyMem_Malloc((4 * events->shape[0] + 1) * sizeof(double));
            if (!work) {
                PyErr_NoMemory();
            } else {
                result = PyBool_FromLong(excursion(DOUBLES(events), DOUBLES(rates), events->shape[0], DOUBLES(x),
                                                   DOUBLES(y), n, length, work));
                PyMem_Free(work);
            }
        }
    }
    release_views(&v);
    return result;
}

static PyMethodDef methods[] = {
    FASTCALL(integrate, "The stepping loop (stepping_kernels.py)."),
    FASTCALL(matvec, "out = M x from M^T."),
    FASTCALL(excursion, "The interior-excursion test."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_stepping, "Compiled stepping loop of the exact engine.")
