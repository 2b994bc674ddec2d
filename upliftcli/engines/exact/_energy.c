/* Compiled loop of the exact engine's energy balance: the work integrals over the intervals
 * between samples. See energy.py (work) for the arguments; the numpy twin is energy_numpy.py. */

#include "buffers.h"
#include <math.h>
#include <stdlib.h>

/* the quintic Hermite interpolant on [0, 1] through p0, p1, slopes d0, d1 and curvatures c0, c1
 * (slopes times the interval length, curvatures times its square) at s */
static inline double quintic(double p0, double d0, double c0, double p1, double d1, double c1, double s)
{
    const double a2 = 0.5 * c0;
    const double a3 = -1.5 * c0 + 0.5 * c1 - 6.0 * d0 - 4.0 * d1 - 10.0 * p0 + 10.0 * p1;
    const double a4 = 1.5 * c0 - c1 + 8.0 * d0 + 7.0 * d1 + 15.0 * p0 - 15.0 * p1;
    const double a5 = -0.5 * c0 + 0.5 * c1 - 3.0 * d0 - 3.0 * d1 - 6.0 * p0 + 6.0 * p1;
    return p0 + s * (d0 + s * (a2 + s * (a3 + s * (a4 + s * a5))));
}

#define NODES 6

/* 6-point Gauss-Legendre on [0, 1]: exact to degree 11, so for the products of two quintics */
static void gauss_rule(double nodes[NODES], double weights[NODES])
{
    static const double x[3] = {0.2386191860831969086, 0.6612093864662645137, 0.9324695142031520278};
    static const double w[3] = {0.4679139345726910474, 0.3607615730481386076, 0.1713244923791703450};
    for (int j = 0; j < 3; j++) {
        nodes[2 - j] = 0.5 * (1.0 - x[j]);
        nodes[3 + j] = 0.5 * (1.0 + x[j]);
        weights[2 - j] = weights[3 + j] = 0.5 * w[j];
    }
}

/* gauss[g k + q], q in [lo, hi): the quintic Hermite interpolant of signal q at Gauss node g, from the
 * basis there (basis[g] holds the weights of p0, d0, c0, p1, d1, c1) */
static inline void interpolate_at_nodes(const double *restrict v0, const double *restrict s0,
                                        const double *restrict c0, const double *restrict v1,
                                        const double *restrict s1, const double *restrict c1, double length,
                                        int64_t lo, int64_t hi, int64_t k, const double basis[NODES][6],
                                        double *restrict gauss)
{
    const double l2 = length * length;
    for (int64_t q = lo; q < hi; q++) {
        const double d0 = s0[q] * length, d1 = s1[q] * length, e0 = c0[q] * l2, e1 = c1[q] * l2;
        for (int g = 0; g < NODES; g++) {
            const double *b = basis[g];
            gauss[g * k + q] = b[0] * v0[q] + b[1] * d0 + b[2] * e0 + b[3] * v1[q] + b[4] * d1 + b[5] * e1;
        }
    }
}

typedef struct {
    const double *values, *slopes, *curvatures, *end_curvatures, *end_values, *end_slopes, *lengths,
        *modal_damping, *element_stiffness, *element_damping;
    const int64_t *switch_;
    const unsigned char *lifted;
    int64_t n_intervals, k, k_s, k_e, k_c, n_interpolated, row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements;
} WorkInput;

/* the integrands at one node: input work, structural and foundation damping power */
static inline void powers(const WorkInput *in, const double *at, const unsigned char *lifted, double out[3])
{
    out[0] = at[in->row_a] * at[in->row_input];
    double acc = 0.0;
    for (int64_t mode = 0; mode < in->n_modes; mode++) {
        const double yd = at[in->row_ydot + mode];
        acc += in->modal_damping[mode] * yd * yd;
    }
    out[1] = acc;
    acc = 0.0;
    for (int64_t e = 0; e < in->n_elements; e++) {
        const double c = in->element_damping[e];
        if (c > 0.0 && !lifted[e]) {
            const double vel = at[in->row_vel + e];
            acc += c * vel * vel;
        }
    }
    out[2] = acc;
}

/* a lifted element relaxes on its own, k z + c z' = 0: its dashpot dissipates exactly the spring energy
 * released, k (z0^2 - z1^2) / 2 (no quadrature: z may decay within the step) */
static inline double relaxation(const WorkInput *in, int64_t i, const double *v1, const unsigned char *lifted)
{
    double released = 0.0;
    for (int64_t e = 0; e < in->n_elements; e++) {
        if (in->element_damping[e] > 0.0 && lifted[e]) {
            const double z0 = in->values[i * in->k + in->row_z + e], z1 = v1[in->row_z + e];
            released += 0.5 * in->element_stiffness[e] * (z0 * z0 - z1 * z1);
        }
    }
    return released;
}

/* Input work, structural and foundation damping energy [J] by 6-point Gauss quadrature on the
 * quintic Hermite interpolants of the signals (values, exact slopes and curvatures at both ends)
 * in every interval, the dashpots of lifted elements exactly. gauss: NODES n_interpolated doubles
 * of work space. */
HOT_LOOP static void work_integrals(const WorkInput *in, double *gauss, double out[3])
{
    double nodes[NODES], weights[NODES], basis[NODES][6];
    gauss_rule(nodes, weights);
    for (int g = 0; g < NODES; g++) {
        for (int j = 0; j < 6; j++) {
            double unit[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
            unit[j] = 1.0;
            basis[g][j] = quintic(unit[0], unit[1], unit[2], unit[3], unit[4], unit[5], nodes[g]);
        }
    }
    const int64_t k = in->n_interpolated, kv = in->k, ks = in->k_s, ke = in->k_e;
    double total[3] = {0.0, 0.0, 0.0};
    for (int64_t i = 0; i < in->n_intervals; i++) {
        const double length = in->lengths[i];
        const int64_t fix = in->switch_[i];
        /* the right ends: the next sample, or the left limits where the interval ends at a transition */
        const double *v0 = in->values + i * kv, *s0 = in->slopes + i * ks;
        const double *v1 = fix >= 0 ? in->end_values + fix * kv : v0 + kv;
        const double *s1 = fix >= 0 ? in->end_slopes + fix * ke : s0 + ks;
        /* the signals the integrands read: the modal velocities, the input signal, the element velocities */
        const double *c0 = in->curvatures + i * in->k_c, *c1 = in->end_curvatures + i * in->k_c;
        interpolate_at_nodes(v0, s0, c0, v1, s1, c1, length, in->row_ydot, in->row_ydot + in->n_modes, k, basis, gauss);
        interpolate_at_nodes(v0, s0, c0, v1, s1, c1, length, in->row_input, in->row_input + 1, k, basis, gauss);
        interpolate_at_nodes(v0, s0, c0, v1, s1, c1, length, in->row_vel, in->row_vel + in->n_elements, k, basis, gauss);
        /* the ground acceleration is linear inside the interval (its slope jumps at samples) */
        const int64_t q = in->row_a;
        for (int g = 0; g < NODES; g++) {
            gauss[g * k + q] = v0[q] + s0[q] * length * nodes[g];
        }
        const unsigned char *lifted = in->lifted + i * in->n_elements;
        for (int g = 0; g < NODES; g++) {
            double p[3];
            powers(in, gauss + g * k, lifted, p);
            for (int j = 0; j < 3; j++) {
                total[j] += weights[g] * length * p[j];
            }
        }
        total[2] += relaxation(in, i, v1, lifted);
    }
    for (int j = 0; j < 3; j++) {
        out[j] = total[j];
    }
}

/* ---------------------------------------------------------------------------- Python entry points */

/* work_integrals(values, slopes, curvatures, end_curvatures, switch, end_values, end_slopes, lengths, lifted,
 *                n_interpolated, row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements, modal_damping,
 *                element_stiffness, element_damping) -> (work_in, damp_struct, damp_found) */
static PyObject *py_work_integrals(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 20, "work_integrals")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "values"}, {1, 'd', 2, 0, "slopes"},
        {2, 'd', 2, 0, "curvatures"}, {3, 'd', 2, 0, "end_curvatures"}, {4, 'q', 1, 0, "switch"},
        {5, 'd', 2, 0, "end_values"}, {6, 'd', 2, 0, "end_slopes"}, {7, 'd', 1, 0, "lengths"},
        {8, '?', 2, 0, "lifted"}, {17, 'd', 1, 0, "modal_damping"}, {18, 'd', 1, 0, "element_stiffness"},
        {19, 'd', 1, 0, "element_damping"}};
    Py_buffer *b[12];
    int taken = take_views(&v, args, arrays, 12, b);
    Py_buffer *values = b[0], *slopes = b[1], *curvatures = b[2], *end_curvatures = b[3], *switch_ = b[4],
              *end_values = b[5], *end_slopes = b[6], *lengths = b[7], *lifted = b[8], *modal = b[9],
              *stiffness = b[10], *damping = b[11];
    if (!taken) {
        goto done;
    }
    int64_t scalars[8];
    for (int a = 0; a < 8; a++) {
        scalars[a] = PyLong_AsLongLong(args[9 + a]);
    }
    if (PyErr_Occurred()) {
        goto done;
    }
    WorkInput in = {
        .values = DOUBLES(values), .slopes = DOUBLES(slopes), .curvatures = DOUBLES(curvatures),
        .end_curvatures = DOUBLES(end_curvatures), .end_values = DOUBLES(end_values),
        .end_slopes = DOUBLES(end_slopes), .lengths = DOUBLES(lengths), .modal_damping = DOUBLES(modal),
        .element_stiffness = DOUBLES(stiffness), .element_damping = DOUBLES(damping), .switch_ = INT64S(switch_),
        .lifted = BOOLS(lifted), .n_intervals = lengths->shape[0], .k = values->shape[1], .k_s = slopes->shape[1],
        .k_e = end_slopes->shape[1], .k_c = curvatures->shape[1], .n_interpolated = scalars[0], .row_a = scalars[1], .row_input = scalars[2],
        .row_ydot = scalars[3], .n_modes = scalars[4], .row_vel = scalars[5], .row_z = scalars[6],
        .n_elements = scalars[7],
    };
    const int64_t k = in.n_interpolated;
    int ok = values->shape[0] == in.n_intervals + 1 && slopes->shape[0] == in.n_intervals + 1
             && curvatures->shape[0] >= in.n_intervals && end_curvatures->shape[0] >= in.n_intervals
             && end_curvatures->shape[1] == in.k_c && in.row_ydot + in.n_modes <= in.k_c
             && in.row_input < in.k_c && in.row_vel + in.n_elements <= in.k_c
             && switch_->shape[0] >= in.n_intervals && lifted->shape[0] >= in.n_intervals
             && lifted->shape[1] == in.n_elements && k <= in.k_s && k <= in.k_e && end_values->shape[1] == in.k
             && in.row_a >= 0 && in.row_a < k && in.row_input >= 0 && in.row_input < k && in.row_ydot >= 0
             && in.row_ydot + in.n_modes <= k && in.row_vel >= 0 && in.row_vel + in.n_elements <= k
             && in.row_z >= 0 && in.row_z + in.n_elements <= in.k && modal->shape[0] >= in.n_modes
             && stiffness->shape[0] >= in.n_elements && damping->shape[0] >= in.n_elements;
    for (int64_t i = 0; ok && i < in.n_intervals; i++) {
        ok = in.switch_[i] < end_values->shape[0];
    }
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "work_integrals: inconsistent array shapes");
        goto done;
    }
    double *gauss = malloc((NODES * k + 1) * sizeof(double));
    if (!gauss) {
        PyErr_NoMemory();
        goto done;
    }
    double out[3];
    Py_BEGIN_ALLOW_THREADS
    work_integrals(&in, gauss, out);
    Py_END_ALLOW_THREADS
    free(gauss);
    result = Py_BuildValue("(ddd)", out[0], out[1], out[2]);
done:
    release_views(&v);
    return result;
}

static PyMethodDef methods[] = {
    FASTCALL(work_integrals, "Work integrals."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_energy, "The work integrals of the exact engine's energy balance.")
