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

/* What the integrals need of the quintic Hermite basis b_j on [0, 1] (the weights of p0, d0, c0, p1, d1,
 * c1): its moments int b_j and int s b_j (times a linear ground acceleration) and its Gram matrix
 * int b_j b_k split by the symmetry s -> 1 - s (b_p0 <-> b_p1, b_d0 <-> -b_d1, b_c0 <-> b_c1): with the
 * even sums e = (p0 + p1, d0 - d1, c0 + c1) and odd differences o = (p0 - p1, d0 + d1, c0 - c1),
 * int p^2 = e^T E e + o^T O o (the even and odd parts of p are orthogonal); E and O as upper triangles,
 * the off-diagonal entries doubled. All by the 6-point Gauss rule (exact: degree 10 at most). */
typedef struct {
    double even[3][3], odd[3][3], mean[6], first[6];
} Basis;

/* the 3 x 3 block of the Gram matrix g for the coefficients u = (x, sign x) / 2, as an upper triangle with
 * the off-diagonal entries doubled (sign: +1 for E, -1 for O; d1 enters the other way round) */
static void symmetric_block(const double g[6][6], double sign, double out[3][3])
{
    const double r[3] = {sign, -sign, sign};
    for (int j = 0; j < 3; j++) {
        for (int k = 0; k < 3; k++) {
            const double sum = g[j][k] + r[k] * g[j][3 + k] + r[j] * g[3 + j][k] + r[j] * r[k] * g[3 + j][3 + k];
            out[j][k] = k < j ? 0.0 : (k == j ? 0.25 : 0.5) * sum;
        }
    }
}

static void basis_integrals(Basis *out)
{
    double nodes[NODES], weights[NODES], b[NODES][6], gram[6][6];
    gauss_rule(nodes, weights);
    for (int g = 0; g < NODES; g++) {
        for (int j = 0; j < 6; j++) {
            double unit[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
            unit[j] = 1.0;
            b[g][j] = quintic(unit[0], unit[1], unit[2], unit[3], unit[4], unit[5], nodes[g]);
        }
    }
    for (int j = 0; j < 6; j++) {
        out->mean[j] = out->first[j] = 0.0;
        for (int g = 0; g < NODES; g++) {
            out->mean[j] += weights[g] * b[g][j];
            out->first[j] += weights[g] * nodes[g] * b[g][j];
        }
        for (int k = 0; k < 6; k++) {
            gram[j][k] = 0.0;
            for (int g = 0; g < NODES; g++) {
                gram[j][k] += weights[g] * b[g][j] * b[g][k];
            }
        }
    }
    symmetric_block(gram, 1.0, out->even);
    symmetric_block(gram, -1.0, out->odd);
}

/* int_0^1 p_q(s)^2 ds of the quintic Hermite p_q through values v0[q], v1[q], slopes s0[q], s1[q] and
 * curvatures c0[q], c1[q] + jump_row[q] jump (times the interval length and its square) for q < count, into
 * out: elementwise, so it vectorises */
static inline void squared_integrals(const Basis *basis, const double *restrict v0, const double *restrict s0,
                                     const double *restrict c0, const double *restrict v1,
                                     const double *restrict s1, const double *restrict c1,
                                     const double *restrict jump_row, double jump, double length, int64_t count,
                                     double *restrict out)
{
    const double (*e)[3] = basis->even, (*o)[3] = basis->odd, l2 = length * length;
    const double e00 = e[0][0], e01 = e[0][1], e02 = e[0][2], e11 = e[1][1], e12 = e[1][2], e22 = e[2][2];
    const double o00 = o[0][0], o01 = o[0][1], o02 = o[0][2], o11 = o[1][1], o12 = o[1][2], o22 = o[2][2];
    for (int64_t q = 0; q < count; q++) {
        const double d0 = s0[q] * length, d1 = s1[q] * length, k0 = c0[q] * l2, k1 = (c1[q] + jump_row[q] * jump) * l2;
        const double x0 = v0[q] + v1[q], x1 = d0 - d1, x2 = k0 + k1, y0 = v0[q] - v1[q], y1 = d0 + d1, y2 = k0 - k1;
        out[q] = x0 * (e00 * x0 + e01 * x1 + e02 * x2) + x1 * (e11 * x1 + e12 * x2) + x2 * (e22 * x2)
                 + (y0 * (o00 * y0 + o01 * y1 + o02 * y2) + y1 * (o11 * y1 + o12 * y2) + y2 * (o22 * y2));
    }
}

typedef struct {
    const double *values, *slopes, *end_values, *end_slopes, *slope_rows, *lengths, *modal_damping,
        *element_stiffness, *element_damping;
    const int64_t *switch_, *ids;
    const unsigned char *lifted;
    int64_t n_intervals, k, k_s, k_e, k_c, row_a, row_input, row_ydot, n_modes, row_vel, row_z, n_elements,
        curvature_ydot, curvature_input, curvature_vel;
} WorkInput;

/* One interval: its length, the values and slopes at its start and right end (the next sample, or the
 * left limits where it ends at a transition), and what the right end's curvatures lack: they are read
 * with the next sample's ground slope, the interval's own is `jump` more (each curvature row's
 * coefficient on it: jump_row). */
typedef struct {
    const double *v0, *s0, *v1, *s1, *jump_row;
    double length, squared_length, jump;
} Interval;

static inline Interval interval(const WorkInput *in, int64_t i)
{
    const int64_t fix = in->switch_[i];
    const double *v0 = in->values + i * in->k, *s0 = in->slopes + i * in->k_s;
    Interval it = {.v0 = v0, .s0 = s0, .v1 = fix >= 0 ? in->end_values + fix * in->k : v0 + in->k,
                   .s1 = fix >= 0 ? in->end_slopes + fix * in->k_e : s0 + in->k_s,
                   .jump_row = in->slope_rows + in->ids[i] * in->k_c, .length = in->lengths[i],
                   .jump = s0[in->row_a] - s0[in->k_s + in->row_a]};
    it.squared_length = it.length * it.length;
    return it;
}

/* the quintic Hermite coefficients of signal q (its curvatures in slope column c) in an interval */
static inline void coefficients(const Interval *it, int64_t q, int64_t c, double u[6])
{
    u[0] = it->v0[q];
    u[1] = it->s0[q] * it->length;
    u[2] = it->s0[c] * it->squared_length;
    u[3] = it->v1[q];
    u[4] = it->s1[q] * it->length;
    u[5] = (it->s1[c] + it->jump_row[q] * it->jump) * it->squared_length;
}

/* input work of an interval: the input signal (quintic) times the ground acceleration (linear) */
static inline double input_work(const WorkInput *in, const Basis *basis, const Interval *it)
{
    double u[6], sum = 0.0;
    coefficients(it, in->row_input, in->curvature_input, u);
    const double a0 = it->v0[in->row_a], a1 = it->s0[in->row_a] * it->length;
    for (int j = 0; j < 6; j++) {
        sum += u[j] * (a0 * basis->mean[j] + a1 * basis->first[j]);
    }
    return it->length * sum;
}

/* int_0^1 p^2 of the signals first..first + count (their curvatures in slope columns curvature..) in an
 * interval, into out */
static inline void interval_squares(const Basis *basis, const Interval *it, int64_t first, int64_t curvature,
                                    int64_t count, double *out)
{
    squared_integrals(basis, it->v0 + first, it->s0 + first, it->s0 + curvature, it->v1 + first, it->s1 + first,
                      it->s1 + curvature, it->jump_row + first, it->jump, it->length, count, out);
}

/* structural damping energy of an interval: sum_n c_n int Y_n*'^2 (squares: n_modes doubles of work space) */
static inline double structural_damping(const WorkInput *in, const Basis *basis, const Interval *it, double *squares)
{
    interval_squares(basis, it, in->row_ydot, in->curvature_ydot, in->n_modes, squares);
    double sum = 0.0;
    for (int64_t mode = 0; mode < in->n_modes; mode++) {
        sum += in->modal_damping[mode] * squares[mode];
    }
    return it->length * sum;
}

/* foundation damping energy of an interval: int c_i v_i'^2 of the elements in contact; a lifted element
 * relaxes on its own, k z + c z' = 0, and its dashpot dissipates exactly the spring energy released,
 * k (z0^2 - z1^2) / 2 (no quadrature: z may decay within the step) (squares: n_elements doubles) */
static inline double foundation_damping(const WorkInput *in, const Basis *basis, const Interval *it,
                                        const unsigned char *lifted, double *squares)
{
    interval_squares(basis, it, in->row_vel, in->curvature_vel, in->n_elements, squares);
    double sum = 0.0, released = 0.0;
    for (int64_t e = 0; e < in->n_elements; e++) {
        const double c = in->element_damping[e];
        if (c > 0.0 && !lifted[e]) {
            sum += c * squares[e];
        } else if (c > 0.0) {
            const double z0 = it->v0[in->row_z + e], z1 = it->v1[in->row_z + e];
            released += 0.5 * in->element_stiffness[e] * (z0 * z0 - z1 * z1);
        }
    }
    return it->length * sum + released;
}

/* Input work, structural and foundation damping energy [J]: the integrals of the quintic Hermite
 * interpolants of the signals (values, exact slopes and curvatures at both ends) in every interval,
 * exactly (their products are polynomials: the basis' Gram matrix and moments), the dashpots of lifted
 * elements exactly. squares: max(n_modes, n_elements) doubles of work space. */
HOT_LOOP static void work_integrals(const WorkInput *in, double *squares, double out[3])
{
    Basis basis;
    basis_integrals(&basis);
    double total[3] = {0.0, 0.0, 0.0};
    for (int64_t i = 0; i < in->n_intervals; i++) {
        const Interval it = interval(in, i);
        total[0] += input_work(in, &basis, &it);
        total[1] += structural_damping(in, &basis, &it, squares);
        total[2] += foundation_damping(in, &basis, &it, in->lifted + i * in->n_elements, squares);
    }
    for (int j = 0; j < 3; j++) {
        out[j] = total[j];
    }
}

/* ---------------------------------------------------------------------------- Python entry points */

/* the shapes and columns agree */
static int consistent(const WorkInput *in, Py_buffer *const *b)
{
    /* b: values, slopes, end_values, end_slopes, switch, ids, slope_rows, lengths, lifted, modal, stiffness,
     * damping */
    const int64_t n = in->n_intervals, k = in->k, k_s = in->k_s, k_c = in->k_c;
    int ok = b[0]->shape[0] == n + 1 && b[1]->shape[0] == n + 1 && b[2]->shape[1] == k && k_s == in->k_e
             && b[3]->shape[0] == b[2]->shape[0] && b[4]->shape[0] >= n && b[5]->shape[0] >= n
             && b[8]->shape[0] >= n && b[8]->shape[1] == in->n_elements && k_c <= k_s && k_c <= k
             && in->row_a >= 0 && in->row_a < k_c && in->row_input >= 0 && in->row_input < k_c
             && in->row_ydot >= 0 && in->row_ydot + in->n_modes <= k_c && in->row_vel >= 0
             && in->row_vel + in->n_elements <= k_c && in->row_z >= 0 && in->row_z + in->n_elements <= k
             && in->curvature_ydot >= 0 && in->curvature_ydot + in->n_modes <= k_s && in->curvature_input >= 0
             && in->curvature_input < k_s && in->curvature_vel >= 0 && in->curvature_vel + in->n_elements <= k_s
             && b[9]->shape[0] >= in->n_modes && b[10]->shape[0] >= in->n_elements
             && b[11]->shape[0] >= in->n_elements;
    for (int64_t i = 0; ok && i < n; i++) {
        ok = in->switch_[i] < b[2]->shape[0] && in->ids[i] >= 0 && in->ids[i] < b[6]->shape[0];
    }
    return ok;
}

/* work_integrals(values, slopes, end_values, end_slopes, switch, ids, slope_rows, lengths, lifted, row_a,
 *                row_input, row_ydot, n_modes, row_vel, row_z, n_elements, curvature_ydot, curvature_input,
 *                curvature_vel, modal_damping, element_stiffness, element_damping)
 *   -> (work_in, damp_struct, damp_found) */
static PyObject *py_work_integrals(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 22, "work_integrals")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {{0, 'd', 2, 0, "values"}, {1, 'd', 2, 0, "slopes"},
        {2, 'd', 2, 0, "end_values"}, {3, 'd', 2, 0, "end_slopes"}, {4, 'q', 1, 0, "switch"}, {5, 'q', 1, 0, "ids"},
        {6, 'd', 2, 0, "slope_rows"}, {7, 'd', 1, 0, "lengths"}, {8, '?', 2, 0, "lifted"},
        {19, 'd', 1, 0, "modal_damping"}, {20, 'd', 1, 0, "element_stiffness"}, {21, 'd', 1, 0, "element_damping"}};
    Py_buffer *b[12];
    if (!take_views(&v, args, arrays, 12, b)) {
        goto done;
    }
    int64_t scalars[10];
    for (int a = 0; a < 10; a++) {
        scalars[a] = PyLong_AsLongLong(args[9 + a]);
    }
    if (PyErr_Occurred()) {
        goto done;
    }
    WorkInput in = {
        .values = DOUBLES(b[0]), .slopes = DOUBLES(b[1]), .end_values = DOUBLES(b[2]), .end_slopes = DOUBLES(b[3]),
        .switch_ = INT64S(b[4]), .ids = INT64S(b[5]), .slope_rows = DOUBLES(b[6]), .lengths = DOUBLES(b[7]),
        .lifted = BOOLS(b[8]), .modal_damping = DOUBLES(b[9]), .element_stiffness = DOUBLES(b[10]),
        .element_damping = DOUBLES(b[11]), .n_intervals = b[7]->shape[0], .k = b[0]->shape[1],
        .k_s = b[1]->shape[1], .k_e = b[3]->shape[1], .k_c = b[6]->shape[1], .row_a = scalars[0],
        .row_input = scalars[1], .row_ydot = scalars[2], .n_modes = scalars[3], .row_vel = scalars[4],
        .row_z = scalars[5], .n_elements = scalars[6], .curvature_ydot = scalars[7], .curvature_input = scalars[8],
        .curvature_vel = scalars[9],
    };
    if (!consistent(&in, b)) {
        PyErr_SetString(PyExc_ValueError, "work_integrals: inconsistent array shapes");
        goto done;
    }
    double *squares = malloc(((in.n_modes > in.n_elements ? in.n_modes : in.n_elements) + 1) * sizeof(double));
    if (!squares) {
        PyErr_NoMemory();
        goto done;
    }
    double out[3];
    Py_BEGIN_ALLOW_THREADS
    work_integrals(&in, squares, out);
    Py_END_ALLOW_THREADS
    free(squares);
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
