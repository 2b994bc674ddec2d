/* Compiled loop of the exact engine's energy balance: the work integrals over the intervals
 * between samples. See response_kernels.work_integrals for the arguments; the numpy twin is in
 * tests/test_response_kernels.py. */

#include "buffers.h"
#include <math.h>
#include <stdlib.h>

static inline double hermite(double v0, double v1, double d0, double d1, double s)
{
    double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * d1;
}

/* gauss[g k + q]: the cubic Hermite interpolant of signal q (values v, slopes s at the ends of an
 * interval of `length`) at Gauss node g, from the Hermite basis there (it vectorises over q) */
static inline void interpolate_at_nodes(const double *restrict v0, const double *restrict s0,
                                        const double *restrict v1, const double *restrict s1, double length,
                                        int64_t k, const double basis[3][4], double *restrict gauss)
{
    for (int64_t q = 0; q < k; q++) {
        const double d0 = s0[q] * length, d1 = s1[q] * length;
        for (int g = 0; g < 3; g++) {
            gauss[g * k + q] = basis[g][0] * v0[q] + basis[g][1] * d0 + basis[g][2] * v1[q] + basis[g][3] * d1;
        }
    }
}

typedef struct {
    const double *values, *slopes, *end_values, *end_slopes, *lengths, *modal_damping, *element_stiffness,
        *element_damping;
    const int64_t *switch_;
    const unsigned char *lifted;
    int64_t n_intervals, k, k_s, k_e, n_interpolated, row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements;
} WorkInput;

/* Input work, structural and foundation damping energy [J] by 3-point Gauss quadrature on the
 * cubic Hermite interpolants of the signals in every interval (the dashpots of lifted elements
 * exactly: k (z0^2 - z1^2) / 2). gauss: 3 n_interpolated doubles of work space. */
HOT_LOOP static void work_integrals(const WorkInput *in, double *gauss, double out[3])
{
    const double root = sqrt(0.6);
    const double nodes[3] = {0.5 * (1.0 - root), 0.5, 0.5 * (1.0 + root)};
    const double weights[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    double basis[3][4]; /* Hermite basis h00, h10, h01, h11 at the Gauss nodes */
    for (int g = 0; g < 3; g++) {
        basis[g][0] = hermite(1.0, 0.0, 0.0, 0.0, nodes[g]);
        basis[g][1] = hermite(0.0, 0.0, 1.0, 0.0, nodes[g]);
        basis[g][2] = hermite(0.0, 1.0, 0.0, 0.0, nodes[g]);
        basis[g][3] = hermite(0.0, 0.0, 0.0, 1.0, nodes[g]);
    }
    const int64_t k = in->n_interpolated, kv = in->k, ks = in->k_s, ke = in->k_e;
    double work_in = 0.0, damp_struct = 0.0, damp_found = 0.0;
    for (int64_t i = 0; i < in->n_intervals; i++) {
        const double length = in->lengths[i];
        const int64_t fix = in->switch_[i];
        /* the right ends: the next sample, or the left limits where the interval ends at a transition */
        const double *v0 = in->values + i * kv, *s0 = in->slopes + i * ks;
        const double *v1 = fix >= 0 ? in->end_values + fix * kv : v0 + kv;
        const double *s1 = fix >= 0 ? in->end_slopes + fix * ke : s0 + ks;
        interpolate_at_nodes(v0, s0, v1, s1, length, k, basis, gauss);
        if (fix < 0) {
            /* the ground acceleration is linear inside the interval (its slope jumps at samples) */
            const int64_t q = in->row_a;
            const double d0 = s0[q] * length;
            for (int g = 0; g < 3; g++) {
                gauss[g * k + q] = basis[g][0] * v0[q] + basis[g][1] * d0 + basis[g][2] * v1[q] + basis[g][3] * d0;
            }
        }
        const unsigned char *lifted = in->lifted + i * in->n_elements;
        /* sum_n c_n Y_n*'^2 at the three nodes, each in the order of the modes (one pass over them) */
        double modal[3] = {0.0, 0.0, 0.0};
        for (int64_t mode = 0; mode < in->n_modes; mode++) {
            const double c = in->modal_damping[mode];
            const double y0 = gauss[in->row_ydot + mode], y1 = gauss[k + in->row_ydot + mode],
                         y2 = gauss[2 * k + in->row_ydot + mode];
            modal[0] += c * y0 * y0;
            modal[1] += c * y1 * y1;
            modal[2] += c * y2 * y2;
        }
        /* sum_e c_e v_e'^2 over the elements in contact at the three nodes, each in the order of the elements */
        double dashpots[3] = {0.0, 0.0, 0.0};
        for (int64_t e = 0; e < in->n_elements; e++) {
            const double c = in->element_damping[e];
            if (c > 0.0 && !lifted[e]) {
                for (int g = 0; g < 3; g++) {
                    const double vel = gauss[g * k + in->row_vel + e];
                    dashpots[g] += c * vel * vel;
                }
            }
        }
        for (int g = 0; g < 3; g++) {
            const double *at = gauss + g * k;
            double w = weights[g] * length;
            work_in += w * at[in->row_a] * at[in->row_input];
            damp_struct += w * modal[g];
            damp_found += w * dashpots[g];
        }
        /* a lifted element relaxes on its own, k z + c z' = 0: its dashpot dissipates exactly the
         * spring energy released, k (z0^2 - z1^2) / 2 (no quadrature: z may decay within the step) */
        for (int64_t e = 0; e < in->n_elements; e++) {
            if (in->element_damping[e] > 0.0 && lifted[e]) {
                double z0 = in->values[i * kv + in->row_z + e];
                double z1 = fix >= 0 ? in->end_values[fix * kv + in->row_z + e] : in->values[(i + 1) * kv + in->row_z + e];
                damp_found += 0.5 * in->element_stiffness[e] * (z0 * z0 - z1 * z1);
            }
        }
    }
    out[0] = work_in;
    out[1] = damp_struct;
    out[2] = damp_found;
}

/* ---------------------------------------------------------------------------- Python entry points */

/* work_integrals(values, slopes, switch, end_values, end_slopes, lengths, lifted, n_interpolated,
 *                row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements, modal_damping,
 *                element_stiffness, element_damping) -> (work_in, damp_struct, damp_found) */
static PyObject *py_work_integrals(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 18, "work_integrals")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "values"}, {1, 'd', 2, 0, "slopes"}, {2, 'q', 1, 0, "switch"},
        {3, 'd', 2, 0, "end_values"}, {4, 'd', 2, 0, "end_slopes"}, {5, 'd', 1, 0, "lengths"},
        {6, '?', 2, 0, "lifted"}, {15, 'd', 1, 0, "modal_damping"}, {16, 'd', 1, 0, "element_stiffness"},
        {17, 'd', 1, 0, "element_damping"}};
    Py_buffer *b[10];
    int taken = take_views(&v, args, arrays, 10, b);
    Py_buffer *values = b[0], *slopes = b[1], *switch_ = b[2], *end_values = b[3], *end_slopes = b[4], *lengths = b[5],
              *lifted = b[6], *modal = b[7], *stiffness = b[8], *damping = b[9];
    if (!taken) {
        goto done;
    }
    int64_t scalars[8];
    for (int a = 0; a < 8; a++) {
        scalars[a] = PyLong_AsLongLong(args[7 + a]);
    }
    if (PyErr_Occurred()) {
        goto done;
    }
    WorkInput in = {
        .values = DOUBLES(values), .slopes = DOUBLES(slopes), .end_values = DOUBLES(end_values),
        .end_slopes = DOUBLES(end_slopes), .lengths = DOUBLES(lengths), .modal_damping = DOUBLES(modal),
        .element_stiffness = DOUBLES(stiffness), .element_damping = DOUBLES(damping), .switch_ = INT64S(switch_),
        .lifted = BOOLS(lifted), .n_intervals = lengths->shape[0], .k = values->shape[1], .k_s = slopes->shape[1],
        .k_e = end_slopes->shape[1], .n_interpolated = scalars[0], .row_a = scalars[1], .row_input = scalars[2],
        .row_ydot = scalars[3], .n_modes = scalars[4], .row_vel = scalars[5], .row_z = scalars[6],
        .n_elements = scalars[7],
    };
    const int64_t k = in.n_interpolated;
    int ok = values->shape[0] == in.n_intervals + 1 && slopes->shape[0] == in.n_intervals + 1
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
    double *gauss = malloc((3 * k + 1) * sizeof(double));
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
