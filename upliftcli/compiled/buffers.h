/* Typed, C-contiguous views of the arrays the compiled loops take, through the buffer protocol
 * (no numpy headers at build time). Shared by every extension module of the package. */
#ifndef UPLIFT_BUFFERS_H
#define UPLIFT_BUFFERS_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>
#include <string.h>

/* C99's restrict, which MSVC's C compiler spells __restrict (the headers of the loops include this
 * file first); GCC and Clang extensions (HOT_LOOP here, PREFETCH, ALWAYS_INLINE and the vector type
 * of product.h) are used only where __GNUC__ says they exist, with portable fallbacks. */
#if defined(_MSC_VER) && !defined(__clang__)
#define restrict __restrict
#endif

#define MAX_VIEWS 40

/* the views taken by one call, released together */
typedef struct {
    Py_buffer views[MAX_VIEWS];
    int count;
} Views;

static void release_views(Views *v)
{
    for (int i = 0; i < v->count; i++) {
        PyBuffer_Release(&v->views[i]);
    }
    v->count = 0;
}

static int format_is(const Py_buffer *view, char kind)
{
    const char *f = view->format ? view->format : "B";
    char last = f[strlen(f) - 1];
    switch (kind) {
    case 'd':
        return last == 'd' && view->itemsize == 8;
    case 'q':
        return (last == 'q' || last == 'l') && view->itemsize == 8;
    case '?':
        return last == '?' && view->itemsize == 1;
    default:
        return 0;
    }
}

/* A C-contiguous view of obj with items of `kind` ('d' float64, 'q' int64, '?' bool) and `ndim`
 * dimensions, writable if asked; NULL with a TypeError naming the argument otherwise. */
static Py_buffer *take_view(Views *v, PyObject *obj, char kind, int ndim, int writable, const char *name)
{
    if (v->count == MAX_VIEWS) {
        PyErr_SetString(PyExc_RuntimeError, "too many array arguments");
        return NULL;
    }
    Py_buffer *view = &v->views[v->count];
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) {
        PyErr_Format(PyExc_TypeError, "%s: a C-contiguous%s array is expected", name, writable ? " writable" : "");
        return NULL;
    }
    v->count++;
    if (!format_is(view, kind) || view->ndim != ndim) {
        PyErr_Format(PyExc_TypeError, "%s: a %d-D array of %s is expected", name, ndim,
                     kind == 'd' ? "float64" : kind == 'q' ? "int64" : "bool");
        return NULL;
    }
    return view;
}

/* one array argument of a call: its position, item kind, dimensions, whether it is written, name */
typedef struct {
    int arg;
    char kind;
    int ndim;
    int writable;
    const char *name;
} ArraySpec;

/* Views of the `count` array arguments of `specs`, out[i] for specs[i]; 0 with the error set at
 * the first that is not as specified. */
static int take_views(Views *v, PyObject *const *args, const ArraySpec *specs, int count, Py_buffer **out)
{
    for (int i = 0; i < count; i++) {
        out[i] = take_view(v, args[specs[i].arg], specs[i].kind, specs[i].ndim, specs[i].writable, specs[i].name);
        if (!out[i]) {
            return 0;
        }
    }
    return 1;
}

#define DOUBLES(view) ((double *)(view)->buf)
#define INT64S(view) ((int64_t *)(view)->buf)
#define BOOLS(view) ((const unsigned char *)(view)->buf)

/* The loops are compiled twice where the compiler and C library allow: for AVX2 and for the
 * baseline instruction set, the one the processor runs chosen when the module loads. Only
 * elementwise loops vectorise (reductions keep their order, no FMA: -ffp-contract=off), so both
 * versions give the same bits. No AVX-512 version: its 512-bit loops over these short rows (10-70
 * entries) ran 1.3-1.7x slower than AVX2 on an AMD EPYC (Zen 4) machine. */
#if defined(__x86_64__) && defined(__GNUC__) && defined(__GLIBC__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define HOT_LOOP __attribute__((target_clones("default", "avx2")))
#endif
#endif
#ifndef HOT_LOOP
#define HOT_LOOP
#endif

/* a METH_FASTCALL entry of a module's method table */
#define FASTCALL(name, doc) {#name, (PyCFunction)(void (*)(void))py_##name, METH_FASTCALL, doc}

/* The module definition and its init function, PyInit_<name>, for the method table `methods`. */
#define DEFINE_MODULE(name, doc)                                                                                      \
    static struct PyModuleDef module = {                                                                              \
        PyModuleDef_HEAD_INIT, .m_name = #name, .m_doc = doc, .m_size = -1, .m_methods = methods,                     \
    };                                                                                                                 \
    PyMODINIT_FUNC PyInit_##name(void)                                                                                 \
    {                                                                                                                  \
        return PyModule_Create(&module);                                                                               \
    }

/* positional-argument count check of a METH_FASTCALL function */
static int expect_args(Py_ssize_t nargs, Py_ssize_t expected, const char *function)
{
    if (nargs != expected) {
        PyErr_Format(PyExc_TypeError, "%s takes %zd arguments (%zd given)", function, expected, nargs);
        return 0;
    }
    return 1;
}

/* the `size` items of the tuple argument `name` of `function` into out; 0 with a TypeError otherwise */
static inline int unpack(PyObject *tuple, Py_ssize_t size, const char *function, const char *name, PyObject **out)
{
    if (!PyTuple_Check(tuple) || PyTuple_Size(tuple) != size) {
        PyErr_Format(PyExc_TypeError, "%s: %s must be a tuple of %zd items", function, name, size);
        return 0;
    }
    for (Py_ssize_t i = 0; i < size; i++) {
        out[i] = PyTuple_GetItem(tuple, i);
    }
    return 1;
}

#endif
