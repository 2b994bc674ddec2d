/* Compiled assembly of the contact states of a foundation whose elements yield (docs/theory.md 14.2-14.3):
 * per state, A of X' = A X, the velocity map X -> p' and the 2 n_e event rows, from the structure's
 * terms and the state's pattern (each element in elastic contact C, yielding Y or lifted L). See
 * patterns.py (_soil_states) for the arguments; the numpy twin is soil_states_numpy.py. */

#include "buffers.h"
#include <stdlib.h>

typedef struct {
    const double *stiffness, *damping, *forcing, *masses, *position, *directions, *k, *c, *q, *displacement, *scales;
    const unsigned char *lifted, *yielding;
    const int64_t *massive, *massless, *tops, *settlements;
    int64_t count, n_p, n_aug, n_e, n_a, n_b, reaction;
    double *matrix, *velocity, *events;
} Soil;

/* the structure with the elements on the mat, item r: stiffness k_i e_i^T e_i in elastic contact, damping
 * c_i e_i^T e_i in contact or yielding, forcing k_i e_i^T in the column of s_i in contact and Q_i e_i^T in
 * that of the constant 1 while yielding (patterns.py) */
static void on_the_mat(const Soil *in, int64_t r, double *stiff, double *damp, double *force)
{
    const int64_t n_p = in->n_p, n = in->n_aug, n_e = in->n_e, one = n - 1;
    const double *e = in->directions + r * n_e * n_p, *k = in->k + r * n_e, *c = in->c + r * n_e,
                 *q = in->q + r * n_e;
    const unsigned char *lifted = in->lifted + r * n_e, *yielding = in->yielding + r * n_e;
    memcpy(force, in->forcing + r * n_p * n, n_p * n * sizeof(double));
    memset(stiff, 0, n_p * n_p * sizeof(double));
    memset(damp, 0, n_p * n_p * sizeof(double));
    for (int64_t i = 0; i < n_e; i++) {  /* the sums over the elements, i in order (e_i: theta and v only) */
        const double ek = lifted[i] || yielding[i] ? 0.0 : k[i], ec = lifted[i] ? 0.0 : c[i];
        const double *ei = e + i * n_p;
        for (int64_t p = 0; p < n_p; p++) {
            if (ei[p] == 0.0) {
                continue;
            }
            for (int64_t t = 0; t < n_p; t++) {
                if (ei[t] != 0.0) {
                    stiff[p * n_p + t] += ei[p] * ek * ei[t];
                    damp[p * n_p + t] += ei[p] * ec * ei[t];
                }
            }
        }
    }
    for (int64_t p = 0; p < n_p; p++) {
        for (int64_t t = 0; t < n_p; t++) {
            stiff[p * n_p + t] += in->stiffness[(r * n_p + p) * n_p + t];
            damp[p * n_p + t] += in->damping[(r * n_p + p) * n_p + t];
        }
        double capacity = 0.0;
        for (int64_t i = 0; i < n_e; i++) {
            if (!lifted[i] && !yielding[i]) {
                force[p * n + in->settlements[i]] += e[i * n_p + p] * k[i];
            }
            capacity += e[i * n_p + p] * (yielding[i] ? q[i] : 0.0);
        }
        force[p * n + one] += capacity;
    }
}

/* row (n_aug) := force[p] - damp[p] . velocity - stiff[p] . position (the generalised force of coordinate p):
 * the two sums along the rows of velocity and position (t in order, zero coefficients skipped), in `sums`
 * (2 n_aug) */
HOT_LOOP static void force_row(const Soil *in, int64_t p, const double *stiff, const double *damp,
                               const double *force, const double *velocity, double *row, double *sums)
{
    const int64_t n_p = in->n_p, n = in->n_aug;
    double *restrict d = sums, *restrict s = sums + n;
    for (int64_t col = 0; col < n; col++) {
        d[col] = s[col] = 0.0;
    }
    for (int64_t t = 0; t < n_p; t++) {
        const double dt = damp[p * n_p + t], st = stiff[p * n_p + t];
        const double *restrict v = velocity + t * n, *restrict x = in->position + t * n;
        if (dt != 0.0) {
            for (int64_t col = 0; col < n; col++) {
                d[col] += dt * v[col];
            }
        }
        if (st != 0.0) {
            for (int64_t col = 0; col < n; col++) {
                s[col] += st * x[col];
            }
        }
    }
    for (int64_t col = 0; col < n; col++) {
        row[col] = force[p * n + col] - d[col] - s[col];
    }
}

/* edge (n_e x n_aug) := the rows X -> v_i' of item r, e_i . velocity (p in order, zero entries of e_i
 * skipped: e_i reads theta and v only) */
HOT_LOOP static void edge_velocities(const Soil *in, int64_t r, double *edge)
{
    const int64_t n_p = in->n_p, n = in->n_aug, n_e = in->n_e;
    const double *velocity = in->velocity + r * n_p * n;
    for (int64_t i = 0; i < n_e; i++) {
        const double *e = in->directions + (r * n_e + i) * n_p;
        double *restrict to = edge + i * n;
        for (int64_t col = 0; col < n; col++) {
            to[col] = 0.0;
        }
        for (int64_t p = 0; p < n_p; p++) {
            if (e[p] == 0.0) {
                continue;
            }
            const double *restrict v = velocity + p * n;
            for (int64_t col = 0; col < n; col++) {
                to[col] += e[p] * v[col];
            }
        }
    }
}

/* the velocity map and A of item r (statespace.dynamics: the massive coordinates' velocities are state
 * entries, a massless one's from its first-order equation), with the rows of the yielding settlements
 * (s_i' = v_i') and of the lifted tops with a dashpot; 0 if a massless rotation has no damping */
static int dynamics(const Soil *in, int64_t r, const double *stiff, const double *damp, const double *force,
                    double *row, double *sums, double *edge)
{
    const int64_t n_p = in->n_p, n = in->n_aug, n_a = in->n_a, n_e = in->n_e;
    double *velocity = in->velocity + r * n_p * n, *matrix = in->matrix + r * n * n;
    memset(velocity, 0, n_p * n * sizeof(double));
    memset(matrix, 0, n * n * sizeof(double));
    for (int64_t t = 0; t < n_a; t++) {
        velocity[in->massive[t] * n + n_a + t] = 1.0;
    }
    for (int64_t u = 0; u < in->n_b; u++) {  /* at most one: the mat rotation without inertia */
        const int64_t b = in->massless[u];
        const double c_bb = damp[b * n_p + b];
        if (!(c_bb > 0.0)) {
            return 0;
        }
        force_row(in, b, stiff, damp, force, velocity, row, sums);
        for (int64_t col = 0; col < n; col++) {
            velocity[b * n + col] = row[col] / c_bb;
        }
        memcpy(matrix + (2 * n_a + u) * n, velocity + b * n, n * sizeof(double));
    }
    for (int64_t t = 0; t < n_a; t++) {
        const int64_t a = in->massive[t];
        memcpy(matrix + t * n, velocity + a * n, n * sizeof(double));
        force_row(in, a, stiff, damp, force, velocity, row, sums);
        for (int64_t col = 0; col < n; col++) {
            matrix[(n_a + t) * n + col] = row[col] / in->masses[r * n_p + a];
        }
    }
    matrix[(n - 3) * n + n - 2] = 1.0;
    edge_velocities(in, r, edge);
    const unsigned char *lifted = in->lifted + r * n_e, *yielding = in->yielding + r * n_e;
    for (int64_t i = 0; i < n_e; i++) {
        const double k = in->k[r * n_e + i], c = in->c[r * n_e + i];
        const int64_t z = in->tops[i], s = in->settlements[i];
        if (yielding[i]) {
            memcpy(matrix + s * n, edge + i * n, n * sizeof(double));
        }
        if (lifted[i] && c > 0.0) {
            matrix[z * n + z] = -(k / c);
            matrix[z * n + s] = k / c;
        }
    }
    return 1;
}

/* the 2 n_e event rows of item r (yielding.py; > 0: the element switches): row i the lift-off (C) or the
 * recontact (L), row n_e + i the onset of yield (C) or the unloading (Y), -1 (the constant) where a row
 * cannot cross; dimensionless: forces by W, displacements by the static settlement, velocities by g / w_v */
static void event_rows(const Soil *in, int64_t r, const double *edge)
{
    const int64_t n = in->n_aug, n_e = in->n_e, one = n - 1;
    const double weight = in->scales[3 * r], settlement = in->scales[3 * r + 1], vertical = in->scales[3 * r + 2];
    const unsigned char *lifted = in->lifted + r * n_e, *yielding = in->yielding + r * n_e;
    double *events = in->events + r * 2 * n_e * n;
    for (int64_t i = 0; i < n_e; i++) {
        const double k = in->k[r * n_e + i], c = in->c[r * n_e + i], q = in->q[r * n_e + i];
        const double *d = in->displacement + (r * n_e + i) * n;
        const int64_t s = in->settlements[i], top = c > 0.0 ? in->tops[i] : s;
        const double *ev = edge + i * n;
        double *first = events + i * n, *second = events + (n_e + i) * n;
        for (int64_t col = 0; col < n; col++) {
            const double spring = d[col] - (col == s ? 1.0 : 0.0), never = col == one ? -1.0 : -0.0;
            if (lifted[i]) {
                first[col] = ((col == top ? 1.0 : 0.0) - d[col]) / settlement;
            } else if (yielding[i]) {
                first[col] = never;
            } else {
                first[col] = in->reaction ? (k * spring + c * ev[col]) / weight : spring / settlement;
            }
            if (!lifted[i] && !yielding[i]) {
                second[col] = -(k * spring + q * (col == one ? 1.0 : 0.0)) / weight;
            } else {
                second[col] = yielding[i] ? ev[col] / (settlement * vertical) : never;
            }
        }
    }
}

static int soil_states(const Soil *in, double *scratch)
{
    const int64_t n_p = in->n_p;
    const int64_t n = in->n_aug;
    double *stiff = scratch, *damp = stiff + n_p * n_p, *force = damp + n_p * n_p, *row = force + n_p * n,
           *sums = row + n, *edge = sums + 2 * n;
    for (int64_t r = 0; r < in->count; r++) {
        on_the_mat(in, r, stiff, damp, force);
        if (!dynamics(in, r, stiff, damp, force, row, sums, edge)) {
            return 0;
        }
        event_rows(in, r, edge);
    }
    return 1;
}

static int consistent(const Soil *in, Py_buffer *const *b)
{
    const int64_t count = in->count, n_p = in->n_p, n = in->n_aug, n_e = in->n_e;
    int ok = n >= 3 && b[0]->shape[1] == n_p && b[0]->shape[2] == n_p && b[1]->shape[0] == count
             && b[1]->shape[1] == n_p && b[1]->shape[2] == n_p && b[2]->shape[0] == count && b[2]->shape[1] == n_p
             && b[3]->shape[0] == count && b[3]->shape[1] == n_p && b[4]->shape[0] == n_p && b[4]->shape[1] == n
             && b[5]->shape[0] == count && b[5]->shape[1] == n_e && b[5]->shape[2] == n_p && b[6]->shape[0] == count
             && b[6]->shape[1] == n_e && b[7]->shape[0] == count && b[7]->shape[1] == n_e && b[8]->shape[0] == count
             && b[8]->shape[1] == n_e && b[9]->shape[0] == count && b[9]->shape[1] == n_e && b[9]->shape[2] == n
             && b[10]->shape[0] == count && b[10]->shape[1] == 3 && b[11]->shape[0] == count && b[11]->shape[1] == n_e
             && b[12]->shape[0] == count && b[12]->shape[1] == n_e && b[15]->shape[0] == n_e && b[16]->shape[0] == n_e
             && b[17]->shape[0] == count && b[17]->shape[1] == n && b[17]->shape[2] == n && b[18]->shape[0] == count
             && b[18]->shape[1] == n_p && b[18]->shape[2] == n && b[19]->shape[0] == count
             && b[19]->shape[1] == 2 * n_e && b[19]->shape[2] == n && in->n_b <= 1 && in->n_a + in->n_b <= n_p
             && 2 * in->n_a + in->n_b <= n - 3;
    for (int64_t t = 0; ok && t < in->n_a; t++) {
        ok = in->massive[t] >= 0 && in->massive[t] < n_p;
    }
    for (int64_t u = 0; ok && u < in->n_b; u++) {
        ok = in->massless[u] >= 0 && in->massless[u] < n_p;
    }
    for (int64_t i = 0; ok && i < n_e; i++) {
        ok = in->tops[i] >= 0 && in->tops[i] < n - 3 && in->settlements[i] >= 0 && in->settlements[i] < n - 3;
    }
    return ok;
}

static PyObject *py_soil_states(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 21, "soil_states")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 3, 0, "stiffness"}, {1, 'd', 3, 0, "damping"},
        {2, 'd', 3, 0, "forcing"}, {3, 'd', 2, 0, "masses"}, {4, 'd', 2, 0, "position"},
        {5, 'd', 3, 0, "directions"}, {6, 'd', 2, 0, "element_stiffness"}, {7, 'd', 2, 0, "element_damping"},
        {8, 'd', 2, 0, "element_capacity"}, {9, 'd', 3, 0, "displacement_rows"}, {10, 'd', 2, 0, "scales"},
        {11, '?', 2, 0, "lifted"}, {12, '?', 2, 0, "yielding"}, {13, 'q', 1, 0, "massive"},
        {14, 'q', 1, 0, "massless"}, {15, 'q', 1, 0, "tops"}, {16, 'q', 1, 0, "settlements"},
        {18, 'd', 3, 1, "matrix"}, {19, 'd', 3, 1, "velocity"}, {20, 'd', 3, 1, "events"}};
    Py_buffer *b[20];
    if (!take_views(&v, args, arrays, 20, b)) {
        goto done;
    }
    const int reaction = PyObject_IsTrue(args[17]);
    if (reaction < 0) {
        goto done;
    }
    Soil in = {
        .stiffness = DOUBLES(b[0]), .damping = DOUBLES(b[1]), .forcing = DOUBLES(b[2]), .masses = DOUBLES(b[3]),
        .position = DOUBLES(b[4]), .directions = DOUBLES(b[5]), .k = DOUBLES(b[6]), .c = DOUBLES(b[7]),
        .q = DOUBLES(b[8]), .displacement = DOUBLES(b[9]), .scales = DOUBLES(b[10]), .lifted = BOOLS(b[11]),
        .yielding = BOOLS(b[12]), .massive = INT64S(b[13]), .massless = INT64S(b[14]), .tops = INT64S(b[15]),
        .settlements = INT64S(b[16]), .count = b[0]->shape[0], .n_p = b[0]->shape[1], .n_aug = b[2]->shape[2],
        .n_e = b[11]->shape[1], .n_a = b[13]->shape[0], .n_b = b[14]->shape[0], .reaction = reaction,
        .matrix = DOUBLES(b[17]), .velocity = DOUBLES(b[18]), .events = DOUBLES(b[19]),
    };
    if (!consistent(&in, b)) {
        PyErr_SetString(PyExc_ValueError, "soil_states: inconsistent array shapes");
        goto done;
    }
    double *scratch = malloc((2 * in.n_p * in.n_p + (in.n_p + 3 + in.n_e) * in.n_aug) * sizeof(double));
    if (!scratch) {
        PyErr_NoMemory();
        goto done;
    }
    int ok;
    Py_BEGIN_ALLOW_THREADS
    ok = soil_states(&in, scratch);
    Py_END_ALLOW_THREADS
    free(scratch);
    if (!ok) {
        PyErr_SetString(PyExc_ZeroDivisionError, "massless rotation with no damping");
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    release_views(&v);
    return result;
}

static PyMethodDef methods[] = {
    FASTCALL(soil_states, "Contact states of a foundation whose elements yield."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_soil_states, "The contact states of a foundation whose elements yield: A, velocity map, event rows.")
