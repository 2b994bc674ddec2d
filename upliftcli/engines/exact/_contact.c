/* Compiled loop of the exact engine's contact elements: reactions between samples, impacts and
 * the uplift statistics, in one pass. See response_kernels.contact_response for the arguments;
 * the numpy twin is in tests/test_response_kernels.py. */

#include "buffers.h"
#include <math.h>
#include <stdlib.h>

/* The sum of a[0..n) as numpy sums a contiguous array (pairwise, eight accumulators in blocks of
 * up to 128), so that a total agrees with numpy's bit for bit. */
static double pairwise_sum(const double *a, int64_t n)
{
    if (n < 8) {
        double sum = 0.0;
        for (int64_t i = 0; i < n; i++) {
            sum += a[i];
        }
        return sum;
    }
    if (n <= 128) {
        double r[8];
        for (int l = 0; l < 8; l++) {
            r[l] = a[l];
        }
        int64_t i = 8;
        for (; i < n - (n % 8); i += 8) {
            for (int l = 0; l < 8; l++) {
                r[l] += a[i + l];
            }
        }
        double sum = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for (; i < n; i++) {
            sum += a[i];
        }
        return sum;
    }
    int64_t half = n / 2;
    half -= half % 8;
    return pairwise_sum(a, half) + pairwise_sum(a + half, n - half);
}

/* Largest value of the cubic Hermite p(s), s in [0, 1], with p(0) = p0, p(1) = p1, p'(0) = d0,
 * p'(1) = d1 (slopes times the interval length); *where = s. */
static double cubic_maximum(double p0, double p1, double d0, double d1, double *where)
{
    const double a = 2.0 * (p0 - p1) + d0 + d1;
    const double b = 3.0 * (p1 - p0) - 2.0 * d0 - d1;
    double best = p0 > p1 ? p0 : p1;
    *where = p1 > p0 ? 1.0 : 0.0;
    const double disc = b * b - 3.0 * a * d0;
    const double root = sqrt(disc > 0.0 ? disc : 0.0);
    const int quadratic = fabs(a) > 1e-14 * (fabs(b) + fabs(d0));
    double candidates[2];
    candidates[0] = quadratic ? (-b + root) / (3.0 * a) : (b != 0.0 ? -d0 / (2.0 * b) : -1.0);
    candidates[1] = quadratic ? (-b - root) / (3.0 * a) : -1.0;
    for (int c = 0; c < 2; c++) {
        const double s = candidates[c];
        if (s > 0.0 && s < 1.0 && disc >= 0.0) {
            const double value = ((a * s + b) * s + d0) * s + p0;
            if (value > best) {
                best = value;
                *where = s;
            }
        }
    }
    return best;
}

typedef struct {
    const double *values, *slopes, *end_values, *end_slopes, *lengths, *times, *stiffness, *damping;
    const int64_t *switch_;
    const unsigned char *lifted;
    int64_t n, k, k_s, k_e, n_elements, row_displacement, row_velocity, row_z, row_theta;
} ContactInput;

/* summary entries, in order (response_kernels.SUMMARY) */
enum { MAX_ROTATION, UPLIFT_TIME, EPISODES, FLIGHT_TIME, EPISODES_LEFT, EPISODES_RIGHT, MAX_UPLIFT_LEFT,
       MAX_UPLIFT_RIGHT, MAX_EDGE_LEFT, MAX_EDGE_RIGHT, MIN_REACTION_LEFT, MIN_REACTION_RIGHT, MIN_REACTION,
       N_SUMMARY };

/* reaction R = -(k v + c v') [3a] of element e and its rate from a row of values and slopes (as if
 * in contact: the callers leave out the lifted elements) */
static inline void reaction_at(const ContactInput *in, const double *values, const double *slopes, int64_t e,
                               double *reaction, double *rate)
{
    const double k = in->stiffness[e], c = in->damping[e];
    const double v = values[in->row_displacement + e], velocity = values[in->row_velocity + e];
    *reaction = -(v * k + velocity * c);
    *rate = -(velocity * k + slopes[in->row_velocity + e] * c);
}

/* Per element: the largest compression between samples (cubic Hermite interpolant of R in each
 * interval in contact) and when, the largest reaction at a recontact (the sample where a contact
 * starts) and when (NaN: none); the uplift statistics summary[N_SUMMARY] (docs/theory.md section
 * 4). One pass over the samples, in the order and with the arithmetic of its numpy twin (ties go
 * to the first interval or sample; times summed as numpy sums). Work space: uplifted, flying
 * (n - 1 doubles each), reactions (4 n_elements). */
HOT_LOOP static void contact_response(const ContactInput *in, double *peak, double *peak_time, double *impact,
                                      double *impact_time, double *summary, double *uplifted, double *flying,
                                      double *reactions)
{
    const int64_t n = in->n, n_e = in->n_elements;
    const int64_t sides[2] = {0, n_e - 1};
    for (int64_t e = 0; e < n_e; e++) {
        peak[e] = impact[e] = -INFINITY;
        peak_time[e] = 0.0;
        impact_time[e] = NAN;
    }
    double max_rotation = 0.0, min_reaction = INFINITY;
    int64_t n_uplifted = 0, n_flying = 0;
    double max_gap[2] = {-INFINITY, -INFINITY}, max_edge[2] = {-INFINITY, -INFINITY};
    double min_side[2] = {INFINITY, INFINITY};
    int64_t episodes = 0, side_episodes[2] = {0, 0};
    /* the reactions and their rates at sample i (r, d) and at sample i + 1 (r_next, d_next) */
    double *r = reactions, *d = reactions + n_e, *r_next = reactions + 2 * n_e, *d_next = reactions + 3 * n_e;
    for (int64_t e = 0; e < n_e && n > 0; e++) {
        reaction_at(in, in->values, in->slopes, e, r + e, d + e);
    }
    for (int64_t i = 0; i < n; i++) {
        const double *values = in->values + i * in->k, *slopes = in->slopes + i * in->k_s;
        const unsigned char *lifted = in->lifted + i * n_e;
        const double theta = in->row_theta >= 0 ? fabs(values[in->row_theta]) : 0.0;
        max_rotation = theta > max_rotation ? theta : max_rotation;
        int any = 0, all = 1;
        for (int64_t e = 0; e < n_e; e++) {
            any |= lifted[e];
            all &= lifted[e];
            if (!lifted[e]) {
                min_reaction = r[e] < min_reaction ? r[e] : min_reaction;
            }
        }
        for (int side = 0; side < 2; side++) {
            const int64_t e = sides[side];
            const double displacement = values[in->row_displacement + e];
            const double gap = lifted[e] ? displacement - (in->damping[e] > 0.0 ? values[in->row_z + e] : 0.0) : 0.0;
            max_gap[side] = gap > max_gap[side] ? gap : max_gap[side];
            max_edge[side] = displacement > max_edge[side] ? displacement : max_edge[side];
            if (!lifted[e]) {
                min_side[side] = r[e] < min_side[side] ? r[e] : min_side[side];
            }
        }
        if (i + 1 == n) {
            break;
        }
        /* the interval from sample i to i + 1; its right end is the left limit where it ends at a transition */
        const unsigned char *lifted1 = lifted + n_e;
        int any1 = 0;
        for (int64_t e = 0; e < n_e; e++) {
            any1 |= lifted1[e];
            reaction_at(in, values + in->k, slopes + in->k_s, e, r_next + e, d_next + e);
        }
        episodes += any1 && !any;
        for (int side = 0; side < 2; side++) {
            side_episodes[side] += lifted1[sides[side]] && !lifted[sides[side]];
        }
        const double length = in->lengths[i];
        if (any) {
            uplifted[n_uplifted++] = length;
        }
        if (all && n_e > 1) {
            flying[n_flying++] = length;
        }
        const int64_t fix = in->switch_[i];
        for (int64_t e = 0; e < n_e; e++) {
            double value = 0.0, s = 0.0;
            if (!lifted[e]) {
                double r1 = 0.0, d1 = 0.0;
                if (fix >= 0) {
                    reaction_at(in, in->end_values + fix * in->k, in->end_slopes + fix * in->k_e, e, &r1, &d1);
                } else if (!lifted1[e]) {
                    r1 = r_next[e];
                    d1 = d_next[e];
                }
                value = cubic_maximum(r[e], r1, d[e] * length, d1 * length, &s);
            }
            if (value > peak[e]) {
                peak[e] = value;
                peak_time[e] = in->times[i] + s * length;
            }
            if (lifted[e] && !lifted1[e] && r_next[e] > impact[e]) { /* sample i + 1 starts a contact: the impact */
                impact[e] = r_next[e];
                impact_time[e] = in->times[i + 1];
            }
        }
        double *swap = r;
        r = r_next;
        r_next = swap;
        swap = d;
        d = d_next;
        d_next = swap;
    }
    for (int64_t e = 0; e < n_e; e++) {
        peak[e] = peak[e] > 0.0 ? peak[e] : 0.0;
        impact[e] = isnan(impact_time[e]) ? 0.0 : impact[e] > 0.0 ? impact[e] : 0.0;
    }
    summary[MAX_ROTATION] = max_rotation;
    summary[UPLIFT_TIME] = pairwise_sum(uplifted, n_uplifted);
    summary[EPISODES] = (double)episodes;
    summary[FLIGHT_TIME] = pairwise_sum(flying, n_flying);
    summary[EPISODES_LEFT] = (double)side_episodes[0];
    summary[EPISODES_RIGHT] = (double)side_episodes[1];
    summary[MAX_UPLIFT_LEFT] = max_gap[0] > 0.0 ? max_gap[0] : 0.0;
    summary[MAX_UPLIFT_RIGHT] = max_gap[1] > 0.0 ? max_gap[1] : 0.0;
    summary[MAX_EDGE_LEFT] = max_edge[0];
    summary[MAX_EDGE_RIGHT] = max_edge[1];
    summary[MIN_REACTION_LEFT] = min_side[0];
    summary[MIN_REACTION_RIGHT] = min_side[1];
    summary[MIN_REACTION] = min_reaction;
}

/* ---------------------------------------------------------------------------- Python entry points */

/* contact_response(values, slopes, end_values, end_slopes, switch, lifted, lengths, times, stiffness,
 *                  damping, rows, peak, peak_time, impact, impact_time, summary); rows: int64
 *                  (element displacement, element velocity, z, theta or -1) columns */
static PyObject *py_contact_response(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (!expect_args(nargs, 16, "contact_response")) {
        return NULL;
    }
    Views v = {.count = 0};
    PyObject *result = NULL;
    static const ArraySpec arrays[] = {
        {0, 'd', 2, 0, "values"}, {1, 'd', 2, 0, "slopes"}, {2, 'd', 2, 0, "end_values"},
        {3, 'd', 2, 0, "end_slopes"}, {4, 'q', 1, 0, "switch"}, {5, '?', 2, 0, "lifted"}, {6, 'd', 1, 0, "lengths"},
        {7, 'd', 1, 0, "times"}, {8, 'd', 1, 0, "stiffness"}, {9, 'd', 1, 0, "damping"}, {10, 'q', 1, 0, "rows"},
        {11, 'd', 1, 1, "peak"}, {12, 'd', 1, 1, "peak_time"}, {13, 'd', 1, 1, "impact"},
        {14, 'd', 1, 1, "impact_time"}, {15, 'd', 1, 1, "summary"},
    };
    Py_buffer *b[16];
    if (!take_views(&v, args, arrays, 16, b)) {
        goto done;
    }
    const int64_t *rows = INT64S(b[10]);
    ContactInput in = {
        .values = DOUBLES(b[0]), .slopes = DOUBLES(b[1]), .end_values = DOUBLES(b[2]), .end_slopes = DOUBLES(b[3]),
        .switch_ = INT64S(b[4]), .lifted = BOOLS(b[5]), .lengths = DOUBLES(b[6]), .times = DOUBLES(b[7]),
        .stiffness = DOUBLES(b[8]), .damping = DOUBLES(b[9]), .n = b[0]->shape[0], .k = b[0]->shape[1],
        .k_s = b[1]->shape[1], .k_e = b[3]->shape[1], .n_elements = b[5]->shape[1],
    };
    const int64_t n_e = in.n_elements;
    int ok = b[10]->shape[0] == 4 && n_e >= 1 && in.n >= 1 && b[1]->shape[0] == in.n && b[2]->shape[1] == in.k
             && b[3]->shape[0] == b[2]->shape[0] && b[4]->shape[0] >= in.n - 1 && b[5]->shape[0] == in.n
             && b[6]->shape[0] >= in.n - 1 && b[7]->shape[0] == in.n && b[8]->shape[0] == n_e
             && b[9]->shape[0] == n_e && b[11]->shape[0] == n_e && b[12]->shape[0] == n_e
             && b[13]->shape[0] == n_e && b[14]->shape[0] == n_e && b[15]->shape[0] == N_SUMMARY;
    if (ok) {
        in.row_displacement = rows[0];
        in.row_velocity = rows[1];
        in.row_z = rows[2];
        in.row_theta = rows[3];
        ok = in.row_displacement >= 0 && in.row_displacement + n_e <= in.k && in.row_velocity >= 0
             && in.row_velocity + n_e <= in.k_s && in.row_velocity + n_e <= in.k_e && in.row_z >= 0
             && in.row_z + n_e <= in.k && in.row_theta < in.k;
    }
    for (int64_t i = 0; ok && i + 1 < in.n; i++) {
        ok = in.switch_[i] < b[2]->shape[0];
    }
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "contact_response: inconsistent array shapes");
        goto done;
    }
    double *work = malloc((2 * in.n + 4 * n_e + 1) * sizeof(double));
    if (!work) {
        PyErr_NoMemory();
        goto done;
    }
    Py_BEGIN_ALLOW_THREADS
    contact_response(&in, DOUBLES(b[11]), DOUBLES(b[12]), DOUBLES(b[13]), DOUBLES(b[14]), DOUBLES(b[15]), work,
                     work + in.n, work + 2 * in.n);
    Py_END_ALLOW_THREADS
    free(work);
    result = Py_NewRef(Py_None);
done:
    release_views(&v);
    return result;
}

static PyMethodDef methods[] = {
    FASTCALL(contact_response, "Reactions and uplift."),
    {NULL, NULL, 0, NULL},
};

DEFINE_MODULE(_contact, "Reactions and uplift statistics of the exact engine.")
